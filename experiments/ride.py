"""Ride on rough roads: ISO 8608 roads, ISO 2631-1 weighted comfort and wheel-load fluctuation
against the struts' friction.

The command is ``drake_car.commands.ride``, also installed as ``drake-car-ride``; ``--help`` says
what it writes.
"""

from drake_car import cli
from drake_car.commands.ride import main

if __name__ == "__main__":
    cli.run_main(main)
