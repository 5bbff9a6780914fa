"""The design study: where, over the strut's design and the severity of use, friction
changes the front wheel loads and the steering.

The command is ``drake_car.commands.design``, also installed as ``drake-car-design``;
``--help`` says what it writes. Example: python experiments/design_study.py --out results/design
"""

from drake_car import cli
from drake_car.commands.design import main

if __name__ == "__main__":
    cli.run_main(main)
