"""The commands a user runs, one module per job (``drake_car/commands/JOB.py``), each installed as
the console script ``drake-car-JOB`` (underscores as hyphens) and callable from a checkout as
``python experiments/JOB.py``; ``cli.py`` holds what they share: the options, logging and the
one error path."""
