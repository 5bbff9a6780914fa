"""The strut side-load friction rig: the car's own front strut under a side force, its rod
stroked sinusoidally; friction loops, break-away, and a fit of μs, μd to a measured loop.

The command is ``drake_car.commands.side_load``, also installed as ``drake-car-strut-rig``;
``--help`` says what it writes.
"""

from drake_car import cli
from drake_car.commands.side_load import main

if __name__ == "__main__":
    cli.run_main(main)
