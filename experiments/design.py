"""The design study: where, over the strut's design and the severity of use, dry friction
changes the front wheel loads and the steering.

The command ``drake_car.commands.design``, installed as ``drake-car-design``; ``--help`` says
what it writes.
"""

from drake_car.commands.design import console

if __name__ == "__main__":
    console()
