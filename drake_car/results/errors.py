"""The results room's error: an output that cannot be written, named with why."""


class OutputError(ValueError):
    """The output folder cannot be used; the message names it and why."""
