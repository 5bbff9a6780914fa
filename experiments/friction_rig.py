"""The friction law on a one-degree-of-freedom rig (a block on a belt).

The command ``drake_car.commands.friction_rig``, installed as ``drake-car-friction-rig``; ``--help`` says
what it writes.
"""

from drake_car.commands.friction_rig import console

if __name__ == "__main__":
    console()
