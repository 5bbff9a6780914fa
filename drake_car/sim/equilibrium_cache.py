"""The static equilibrium kept on disk between processes, so a run does not settle the car
again (6 s of simulation at 1 ms) when that settling scene has been run before.

An entry is named by the SHA-256 of everything that changes its bits: the settling scene's
YAML (``sim.equilibrium.equilibrium_scene``), the contents of drake_car's own source and model
files (its Python, the car's SDFormat and tyre files: a commit, an edit not yet committed, an
installed version alike), and the versions of drake, numba and numpy. An entry is JSON holding
its own key; one that does not read back whole (damaged, cut short, another key, a value not a
finite number) is ignored and recomputed, never trusted. Entries are written atomically (a
temporary file in the same folder, then ``os.replace``), so two processes settling the same
scene at once both write a whole entry.

The folder: ``$DRAKE_CAR_CACHE_DIR`` if set, else the platform's cache folder
(``$XDG_CACHE_HOME`` or ``~/.cache`` on Linux, ``~/Library/Caches`` on macOS,
``%LOCALAPPDATA%`` on Windows) + ``drake_car/equilibrium``. Clearing it is always safe:
``python -m drake_car.sim.equilibrium_cache --clear`` (or delete the folder).
``DRAKE_CAR_CACHE_DIR=off`` turns the disk cache off. The lane change's calibrations
(``sim.lane_change_cache``) keep theirs beside it (``cache_root``), written the same way
(``write_entry``).
"""

import dataclasses
import functools
import hashlib
import json
import logging
import math
import os
import tempfile
from importlib import metadata
from pathlib import Path

from drake_car.law.numerics.cache_folder import user_cache_base
from drake_car.sim.equilibrium import Equilibrium

ENVIRONMENT_VARIABLE = "DRAKE_CAR_CACHE_DIR"
FORMAT = 1  # bump when an entry's layout changes
_PACKAGE = Path(__file__).resolve().parents[1]  # drake_car/
_FIELDS = [f.name for f in dataclasses.fields(Equilibrium)]
log = logging.getLogger(__name__)


def cache_root():
    """The folder of drake_car's disk caches (None: off)."""
    chosen = os.environ.get(ENVIRONMENT_VARIABLE)
    if chosen:
        return None if chosen == "off" else Path(chosen).expanduser()
    return user_cache_base() / "drake_car"


def cache_folder():
    """Where entries live (None: the disk cache is off)."""
    root = cache_root()
    return None if root is None else root / "equilibrium"


@functools.lru_cache(maxsize=1)
def code_fingerprint():
    """SHA-256 of drake_car's Python and model files and the versions of the packages that
    compute an equilibrium (once per process: ~100 small files)."""
    digest = hashlib.sha256(f"format {FORMAT}\n".encode())
    for package in ("drake", "numba", "numpy"):
        try:
            version = metadata.version(package)
        except metadata.PackageNotFoundError:
            version = "absent"
        digest.update(f"{package} {version}\n".encode())
    files = sorted(_PACKAGE.rglob("*.py")) + sorted((_PACKAGE / "data" / "urdf").rglob("*"))
    for path in files:
        if path.is_file() and "__pycache__" not in path.parts:
            digest.update(str(path.relative_to(_PACKAGE)).encode() + b"\0")
            digest.update(path.read_bytes() + b"\0")
    return digest.hexdigest()


def entry_key(settle_yaml):
    return hashlib.sha256((code_fingerprint() + "\n" + settle_yaml).encode()).hexdigest()


def load(settle_yaml):
    """The cached equilibrium of this settling scene, or None (absent, off, or not whole: a
    damaged entry is ignored with a warning naming its file)."""
    folder = cache_folder()
    if folder is None:
        return None
    key = entry_key(settle_yaml)
    path = folder / f"{key}.json"
    try:
        text = path.read_text()
    except FileNotFoundError:
        return None
    except (OSError, ValueError) as e:
        return _ignored(path, f"cannot be read ({type(e).__name__})")
    try:
        data = json.loads(text)
    except ValueError:
        return _ignored(path, "not JSON (cut short?)")
    why = _damage(data, key)
    return _ignored(path, why) if why else Equilibrium(**data["equilibrium"])


def discard(settle_yaml, why):
    """Deletes this settling scene's entry, found damaged by its user (``why``), with a
    warning naming its file."""
    folder = cache_folder()
    if folder is not None:
        path = folder / f"{entry_key(settle_yaml)}.json"
        _ignored(path, why)
        path.unlink(missing_ok=True)


def _ignored(path, why):
    log.warning("%s: a damaged equilibrium cache entry (%s); ignored, the car is settled "
                "again", path, why)
    return None


def store(settle_yaml, equilibrium: Equilibrium):
    """Writes the entry atomically; a folder that cannot be written leaves the run uncached."""
    folder = cache_folder()
    if folder is None:
        return
    key = entry_key(settle_yaml)
    write_entry(folder, key, json.dumps({"key": key,
                                         "equilibrium": dataclasses.asdict(equilibrium)}))


def write_entry(folder, key, text):
    """Writes ``folder``/``key``.json atomically (a temporary file in the same folder, then
    ``os.replace``); a folder that cannot be written leaves it unwritten."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(dir=folder, prefix=f".{key}.", suffix=".tmp")
        try:
            with os.fdopen(handle, "w") as f:
                f.write(text)
            os.replace(temporary, folder / f"{key}.json")
        except BaseException:
            Path(temporary).unlink(missing_ok=True)
            raise
    except OSError:
        pass


def clear():
    """Deletes every entry; returns how many."""
    return clear_folder(cache_folder())


def clear_folder(folder):
    """Deletes every entry of a cache folder (its JSON files and unfinished writes; None or
    absent: none); returns how many."""
    if folder is None or not folder.is_dir():
        return 0
    entries = list(folder.glob("*.json")) + list(folder.glob(".*.tmp"))
    for path in entries:
        path.unlink(missing_ok=True)
    return len(entries)


def _finite(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def _damage(data, key):
    """Why ``data`` (an entry's JSON) is not a whole entry of ``key`` (None: it is)."""
    if not isinstance(data, dict) or data.get("key") != key:
        return "not this entry's key"
    e = data.get("equilibrium")
    if not isinstance(e, dict) or set(e) != set(_FIELDS):
        return f"its fields are not {', '.join(_FIELDS)}"
    if not (isinstance(e["positions"], list) and e["positions"]
            and all(map(_finite, e["positions"]))):
        return "positions: not a list of finite numbers"
    for name in ("overlap_m", "corner_loads_N"):
        if not (isinstance(e[name], dict) and all(map(_finite, e[name].values()))):
            return f"{name}: not a mapping to finite numbers"
    for name in ("max_abs_velocity", "settle_s", "time_step_s"):
        if not _finite(e[name]):
            return f"{name}: not a finite number"
    return None
