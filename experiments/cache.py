"""The project's disk caches (static equilibria, lane-change calibrations): where, how many,
--clear.

The command ``drake_car.commands.cache``, installed as ``drake-car-cache``.
"""

from drake_car.commands.cache import console

if __name__ == "__main__":
    console()
