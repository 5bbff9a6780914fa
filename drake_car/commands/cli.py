"""What every command shares, from this one place: the parser with the shared options
(``--out``, ``--scene``/``--scene_text``, ``--workers``/``--scheduler``, ``--quiet``/``--verbose``),
option types that name the option they check, logging, and the one error path.

The one error path, ``run_main``: an ``InputError`` (the input is wrong), a ``RunFailed`` (the
run cannot go on; both from ``drake_car.law.errors``) and an ``OSError`` (no space, no
permission, a folder that vanished) are one line on stderr and exit status 2, no traceback;
Ctrl-C exits 130. Nothing is left half-written: the output folders are written all or nothing
(``results.folder``).

Logging: library code logs through ``logging`` (the ``drake_car`` loggers); every parser has
``--quiet`` (warnings only, no progress bars) and ``--verbose`` (debug messages) and sets the
loggers up when it parses, writing through tqdm so that messages do not break a progress bar.
"""

import argparse
import contextlib
import logging
import os
import sys
from pathlib import Path

from drake_car.commands import started
from drake_car.law.checks import check_input_option, one_line
from drake_car.law.errors import InputError, RunFailed
from drake_car.results.folder import check_apart, check_output_target
from drake_car.sweep.scheduler import SCHEDULER_ADDRESS


class _TqdmHandler(logging.Handler):
    """Writes log records to stderr through ``tqdm.write`` (above any progress bar)."""

    def emit(self, record):
        from tqdm import tqdm
        try:
            tqdm.write(self.format(record), file=sys.stderr)
        except Exception:
            self.handleError(record)


class _Formatter(logging.Formatter):
    def format(self, record):
        text = record.getMessage()
        return text if record.levelno == logging.INFO else f"{record.levelname.lower()}: {text}"


def configure_logging(*, quiet=False, verbose=False):
    """The ``drake_car`` loggers to stderr: info (default), warnings only (``quiet``) or debug
    (``verbose``)."""
    logger = logging.getLogger("drake_car")
    logger.setLevel(logging.DEBUG if verbose else logging.WARNING if quiet else logging.INFO)
    logger.propagate = False
    # Drake's own messages (its spdlog, routed to the "drake" logger): warnings only with quiet
    if quiet:
        logging.getLogger("drake").setLevel(logging.WARNING)
    if not any(isinstance(h, _TqdmHandler) for h in logger.handlers):
        handler = _TqdmHandler()
        handler.setFormatter(_Formatter())
        logger.addHandler(handler)


class CommandParser(argparse.ArgumentParser):
    """An ArgumentParser that sets up logging from ``--quiet``/``--verbose`` when it parses and
    checks the shared options' combinations."""

    def parse_known_args(self, args=None, namespace=None):
        parsed, rest = super().parse_known_args(args, namespace)
        configure_logging(quiet=getattr(parsed, "quiet", False),
                          verbose=getattr(parsed, "verbose", False))
        scheduler = getattr(parsed, "scheduler", None)
        if scheduler and getattr(parsed, "workers", None):
            self.error("--workers sizes the local cluster; a --scheduler cluster has its own "
                       "workers")
        if scheduler and not SCHEDULER_ADDRESS.match(scheduler):
            raise InputError(f"--scheduler {scheduler}: not a Dask scheduler address; give "
                             "tcp://HOST:PORT")
        if getattr(parsed, "scene", None):  # a named pipe would block its reader: refused here
            from drake_car.scene.load import parse_scene_option
            check_input_option("--scene", parse_scene_option(parsed.scene)[0], "scene file",
                               is_text="YAML text")
        return parsed, rest


def command_name(name):
    """A job's console script: ``drake-car-`` and the job's name (its module's), hyphenated."""
    return "drake-car-" + name.replace("_", "-")


