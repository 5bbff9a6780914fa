"""Runs any scene and writes its history, the scene as it ran, the Diagram and the replay.

The command ``drake_car.commands.run``, installed as ``drake-car-run``; ``--help`` says
what it writes.
"""

from drake_car.commands.run import console

if __name__ == "__main__":
    console()
