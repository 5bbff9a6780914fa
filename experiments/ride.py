"""Ride comfort and wheel loads on ISO 8608 roads against strut friction.

The command ``drake_car.commands.ride``, installed as ``drake-car-ride``; ``--help`` says
what it writes.
"""

from drake_car.commands.ride import console

if __name__ == "__main__":
    console()
