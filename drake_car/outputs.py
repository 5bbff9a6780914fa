"""Writing results: all-or-nothing output folders, CSV, JSON with provenance."""

import contextlib
import csv
import datetime
import importlib.metadata
import json
import platform
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

REPO_ROOT = Path(__file__).resolve().parents[1]


@contextlib.contextmanager
def output_folder(out_dir):
    """Yields a temporary folder beside ``out_dir``; on success its files move into ``out_dir``
    (created if needed), on any error the temporary folder is removed and ``out_dir`` is left as
    it was, so nothing half-written appears there."""
    out_dir = Path(out_dir)
    out_dir.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.partial-", dir=out_dir.parent))
    try:
        yield staging
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    out_dir.mkdir(parents=True, exist_ok=True)
    for item in staging.iterdir():
        target = out_dir / item.name
        if target.is_dir():
            shutil.rmtree(target)
        item.replace(target)
    staging.rmdir()


def provenance(**extra):
    """How a result was made: command, versions, commit, time."""
    try:
        commit = subprocess.run(["git", "-C", str(REPO_ROOT), "rev-parse", "HEAD"],
                                capture_output=True, text=True, timeout=5).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        commit = ""
    try:
        drake_version = importlib.metadata.version("drake")
    except importlib.metadata.PackageNotFoundError:
        drake_version = "unknown"
    info = {
        "command": " ".join([Path(sys.argv[0]).name] + sys.argv[1:]),
        "git_commit": commit or "unknown",
        "drake": drake_version,
        "python": platform.python_version(),
        "numpy": np.__version__,
        "machine": platform.machine(),
        "created_utc": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
    }
    info.update(extra)
    return info


def _plain(value):
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, (np.floating, np.integer)):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    return value


def write_json(path, data):
    Path(path).write_text(json.dumps(_plain(data), indent=2, sort_keys=False) + "\n")


def write_csv(path, columns: dict):
    """``columns``: name -> sequence (all the same length); strings or numbers."""
    names = list(columns)
    rows = zip(*(columns[n] for n in names))
    with open(path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(names)
        for row in rows:
            writer.writerow([f"{x:.9g}" if isinstance(x, (float, np.floating)) else x
                             for x in row])


def read_csv(path):
    """Reads a CSV written by ``write_csv``: name -> numpy array (or list of str)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    names, data = rows[0], rows[1:]
    out = {}
    for i, name in enumerate(names):
        values = [r[i] for r in data]
        try:
            out[name] = np.array([float(v) for v in values])
        except ValueError:
            out[name] = values
    return out


class Progress:
    """One line per update when not on a terminal, an updating line on one."""

    def __init__(self, label, total, stream=sys.stderr):
        self.label, self.total, self.stream = label, total, stream
        self.tty = stream.isatty()

    def update(self, done, note=""):
        text = f"{self.label}: {done}/{self.total} {note}".rstrip()
        if self.tty:
            self.stream.write("\r" + text + " " * 10)
            if done >= self.total:
                self.stream.write("\n")
        else:
            self.stream.write(text + "\n")
        self.stream.flush()
