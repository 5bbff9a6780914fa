"""The car checked on its own: settling, kinematics, jammed struts' replay.

The command ``drake_car.commands.car_checks``, installed as ``drake-car-car-checks``; ``--help`` says
what it writes.
"""

from drake_car.commands.car_checks import console

if __name__ == "__main__":
    console()
