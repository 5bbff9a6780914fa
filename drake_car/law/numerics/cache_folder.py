"""Where drake_car's disk caches live, for any user: the user's cache folder (``$XDG_CACHE_HOME``
or ``~/.cache`` on Linux, ``~/Library/Caches`` on macOS, ``%LOCALAPPDATA%`` on Windows), or,
where no home folder can be found (HOME unset and a user id without a passwd entry, as in a
container run as an arbitrary user), the temporary folder's ``drake_car-<uid>``.

numba's on-disk cache of the compiled laws (``cache=True``) lives beside their sources
(``__pycache__``) where the package is writable; where it is not (a shared, read-only install)
numba falls back to the user's cache folder, and without a home folder it fails at import
("cannot cache function ...: no locator available") or writes a folder named ``~`` in the
working folder. ``use_for_numba`` (called by ``drake_car.law`` before any law imports numba)
points numba at ``<cache folder>/drake_car/numba`` in that case; a ``NUMBA_CACHE_DIR`` already
set is kept."""

import os
import sys
import tempfile
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2]  # the drake_car package's folder


def user_cache_base():
    """The user's cache folder (see the module)."""
    try:
        home = Path.home()
    except (RuntimeError, KeyError):  # no HOME and no passwd entry
        home = None
    if home is not None and str(home).startswith("~"):
        home = None
    if sys.platform == "darwin" and home is not None:
        return home / "Library" / "Caches"
    if os.name == "nt":
        local = os.environ.get("LOCALAPPDATA")
        if local:
            return Path(local)
        return home / "AppData" / "Local" if home is not None else _temporary()
    xdg = os.environ.get("XDG_CACHE_HOME")
    if xdg:
        return Path(xdg)
    return home / ".cache" if home is not None else _temporary()


def _temporary():
    uid = os.getuid() if hasattr(os, "getuid") else "user"
    return Path(tempfile.gettempdir()) / f"drake_car-{uid}"


def use_for_numba(environ=os.environ, package=PACKAGE):
    """Sets ``NUMBA_CACHE_DIR`` where numba cannot cache beside the sources (see the module);
    returns the folder set, or None where nothing was set."""
    if environ.get("NUMBA_CACHE_DIR") or os.access(package / "law", os.W_OK):
        return None
    folder = user_cache_base() / "drake_car" / "numba"
    environ["NUMBA_CACHE_DIR"] = str(folder)
    return folder
