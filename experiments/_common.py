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
