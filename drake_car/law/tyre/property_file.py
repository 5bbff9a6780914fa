"""Parses the text of a tyre property file (``.tir``) in the TNO/Adams layout.

A ``.tir`` file is a sequence of ``[SECTION]`` headers; in a section either ``KEY = value`` lines
or, in a table section (``[SHAPE]``, ``[DEFLECTION_LOAD_CURVE]``, ``[BOTTOMING_CURVE]``, ...),
rows of numbers with an optional ``{name name}`` header row. ``$`` and ``!`` start comments
(whole lines, or trailing a value; not inside a quoted string); values are numbers or quoted
strings (``'meter'``, glued to ``=`` or not). Numbers are the format's, Fortran reals as the
TNO and Adams readers take them: an optional sign, digits with an optional point (``12``,
``1.4``, ``.5``, ``5.``), an optional exponent ``E`` or ``D`` (``1.4e+000``, ``0.10D+01``);
nothing else (Python's ``1_0``, ``inf``, ``nan`` are not numbers). A value left empty
(``KEY =``) is an error naming the key and the line: an absent key takes the format's
default, an empty one is a damaged file. A UTF-8 byte-order mark is skipped. Keys are unique
within a section (``MASS`` is a unit in
``[UNITS]`` and a number in ``[INERTIA]``); the coefficients (every section but ``[MDI_HEADER]``
and ``[UNITS]``) must be unique across sections. ``[UNITS]`` names the units of the dimensional
parameters; they are converted to SI here (the Magic Formula's coefficients are dimensionless),
and a unit not known is refused. Anything unreadable raises ``TirFileError`` naming the file,
the line and the key.
"""

import dataclasses
import math
import re
from drake_car.law.errors import InputError

_SECTION = re.compile(r"^\[([A-Za-z0-9_ ]+)\]$")
_ENTRY = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)\s*=\s*(.*)$")
_TABLE_HEADER = re.compile(r"^\{.*\}$")
# A Fortran real (the format's numbers): sign, digits and point, exponent E or D.
_NUMBER = re.compile(r"^[+-]?(?:\d+\.?\d*|\.\d+)(?:[EeDd][+-]?\d+)?$")
# Sections that name the file and its units; every other section holds coefficients.
_META = ("MDI_HEADER", "UNITS")


class TirFileError(InputError):
    """A tyre property file is missing, malformed or lacks a required coefficient."""


# [UNITS] entries: the SI value of one unit (names as Adams writes them, lower case).
UNITS_SI = {
    "LENGTH": {"meter": 1.0, "meters": 1.0, "m": 1.0, "millimeter": 1e-3, "mm": 1e-3,
               "centimeter": 1e-2, "cm": 1e-2, "kilometer": 1e3, "km": 1e3,
               "inch": 0.0254, "in": 0.0254, "foot": 0.3048, "ft": 0.3048},
    "FORCE": {"newton": 1.0, "n": 1.0, "kilonewton": 1e3, "kn": 1e3,
              "pound_force": 4.4482216152605, "lbf": 4.4482216152605,
              "kilogram_force": 9.80665, "kgf": 9.80665},
    "ANGLE": {"radian": 1.0, "radians": 1.0, "rad": 1.0,
              "degree": math.pi / 180, "degrees": math.pi / 180, "deg": math.pi / 180},
    "MASS": {"kg": 1.0, "kilogram": 1.0, "kilograms": 1.0, "gram": 1e-3, "g": 1e-3,
             "tonne": 1e3, "pound_mass": 0.45359237, "lbm": 0.45359237},
    "TIME": {"second": 1.0, "seconds": 1.0, "sec": 1.0, "s": 1.0, "millisecond": 1e-3,
             "ms": 1e-3, "minute": 60.0, "min": 60.0, "hour": 3600.0, "h": 3600.0},
    "PRESSURE": {"pascal": 1.0, "pa": 1.0, "kilopascal": 1e3, "kpa": 1e3, "bar": 1e5,
                 "psi": 6894.757293168, "megapascal": 1e6, "mpa": 1e6},
}
# The dimensional parameters converted to SI: exponents of (LENGTH, FORCE, ANGLE, MASS, TIME,
# PRESSURE). Every other entry is a dimensionless coefficient or a string.
_L, _F, _A, _M, _T, _P = range(6)
_DIMENSIONS = {
    **{k: {_L: 1} for k in ("UNLOADED_RADIUS", "WIDTH", "RIM_RADIUS", "RIM_WIDTH",
                            "BOTTOM_OFFST", "Q_RE0_LENGTH")},
    **{k: {_F: 1} for k in ("FNOMIN", "FZMIN", "FZMAX", "FZ_MIN", "FZ_MAX")},
    **{k: {_A: 1} for k in ("ALPMIN", "ALPMAX", "CAMMIN", "CAMMAX")},
    **{k: {_P: 1} for k in ("INFLPRES", "NOMPRES", "PRESMIN", "PRESMAX")},
    "LONGVL": {_L: 1, _T: -1}, "VXLOW": {_L: 1, _T: -1},
    "VERTICAL_STIFFNESS": {_F: 1, _L: -1}, "VERTICAL_DAMPING": {_F: 1, _T: 1, _L: -1},
    "BOTTOM_STIFF": {_F: 1, _L: -1},
    "LONGITUDINAL_STIFFNESS": {_F: 1, _L: -1}, "LATERAL_STIFFNESS": {_F: 1, _L: -1},
    "MASS": {_M: 1}, "IXX": {_M: 1, _L: 2}, "IYY": {_M: 1, _L: 2},
    "BELT_MASS": {_M: 1}, "BELT_IXX": {_M: 1, _L: 2}, "BELT_IYY": {_M: 1, _L: 2},
}
_UNIT_NAMES = ("LENGTH", "FORCE", "ANGLE", "MASS", "TIME", "PRESSURE")


