"""The handling tests (ISO 4138 ramp steer, ISO 7401 step steer), the understeer budget and
the cross-check against CommonRoad's model of the same car.

The command is ``drake_car.commands.handling``, also installed as ``drake-car-handling``;
``--help`` says what it writes. Example: python experiments/handling.py --out results/handling
"""

from drake_car import cli
from drake_car.commands.handling import main

if __name__ == "__main__":
    cli.run_main(main)
