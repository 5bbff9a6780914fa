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


def positive(name):
    def check(text):
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"--{name}: {text!r} is not a number")
        if not value > 0:
            raise argparse.ArgumentTypeError(f"--{name}: {value} must be > 0")
        return value
    return check


def nonnegative(name):
    def check(text):
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"--{name}: {text!r} is not a number")
        if not value >= 0:
            raise argparse.ArgumentTypeError(f"--{name}: {value} must be >= 0")
        return value
    return check


def number(name):
    def check(text):
        try:
            return float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"--{name}: {text!r} is not a number")
    return check
