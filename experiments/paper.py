"""The paper's study (Harlecki & Kubas, section 4): two lane changes x three friction sets,
with every deciding number converged in the time step. The main job.

The command ``drake_car.commands.paper``, installed as ``drake-car-paper``; ``--help`` says
what it writes.
"""

from drake_car.commands.paper import console

if __name__ == "__main__":
    console()
