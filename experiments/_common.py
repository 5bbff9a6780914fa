"""Shared command-line handling for the experiment scripts."""

import argparse
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

REPO_ROOT = Path(__file__).resolve().parents[1]
if str(REPO_ROOT) not in sys.path:  # run from a checkout without installing
    sys.path.insert(0, str(REPO_ROOT))


def parser(doc, default_out=None):
    p = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", type=Path, default=default_out, required=default_out is None,
                   help="output folder (created; files are written all-or-nothing)")
    return p


def add_scene_options(p, default=None):
    """--scene FILE[:ENTRY] and --scene_text YAML (layered on top)."""
    p.add_argument("--scene", default=default,
                   help="scene file, optionally :entry (default: %(default)s)")
    p.add_argument("--scene_text", default="",
                   help="YAML laid over the scene, e.g. \"friction: {mu_s: 0.3}\"")


def load_scene_option(p, args):
    from drake_car.scene import SceneError, load_scene
    if not args.scene and not args.scene_text:
        return None
    path, child = args.scene, None
    if path and ":" in path:
        path, child = path.rsplit(":", 1)
    try:
        return load_scene(path, child=child, scene_text=args.scene_text)
    except SceneError as e:
        p.error(str(e))


def resolve_or_exit(p, scene):
    """The scene's parameters and setups (drake_car.scene.resolve); a bad value exits with the
    scene's error message."""
    from drake_car.scene import SceneError, resolve
    try:
        return resolve(scene)
    except SceneError as e:
        p.error(str(e))


def _checked(name, valid, requirement):
    def check(text):
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"--{name}: {text!r} is not a number")
        if not valid(value):
            raise argparse.ArgumentTypeError(f"--{name}: {value} must be {requirement}")
        return value
    return check


def positive(name):
    return _checked(name, lambda v: v > 0, "> 0")


def nonnegative(name):
    return _checked(name, lambda v: v >= 0, ">= 0")


def number(name):
    return _checked(name, lambda v: v == v, "a number")
