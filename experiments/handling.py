"""The ISO handling tests (ramp steer, step steer), the understeer budget and the
CommonRoad cross-check.

The command ``drake_car.commands.handling``, installed as ``drake-car-handling``; ``--help`` says
what it writes.
"""

from drake_car.commands.handling import console

if __name__ == "__main__":
    console()
