"""The car's front strut on a side-load friction rig: loops, break-away, and a fit of
mu_s, mu_d to a measured loop.

The command ``drake_car.commands.strut_rig``, installed as ``drake-car-strut-rig``; ``--help`` says
what it writes.
"""

from drake_car.commands.strut_rig import console

if __name__ == "__main__":
    console()
