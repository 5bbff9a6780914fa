"""What every command shares: the scene options, the one validation path, bad input reported
as one line on stderr with exit status 2 (no traceback), nothing left behind, and logging:
library code logs through ``logging`` (the ``drake_car`` loggers); every command's parser has
``--quiet`` (warnings only, no progress bars) and ``--verbose`` (debug messages) and sets the
loggers up when it parses, writing through tqdm so that messages do not break a progress bar.

Bad input is any ``ValueError`` the project raises for a value it refuses (a scene key, a
parameter, a tyre or model file, an output folder, a step above a stability limit) and a
simulation that cannot go on (``SimulationFailure``: divergence, a rod out of its guide); an
``OSError`` (a full disk, a permission, a folder removed) takes the same path.
"""

import argparse
import logging
import os
import sys
from pathlib import Path

from drake_car.law.checks import ParameterError, one_line
from drake_car.law.tyre.tir import TirFileError
from drake_car.model.kinematics import KinematicsError
from drake_car.model.loading import ModelFileError
from drake_car.scene.load import SceneError, load_scene, parse_scene_option
from drake_car.sim.build import BuildError
from drake_car.results.folder import OutputError, check_output_target
from drake_car.study.paper.claims import StudyError
from drake_car.systems.failure import SimulationFailure

BAD_INPUT = (SceneError, ParameterError, TirFileError, ModelFileError, KinematicsError,
             OutputError, BuildError, StudyError, SimulationFailure)


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
    if not any(isinstance(h, _TqdmHandler) for h in logger.handlers):
        handler = _TqdmHandler()
        handler.setFormatter(_Formatter())
        logger.addHandler(handler)


class CommandParser(argparse.ArgumentParser):
    """An ArgumentParser that sets up logging from ``--quiet``/``--verbose`` when it parses."""

    def parse_known_args(self, args=None, namespace=None):
        parsed, rest = super().parse_known_args(args, namespace)
        configure_logging(quiet=getattr(parsed, "quiet", False),
                          verbose=getattr(parsed, "verbose", False))
        return parsed, rest


def parser(doc, *, out=True, prog=None,
           out_help="output folder (written all or nothing; replaced whole)"):
    """A command's parser: the script's docstring, ``--quiet``/``--verbose`` (logging and
    progress bars) and (``out``) a required ``--out``; ``prog``: the command's name in its
    usage line (default: the script's file name)."""
    p = CommandParser(description=doc, prog=prog, conflict_handler="resolve",
                      formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--quiet", action="store_true",
                   help="warnings and errors only, no progress bars")
    p.add_argument("--verbose", action="store_true", help="debug messages too")
    if out:
        p.add_argument("--out", type=Path, required=True, help=out_help)
    return p


def add_scene_options(p, *, default=None, help_scene=None):
    """``--scene FILE[:ENTRY]`` and ``--scene_text YAML`` (laid on top)."""
    p.add_argument("--scene", default=default,
                   help=help_scene or "scene file, optionally :ENTRY (default: %(default)s)")
    p.add_argument("--scene_text", default="",
                   help="YAML laid over the scene, e.g. \"friction: {law: {mu_s: 0.3}}\"")


def scene_from_args(args):
    """The scene of ``--scene``/``--scene_text`` (the defaults when neither is given)."""
    path = child = None
    if args.scene:
        path, child = parse_scene_option(args.scene)
    return load_scene(path, child=child, scene_text=args.scene_text or None)


def positive(name):
    return _checked(name, lambda v: 0 < v < float("inf"), "a finite number > 0")


def nonnegative(name):
    return _checked(name, lambda v: 0 <= v < float("inf"), "a finite number >= 0")


def number(name):
    return _checked(name, lambda v: abs(v) < float("inf"), "a finite number")


def count(text):
    """An option's whole number >= 1 (a count of workers, say)."""
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if n < 1:
        raise argparse.ArgumentTypeError(f"{n} must be >= 1")
    return n


def _checked(name, valid, requirement):
    def check(text):
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"--{name}: {text!r} is not a number") from None
        if not valid(value):
            raise argparse.ArgumentTypeError(f"--{name}: {value} must be {requirement}")
        return value
    return check


def run_main(main, argv=None):
    """Runs ``main(argv)``; bad input and an OS error (a full disk, a permission, a folder
    removed) exit 2 with one line on stderr, Ctrl-C exits 130."""
    try:
        main(argv)
    except BAD_INPUT as e:
        print(f"error: {one_line(e)}", file=sys.stderr)
        raise SystemExit(2) from None
    except OSError as e:
        print(f"error: {one_line(os_error_line(e))}", file=sys.stderr)
        raise SystemExit(2) from None
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        raise SystemExit(130) from None


def os_error_line(error):
    """What an OSError is about, in a line: its paths and its reason; the working folder
    removed under the command named as such (its error names no path)."""
    paths = [os.fsdecode(f) for f in (error.filename, error.filename2) if f is not None]
    if not paths and isinstance(error, FileNotFoundError):
        try:
            os.getcwd()
        except FileNotFoundError:
            return ("the current folder no longer exists (removed while the command ran?); "
                    "change to one that does")
    return ": ".join([*paths, error.strerror or str(error)])


def check_out(args):
    """Refuses a bad ``--out`` before any work (exit 2 through ``run_main``)."""
    check_output_target(args.out)
