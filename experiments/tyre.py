"""A tyre property file's steady-state curves, figures and summary.

The command ``drake_car.commands.tyre``, installed as ``drake-car-tyre``; ``--help`` says
what it writes.
"""

from drake_car.commands.tyre import console

if __name__ == "__main__":
    console()
