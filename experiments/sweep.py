"""Runs many scenes on Dask, keeping each result as it completes (resumable).

The command ``drake_car.commands.sweep``, installed as ``drake-car-sweep``; ``--help`` says
what it writes.
"""

from drake_car.commands.sweep import console

if __name__ == "__main__":
    console()