@dataclasses.dataclass
class PropertyFile:
    """A parsed .tir file. ``sections``: {SECTION: {KEY: value}} in SI; ``tables``:
    {SECTION: [rows of floats]} (a table section given twice keeps both, concatenated);
    ``lines``: {(SECTION, KEY): line number}; ``units``: the [UNITS] entries as written."""

    name: str
    sections: dict
    tables: dict
    lines: dict
    units: dict

    def coefficients(self):
        """{KEY: value} over the coefficient sections (all but [MDI_HEADER] and [UNITS])."""
        return {k: v for s, entries in self.sections.items() if s not in _META
                for k, v in entries.items()}

    def where(self, key):
        """``name:line`` of a coefficient (the file's name alone when it is not in the file)."""
        for (section, k), line in self.lines.items():
            if k == key and section not in _META:
                return f"{self.name}:{line}"
        return self.name

    def header(self, key):
        """A string entry of [MDI_HEADER] or of any coefficient section (None if absent)."""
        for section in ("MDI_HEADER", *self.sections):
            value = self.sections.get(section, {}).get(key)
            if value is not None:
                return value
        return None


def _strip_comment(line):
    quoted = None
    for i, ch in enumerate(line):
        if ch in "'\"" and quoted in (None, ch):
            quoted = None if quoted else ch
        elif ch in "$!" and quoted is None:
            return line[:i]
    return line


def number(text):
    """The value of a number as the format writes it (a Fortran real: ``_NUMBER``), or None."""
    if not _NUMBER.match(text):
        return None
    return float(text.replace("D", "E").replace("d", "e"))


def _value(text, key, where):
    if text[:1] in "'\"":
        if len(text) < 2 or text[-1] != text[0]:
            raise TirFileError(f"{where}: unterminated string for {key}")
        return text[1:-1].strip()
    value = number(text)
    if value is None:
        raise TirFileError(f"{where}: {key} = {text!r} is not a number (the format's numbers: "
                           "1, -1.5, .5, 1.4e+000, 0.10D+01) nor a quoted string")
    if not math.isfinite(value):
        raise TirFileError(f"{where}: {key} = {text!r} is not finite")
    return value


def _table_row(line, section, where):
    row = [number(x) for x in line.replace(",", " ").split()]
    if not row or None in row or not all(math.isfinite(x) for x in row):
        raise TirFileError(f"{where}: cannot read line {line!r} in table [{section}] "
                           "(expected numbers)")
    return row


def parse(text, name="<tir text>"):
    """Parses .tir text into a ``PropertyFile`` (units converted to SI)."""
    sections, tables, lines = {}, {}, {}
    section = None
    text = text.removeprefix("\ufeff")  # a UTF-8 byte-order mark
    for line_number, raw in enumerate(text.splitlines(), start=1):
        where = f"{name}:{line_number}"
        line = _strip_comment(raw).strip()
        if not line:
            continue
        match = _SECTION.match(line)
        if match:
            section = match.group(1).strip().upper()
            sections.setdefault(section, {})
            continue
        match = _ENTRY.match(line)
        if section is None:
            what = f"entry {match.group(1)}" if match else f"line {raw.strip()!r}"
            raise TirFileError(f"{where}: {what} before any [SECTION]")
        if not match:
            if sections[section] and section not in tables:
                raise TirFileError(f"{where}: cannot read line {raw.strip()!r} "
                                   f"(expected KEY = value in [{section}])")
            rows = tables.setdefault(section, [])
            if not _TABLE_HEADER.match(line):
                rows.append(_table_row(line, section, where))
            continue
        if section in tables:
            raise TirFileError(f"{where}: KEY = value line in table [{section}]")
        key, text_value = match.group(1).upper(), match.group(2).strip()
        if key in sections[section]:
            raise TirFileError(f"{where}: {key} is given twice in [{section}]")
        if not text_value:
            raise TirFileError(f"{where}: {key} is given no value; write its value, or leave "
                               "the line out to take the format's default")
        sections[section][key] = _value(text_value, key, where)
        lines[(section, key)] = line_number
    for section, entries in sections.items():
        if section in _META:
            continue
        for key in entries:
            first = next(s for s in sections if s not in _META and key in sections[s])
            if first != section:
                raise TirFileError(f"{name}:{lines[(section, key)]}: {key} is given twice "
                                   f"(in [{first}] and [{section}])")
    units = dict(sections.get("UNITS", {}))
    _to_si(sections, lines, units, name)
    return PropertyFile(name, sections, tables, lines, units)


def _to_si(sections, lines, units, name):
    factors = []
    for unit in _UNIT_NAMES:
        written = units.get(unit, "")
        where = f"{name}:{lines.get(('UNITS', unit), '')}".rstrip(":")
        if written == "":
            factors.append(1.0)
            continue
        if not isinstance(written, str):
            raise TirFileError(f"{where}: [UNITS] {unit} = {written!r} must be a unit name")
        factor = UNITS_SI[unit].get(written.lower())
        if factor is None:
            raise TirFileError(f"{where}: [UNITS] {unit} = {written!r} is not a unit drake_car "
                               f"knows (it knows {', '.join(UNITS_SI[unit])})")
        factors.append(factor)
    for section, entries in sections.items():
        if section in _META:
            continue
        for key, value in entries.items():
            powers = _DIMENSIONS.get(key)
            if powers and isinstance(value, float):
                entries[key] = value * math.prod(factors[i] ** p for i, p in powers.items())
