"""Checks of parameter values that name the parameter (pure Python).

Every loadable parameter dataclass of the project has a ``check()`` that raises
``ParameterError`` naming the field, its value and what is allowed. Where a dataclass sits
inside a larger one (a scene), the caller prefixes the key with ``within``, so the message ends
up naming the whole key path: ``friction.law.mu_d = 0.5 must be <= mu_s = 0.4``.
"""

import math
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
