"""What accuracy costs: the paper's runs at several steps of the fast scheme against the law
applied as stated (the explicit scheme), per deciding outcome.

The command is ``drake_car.commands.accuracy``, also installed as ``drake-car-accuracy``;
``--help`` says what it writes.
"""

from drake_car import cli
from drake_car.commands.accuracy import main

if __name__ == "__main__":
    cli.run_main(main)
