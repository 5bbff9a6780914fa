"""The paper's study (Harlecki & Kubas, section 4): two lane changes x three friction sets,
with every deciding number converged in the time step.

The command is ``drake_car.commands.paper``, also installed as ``drake-car-paper``;
``--help`` says what it writes. Example: python experiments/lane_change.py --out results/paper
"""

from drake_car import cli
from drake_car.commands.paper import main

if __name__ == "__main__":
    cli.run_main(main)
