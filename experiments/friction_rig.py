"""The 1-DOF friction rig: the strut friction law (FRD) on one sliding pair under a force, a
ramp or a belt.

The command is ``drake_car.commands.friction_rig``, also installed as ``drake-car-friction-rig``;
``--help`` says what it writes.
"""

from drake_car import cli
from drake_car.commands.friction_rig import main

if __name__ == "__main__":
    cli.run_main(main)
