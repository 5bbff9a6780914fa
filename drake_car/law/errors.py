"""The two kinds of error every room raises, at the ground floor so that every room can use them.

``InputError``: the input is wrong — a scene key or value, a parameter, a tyre, model or
measured file, an option, an output folder. Its message names where (file, key or option),
the value and what is allowed, as one line. Every refusal of input subclasses it.

``RunFailed``: the input was accepted but the run cannot go on — the state diverged, a rod
left its guide, a worker ran other code. Its message names the time, the quantity and why.

The commands catch these two bases (and ``OSError``) in one place
(``drake_car.commands.cli.run_main``): one line on stderr, exit status 2.
"""


class InputError(ValueError):
    """The input is wrong; the message names where, the value and what is allowed."""


class RunFailed(RuntimeError):
    """The run cannot go on; the message names the time, the quantity and why."""
