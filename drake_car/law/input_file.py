"""A file the user names as input (a scene, car or study file, a .tir file, a measured loop),
read only if it is a regular file and read no further than its limit: a named pipe would
block the open or the read forever, a device (/dev/zero) would be read until memory runs out.
Used by every reader of an input file (``scene.guard.read_yaml_file``, ``law.tyre.tir``,
``study.rig.measured.read_loop``)."""

import os
import stat
from pathlib import Path

from drake_car.law.errors import InputError

_KINDS = ((stat.S_ISFIFO, "a named pipe"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def refusal(mode, what, is_text):
    """Why a file of ``st_mode`` ``mode`` is not read as a ``what`` (None: a regular file)."""
    if stat.S_ISREG(mode):
        return None
    if stat.S_ISDIR(mode):
        return f"is a folder, not a {what}"
    kind = next((name for test, name in _KINDS if test(mode)), "a special file")
    return f"not a regular file ({kind}); a {what} is {is_text}"


def read_input_file(path, what, *, limit, is_text="a text file", error=InputError, where=None):
    """The bytes of ``path``, a ``what`` (e.g. "scene file"), at most ``limit`` bytes; anything
    else is ``error`` naming ``where`` (default: the path; "": the caller names it): missing, a
    folder, not a regular file (``is_text`` says what it should be), unreadable, over the
    limit. The file is opened without blocking (O_NONBLOCK: a named pipe with no writer opens
    at once) and checked before any read."""
    path = Path(path)
    where = str(path) if where is None else where

    def refused(text):
        return error(f"{where}: {text}" if where else text)

    try:
        why = refusal(os.stat(path).st_mode, what, is_text)
        if why:
            raise refused(why)
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except FileNotFoundError:
        raise refused(f"{what} not found") from None
    except OSError as e:
        raise refused(f"cannot be opened: {e.strerror or e}") from None
    with os.fdopen(fd, "rb") as f:
        try:
            why = refusal(os.fstat(f.fileno()).st_mode, what, is_text)  # replaced since?
            if why:
                raise refused(why)
            data = f.read(limit + 1)
        except OSError as e:
            raise refused(f"cannot be read: {e.strerror or e}") from None
    if len(data) > limit:
        raise refused(f"over {limit} bytes; a {what} is at most {limit} bytes")
    return data


def check_input_option(option, path, what, *, is_text="a text file"):
    """Refuses (InputError naming ``option``) an existing ``path`` given to ``option`` that is
    not a regular file, before anything opens it; a missing one is left to its reader."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return
    why = refusal(mode, what, is_text)
    if why:
        raise InputError(f"{option} {path}: {why}")
