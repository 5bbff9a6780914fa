"""The commands a user runs, each also installed as a console script (``pyproject.toml``):
``drake-car-paper`` (the paper's study), ``drake-car-design`` (the design study),
``drake-car-handling`` (the ISO handling tests), ... The scripts in ``experiments/`` call
them, so ``python experiments/NAME.py`` works from a checkout too."""