def parser(doc, *, name=None, prog=None, out=True, out_help="output folder (written all or nothing; replaced "
           "whole)", scene=False, scene_default=None, scene_required=False, scene_help=None,
           scene_text=None, cluster=False):
    """A command's parser, with the shared options it asks for:

    - always ``--quiet`` and ``--verbose``;
    - ``out``: True, a required ``--out`` (a Path; ``out_help`` says what it is); "optional",
      an ``--out`` that may be left out (None); a Path, an ``--out`` with that default (a file
      the command writes); False, none;
    - ``scene``: ``--scene FILE[:ENTRY]`` (``scene_default``, ``scene_required``,
      ``scene_help``) and ``--scene_text YAML`` laid on top; ``scene_text`` alone (a help
      text) gives ``--scene_text`` without ``--scene``;
    - ``cluster``: ``--workers N`` (a local cluster's size) and ``--scheduler ADDRESS`` (a
      running Dask cluster), exclusive.

    ``name``: the job's name, the command's module under ``drake_car.commands``; the usage line
    shows its console script (``command_name``). ``prog``: another usage name (a benchmark's
    script)."""
    p = CommandParser(description=doc, prog=prog or command_name(name),
                      formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--quiet", action="store_true",
                   help="warnings and errors only, no progress bars")
    p.add_argument("--verbose", action="store_true", help="debug messages too")
    if out is True:
        p.add_argument("--out", type=Path, required=True, help=out_help)
    elif out == "optional":
        p.add_argument("--out", type=Path, default=None, help=out_help)
    elif out:
        p.add_argument("--out", type=Path, default=Path(out), help=out_help)
    if scene:
        p.add_argument("--scene", default=scene_default, required=scene_required,
                       help=(scene_help or "scene file, optionally FILE:ENTRY")
                       + ("" if scene_default is None else " (default: %(default)s)"))
    if scene or scene_text:
        p.add_argument("--scene_text", default="", help=scene_text or (
            "YAML laid over the scene, e.g. \"friction: {law: {mu_s: 0.3}}\""))
    if cluster:
        p.add_argument("--workers", type=count, default=None,
                       help="worker processes of the local cluster (default: one per core)")
        p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                       help="a running Dask scheduler, e.g. tcp://127.0.0.1:8786 (default: a "
                            "local cluster on 127.0.0.1)")
    return p


def scene_from_args(args, runs=True):
    """The scene of ``--scene``/``--scene_text`` (the defaults when neither is given); ``runs``:
    ``load_scene``'s (False: only its car is used)."""
    from drake_car.scene.load import load_scene, parse_scene_option
    path = child = None
    if args.scene:
        path, child = parse_scene_option(args.scene)
    return load_scene(path, child=child, scene_text=args.scene_text or None, runs=runs)


def positive(name):
    return _checked(name, lambda v: 0 < v < float("inf"), "a finite number > 0")


def nonnegative(name):
    return _checked(name, lambda v: 0 <= v < float("inf"), "a finite number >= 0")


def number(name):
    return _checked(name, lambda v: abs(v) < float("inf"), "a finite number")


def within(name, low, high, unit=""):
    """A number in [low, high] (``unit`` said after the range)."""
    return _checked(name, lambda v: low <= v <= high,
                    f"in [{low:g}, {high:g}]{' ' + unit if unit else ''}")


def count(text):
    """An option's whole number >= 1 (a count of workers, say)."""
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if n < 1:
        raise argparse.ArgumentTypeError(f"{n} must be >= 1")
    return n


@contextlib.contextmanager
def cluster_client(args, tasks):
    """A Dask client for the shared cluster options: the ``--scheduler`` cluster (its address's
    form is checked when the options are parsed, its handshake here: a listener that is not a
    Dask scheduler is an InputError naming --scheduler), or a local cluster of ``--workers``
    (default: one per core) but no more workers than ``tasks``."""
    from drake_car.sweep.runner import cores, dask_client
    with contextlib.ExitStack() as stack:
        try:
            client = stack.enter_context(
                dask_client(args.scheduler, min(args.workers or cores(), max(tasks, 1))))
        except (OSError, ValueError) as e:
            if not args.scheduler:
                raise
            raise InputError(f"--scheduler {args.scheduler}: {one_line(e)}") from None
        yield client


