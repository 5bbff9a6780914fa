"""What every command shares: the scene options, the one validation path, and bad input
reported as one line on stderr with exit status 2 (no traceback), nothing left behind.

Bad input is any ``ValueError`` the project raises for a value it refuses (a scene key, a
parameter, a tyre or model file, an output folder, a step above a stability limit) and a
simulation that cannot go on (``SimulationFailure``: divergence, a rod out of its guide).
"""

import argparse
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


def parser(doc, *, out=True, prog=None):
    """An ArgumentParser with the script's docstring and (``out``) a required ``--out``;
    ``prog``: the command's name in its usage line (default: the script's file name)."""
    p = argparse.ArgumentParser(description=doc, prog=prog,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    if out:
        p.add_argument("--out", type=Path, required=True,
                       help="output folder (written all or nothing; replaced whole)")
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
    """Runs ``main(argv)``; bad input exits 2 with one line on stderr, Ctrl-C exits 130."""
    try:
        main(argv)
    except BAD_INPUT as e:
        print(f"error: {one_line(e)}", file=sys.stderr)
        raise SystemExit(2) from None
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        raise SystemExit(130) from None


def check_out(args):
    """Refuses a bad ``--out`` before any work (exit 2 through ``run_main``)."""
    check_output_target(args.out)
