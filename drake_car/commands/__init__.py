"""The commands a user runs, one module per job (``drake_car/commands/JOB.py``), each installed as
the console script ``drake-car-JOB`` (underscores as hyphens) and callable from a checkout as
``python experiments/JOB.py``; ``cli.py`` holds what they share: the options, logging and the
one error path."""

import os
import signal
import sys

# Ctrl-C while a command starts (its heavy imports: drake, numba, matplotlib, 1-4 s) is one
# line and exit 130, as it is later (``cli.run_main``), not an import traceback: this package is
# imported before the command's module, so the handler is in place before those imports;
# ``run_main`` hands SIGINT back to Python's KeyboardInterrupt. A worker process a command
# spawns (Dask's, by multiprocessing: it imports the command again as ``__mp_main__``)
# ignores SIGINT: Ctrl-C reaches the whole process group, and the command shuts its workers
# down. A process that inherited SIGINT ignored (a background job) is left as it is.


def _interrupted_while_starting(signum, frame):
    print("interrupted", file=sys.stderr, flush=True)
    raise SystemExit(130)


def _starting():
    """What this process is: "worker" (a multiprocessing child of a command), "command" (a
    console script, ``python -m drake_car.commands.JOB`` or ``python experiments/JOB.py``) or
    None (the library imported by something else: left alone)."""
    argv = getattr(sys, "orig_argv", [])
    if "--multiprocessing-fork" in argv:
        return "worker"
    script = sys.argv[0] if sys.argv else ""
    experiments = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(
        os.path.abspath(__file__)))), "experiments")
    if (os.path.basename(script).startswith("drake-car-")
            or any(a == "-m" and b.startswith(__name__ + ".") for a, b in zip(argv, argv[1:]))
            or (script.endswith(".py")
                and os.path.dirname(os.path.abspath(script)) == experiments)):
        return "command"
    return None


def _on_import():
    import threading
    if threading.current_thread() is not threading.main_thread():
        return
    if signal.getsignal(signal.SIGINT) is not signal.default_int_handler:
        return
    kind = _starting()
    if kind == "worker":
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    elif kind == "command":
        signal.signal(signal.SIGINT, _interrupted_while_starting)


def started():
    """Called by ``cli.run_main`` once the command's module is imported: Ctrl-C is Python's
    KeyboardInterrupt again (caught there)."""
    if signal.getsignal(signal.SIGINT) is _interrupted_while_starting:
        signal.signal(signal.SIGINT, signal.default_int_handler)


_on_import()
