"""The disk caches for any user (review rv44): a user without a home folder (HOME unset, a uid
without a passwd entry: a container run as an arbitrary user) got "Could not determine home
directory" from every command, and with a read-only install numba's cache of the compiled laws
failed at import ("no locator available"). law.numerics.cache_folder finds a writable place."""

from pathlib import Path

from drake_car.law.numerics import cache_folder
from drake_car.sim import equilibrium_cache


def _no_home(monkeypatch):
    def refuse():
        raise RuntimeError("Could not determine home directory.")
    monkeypatch.setattr(Path, "home", staticmethod(refuse))
    monkeypatch.delenv("XDG_CACHE_HOME", raising=False)
    monkeypatch.delenv("HOME", raising=False)


def test_without_a_home_folder_the_caches_go_to_the_temporary_folder(monkeypatch, tmp_path):
    _no_home(monkeypatch)
    monkeypatch.setattr(cache_folder.tempfile, "gettempdir", lambda: str(tmp_path))
    monkeypatch.delenv(equilibrium_cache.ENVIRONMENT_VARIABLE, raising=False)
    base = tmp_path / f"drake_car-{cache_folder.os.getuid()}"
    assert cache_folder.user_cache_base() == base
    assert equilibrium_cache.cache_root() == base / "drake_car"  # no RuntimeError


def test_the_user_s_cache_folder_where_there_is_one(monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert cache_folder.user_cache_base() == tmp_path / "xdg"
    monkeypatch.delenv("XDG_CACHE_HOME")
    monkeypatch.setattr(Path, "home", staticmethod(lambda: tmp_path / "me"))
    assert cache_folder.user_cache_base() == tmp_path / "me" / ".cache"


def test_numba_s_cache_moves_only_where_the_package_is_read_only(monkeypatch, tmp_path):
    writable = tmp_path / "pkg"
    (writable / "law").mkdir(parents=True)
    environ = {}
    assert cache_folder.use_for_numba(environ, writable) is None and environ == {}
    monkeypatch.setattr(cache_folder.os, "access", lambda path, mode: False)  # read-only
    _no_home(monkeypatch)
    monkeypatch.setattr(cache_folder.tempfile, "gettempdir", lambda: str(tmp_path))
    folder = cache_folder.use_for_numba(environ, writable)
    assert environ["NUMBA_CACHE_DIR"] == str(folder)
    assert folder == tmp_path / f"drake_car-{cache_folder.os.getuid()}" / "drake_car" / "numba"
    assert not str(folder).startswith("~")  # not a folder named "~" in the working folder
    given = {"NUMBA_CACHE_DIR": "/somewhere/mine"}
    assert cache_folder.use_for_numba(given, writable) is None
    assert given == {"NUMBA_CACHE_DIR": "/somewhere/mine"}  # the user's own is kept
