"""What accuracy costs: the deciding outcomes against the step, both friction schemes.

The command ``drake_car.commands.accuracy``, installed as ``drake-car-accuracy``; ``--help`` says
what it writes.
"""

from drake_car.commands.accuracy import console

if __name__ == "__main__":
    console()