def _checked(name, valid, requirement):
    name = name.lstrip("-")

    def check(text):
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"--{name}: {text!r} is not a number") from None
        if not valid(value):
            raise argparse.ArgumentTypeError(f"--{name}: {value} must be {requirement}")
        return value
    return check


def describe(error):
    """One line for an error of the one error path: an OSError names its file and its reason
    (``/x/y: No space left on device``; the working folder removed under the command, whose
    error names no file, as such), any other its message."""
    if isinstance(error, FileNotFoundError) and error.filename is None:
        try:
            os.getcwd()
        except FileNotFoundError:
            return ("the current folder no longer exists (removed while the command ran?); "
                    "change to one that does")
    if isinstance(error, OSError) and error.strerror:
        where = error.filename if error.filename is not None else ""
        also = f" -> {error.filename2}" if error.filename2 is not None else ""
        return one_line(f"{where}{also}: {error.strerror}" if where else error.strerror)
    return one_line(error)


class _GuardedStdout:
    """Standard output that keeps its first write error (``failed``) instead of raising it
    into the work: a full disk or a closed pipe behind stdout is not the run's failure."""

    def __init__(self, stream):
        self.stream, self.failed = stream, None

    def _guard(self, call, *args):
        if self.failed is None:
            try:
                return call(*args)
            except BlockingIOError:  # a non-blocking stream that is full for now: not lost
                return None
            except OSError as e:
                self.failed = e
                with contextlib.suppress(Exception):  # nothing more reaches the lost stream,
                    null = os.open(os.devnull, os.O_WRONLY)  # not even the interpreter's last
                    try:  # flush (which would print a traceback)
                        os.dup2(null, self.stream.fileno())
                    finally:
                        os.close(null)
        return None

    def write(self, text):
        if self.stream is not None:
            self._guard(self.stream.write, text)
        return len(text)

    def flush(self):
        if self.stream is not None:
            self._guard(self.stream.flush)

    def __getattr__(self, name):
        return getattr(self.stream, name)


def run_main(main, argv=None):
    """Runs ``main(argv)``: the input is wrong, the run failed, or the machine refused (an OS
    error) -> one line on stderr, exit 2; Ctrl-C -> exit 130 (one line: the interrupt's
    message where it has one, e.g. what a sweep kept and how to finish it). Standard output
    that cannot be written (a full disk behind it: one line, exit 1; a reader that stopped
    reading, ``| head``: nothing) does not stop the work."""
    started()  # Ctrl-C while the command's module was imported: handled in drake_car.commands
    # a closed stdout (`>&-`: None) stays None: print() then writes nothing, as it does
    out = _GuardedStdout(sys.stdout)
    if sys.stdout is not None:
        sys.stdout = out
    try:
        main(argv)
        out.flush()
    except (InputError, RunFailed, OSError) as e:
        print(f"error: {describe(e)}", file=sys.stderr)
        raise SystemExit(2) from None
    except KeyboardInterrupt as e:
        print(f"interrupted: {one_line(e)}" if str(e) else "interrupted", file=sys.stderr)
        raise SystemExit(130) from None
    finally:
        sys.stdout = out.stream
    if out.failed is not None and not isinstance(out.failed, BrokenPipeError):
        print(f"error: standard output: {describe(out.failed)}; the command finished, but "
              "what it printed there is lost (the files it writes were written)",
              file=sys.stderr)
        raise SystemExit(1)


def check_out(args, kept=()):
    """Refuses a bad ``--out`` before any work (exit 2 through ``run_main``), and one that is,
    holds or is inside a folder of the options named in ``kept`` (kept and added to, e.g.
    "runs_dir"): --out is replaced whole."""
    for name in kept:
        check_apart(args.out, getattr(args, name), f"--{name}")
    check_output_target(args.out)
