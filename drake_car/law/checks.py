"""Checks of parameter values that name the parameter (pure Python).

Every loadable parameter dataclass of the project has a ``check()`` that raises
``ParameterError`` naming the field, its value and what is allowed. Where a dataclass sits
inside a larger one (a scene), the caller prefixes the key with ``within``, so the message ends
up naming the whole key path: ``friction.law.mu_d = 0.5 must be <= mu_s = 0.4``.

A file the user names as input (a scene, car or study file, a .tir file, a measured loop) is
read by ``read_input_file``: only if it is a regular file and no further than its limit (a
named pipe would block the open or the read forever, a device such as /dev/zero would be read
until memory runs out); ``check_input_option`` refuses such a file given to an option, naming
the option, before anything opens it.
"""

import math
import os
import stat
from pathlib import Path

from drake_car.law.errors import InputError


class ParameterError(InputError):
    """A parameter is out of its allowed range; ``key`` names it (a dotted path)."""

    def __init__(self, key, value, requirement):
        self.key, self.value, self.requirement = key, value, requirement
        super().__init__(f"{key} = {excerpt(value)} {requirement}")

    def within(self, prefix):
        """The same error with ``prefix.`` put before the key."""
        return ParameterError(f"{prefix}.{self.key}" if prefix else self.key, self.value,
                              self.requirement)


def one_line(error):
    """An exception's message as one line (its whitespace folded): what a command prints."""
    return " ".join(str(error).split())


def is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def finite(obj, *names):
    """Every named attribute is a finite number."""
    for name in names:
        value = getattr(obj, name)
        if not (is_number(value) and math.isfinite(value)):
            raise ParameterError(name, value, "must be a finite number")


def positive(obj, *names):
    """Every named attribute is a finite number > 0."""
    finite(obj, *names)
    for name in names:
        if not getattr(obj, name) > 0:
            raise ParameterError(name, getattr(obj, name), "must be > 0")


def nonnegative(obj, *names):
    """Every named attribute is a finite number >= 0."""
    finite(obj, *names)
    for name in names:
        if not getattr(obj, name) >= 0:
            raise ParameterError(name, getattr(obj, name), "must be >= 0")


def in_range(obj, name, low, high, why=""):
    """low <= value <= high (finite)."""
    finite(obj, name)
    value = getattr(obj, name)
    if not low <= value <= high:
        raise ParameterError(name, value, f"must lie in [{low:g}, {high:g}]"
                             + (f" ({why})" if why else ""))


def one_of(obj, name, allowed):
    value = getattr(obj, name)
    if value not in allowed:
        raise ParameterError(name, value, f"must be one of {', '.join(map(str, allowed))}")


def checked(obj, prefix):
    """Runs ``obj.check()``, prefixing a ParameterError's key with ``prefix``."""
    try:
        obj.check()
    except ParameterError as e:
        raise e.within(prefix) from None
    return obj


_EXCERPT = None


def excerpt(value):
    """``repr(value)`` cut to a bounded excerpt (``reprlib``): what an error message quotes
    of a value that came from outside (a huge list or string stays a line)."""
    global _EXCERPT
    if type(value).__module__ == "numpy" and getattr(value, "ndim", None) == 0:
        value = value.item()  # a numpy scalar is its number (not ``np.float64(2.11)``)
    if _EXCERPT is None:
        import reprlib
        _EXCERPT = reprlib.Repr()
        _EXCERPT.maxstring = _EXCERPT.maxother = 80
        _EXCERPT.maxlist = _EXCERPT.maxdict = _EXCERPT.maxtuple = 6
        _EXCERPT.maxlevel = 3
    return _EXCERPT.repr(value)


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
