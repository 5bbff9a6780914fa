"""Calibrates the lane change's rack profile for a car.

The command ``drake_car.commands.calibrate``, installed as ``drake-car-calibrate``; ``--help`` says
what it writes.
"""

from drake_car.commands.calibrate import console

if __name__ == "__main__":
    console()
