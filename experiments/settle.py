"""The car settling under gravity (a !Settle scene).

The command ``drake_car.commands.settle``, installed as ``drake-car-settle``; ``--help`` says
what it writes.
"""

from drake_car.commands.settle import console

if __name__ == "__main__":
    console()
