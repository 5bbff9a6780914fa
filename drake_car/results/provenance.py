"""How a result was made: the command, the code (git commit and whether it had uncommitted
changes, drake_car's installed version) and the versions of what can change its bits."""

import datetime
import functools
import hashlib
import importlib.metadata
import os
import platform
import shlex
import subprocess
import sys
from pathlib import Path


def provenance(**extra):
    """How a result was made: command, versions (drake_car's as installed, None if it is not),
    the git commit of drake_car's source and whether its working tree had uncommitted changes
    (both None when the source is not in a git checkout: ``source_checkout``), the working
    folder (where a scene's relative file names were found), time."""
    commit, dirty = source_checkout()
    info = {
        # quoted as a shell reads it: --scene_text 'car_file: my.yaml' pastes back as it ran
        "command": " ".join([_program(sys.argv[0])] + [shlex.quote(a) for a in sys.argv[1:]]),
        "git_commit": commit,
        "dirty": dirty,
        "drake_car": _installed_version("drake_car"),
        "drake": _installed_version("drake") or "unknown",
        "python": platform.python_version(),
        "numpy": _installed_version("numpy") or "unknown",
        "numba": _installed_version("numba") or "unknown",
        "host": platform.node(),
        "working_folder": _working_folder(),
        "machine": platform.machine(),
        "created_utc": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
    }
    info.update(extra)
    return info


def _working_folder():
    """The folder the command ran in (a scene's relative file names resolve there); None when
    it no longer exists."""
    try:
        return os.getcwd()
    except OSError:
        return None


def _program(path):
    """How the running program is called again: a console script by its name, a module run with
    ``python -m`` (its file inside the ``drake_car`` package) as that, a script as it was
    given."""
    path = Path(path)
    if path.suffix != ".py":
        return path.name
    package = Path(__file__).resolve().parents[1]
    try:
        module = path.resolve().relative_to(package.parent).with_suffix("")
    except ValueError:
        module = None
    if module is not None and module.parts[0] == package.name:
        return "python -m " + ".".join(module.parts)
    return f"python {path}"


@functools.lru_cache(maxsize=1)
def code_versions():
    """What can change a run's bits, as this process runs it: drake_car's commit (or its
    installed version outside a checkout), whether the checkout had uncommitted changes and a
    hash of them (two different edits are two codes), drake's, numba's and numpy's versions."""
    commit, dirty = source_checkout()
    diff = None
    if dirty:
        package = Path(__file__).resolve().parents[1]
        diff = hashlib.sha256((_git(package, "diff", "HEAD", "--", str(package)) or "")
                              .encode()).hexdigest()[:16]
    return {"drake_car": commit or _installed_version("drake_car"), "dirty": dirty,
            "diff": diff, "drake": _installed_version("drake"),
            "numba": _installed_version("numba"), "numpy": _installed_version("numpy")}


@functools.lru_cache(maxsize=1)
def source_checkout():
    """(commit, dirty) of the git checkout that holds drake_car's source: its HEAD, and whether
    tracked files have uncommitted changes. (None, None) when there is none: no git, or the
    package is not a tracked folder of that checkout (an installed copy inside some other
    repository, say in its ignored virtual environment, does not take that repository's).
    Asked once per process, as ``code_versions``: the code a process runs is the code it
    imported (three git calls, ~15 ms, were made for every run's provenance on a worker)."""
    package = Path(__file__).resolve().parents[1]
    found = (_git(package, "rev-parse", "--show-toplevel", "HEAD") or "").splitlines()
    if len(found) != 2:
        return None, None
    top, commit = Path(found[0]).resolve(), found[1].strip()
    if top not in package.parents or not _git(
            top, "ls-files", "--", str(package.relative_to(top) / "__init__.py")):
        return None, None
    changes = _git(top, "status", "--porcelain", "--untracked-files=no")
    return commit, None if changes is None else bool(changes)


def _git(folder, *args):
    """What ``git -C folder args`` printed, stripped; None if git is missing or fails."""
    try:
        done = subprocess.run(["git", "-C", str(folder), *args], capture_output=True,
                              text=True, timeout=5)
    except (OSError, subprocess.SubprocessError):
        return None
    return done.stdout.strip() if done.returncode == 0 else None


def _installed_version(package):
    """``package``'s installed version (None if it is not installed)."""
    try:
        return importlib.metadata.version(package)
    except importlib.metadata.PackageNotFoundError:
        return None
