"""The front suspension's kinematics, chassis fixed.

The command ``drake_car.commands.kinematics``, installed as ``drake-car-kinematics``; ``--help`` says
what it writes.
"""

from drake_car.commands.kinematics import console

if __name__ == "__main__":
    console()
