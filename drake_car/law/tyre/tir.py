"""Reads and writes tyre property files (``.tir``), the format Adams, Chrono and MF-Tyre read.

``read_tir`` reads a file's bytes and returns ``parse_tir``'s ``PropertyFile`` (the syntax, the
table sections and the units: ``law.tyre.property_file``); it raises ``TirFileError`` naming the
file and the line for anything it cannot read.
"""

from pathlib import Path

from drake_car.law.checks import read_input_file
from drake_car.law.tyre.property_file import TirFileError, parse

__all__ = ["TirFileError", "parse_tir", "read_tir", "read_tir_bytes", "format_tir"]
_SI_NAMES = {"LENGTH": "meter", "FORCE": "newton", "ANGLE": "radian", "MASS": "kg",
             "TIME": "second", "PRESSURE": "pascal"}


def parse_tir(text, name="<tir text>"):
    """Parses .tir text; returns a ``property_file.PropertyFile``."""
    return parse(text, name)


def read_tir(path):
    """The ``PropertyFile`` in .tir file ``path``: UTF-8, or else Latin-1 (tools on Windows
    write comments such as "25 °C" that way; every value the formula reads is ASCII); a file
    with a NUL byte is no text and is refused."""
    path = Path(path)
    data = read_tir_bytes(path)
    if b"\0" in data:
        raise TirFileError(f"{path}: not a text file (byte {data.index(0)} is NUL); a .tir "
                           "file is plain text")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        text = data.decode("latin-1")
    return parse_tir(text, str(path))


# A .tir file's size limit: a Magic Formula file is 10-30 kB (the shipped one 13 kB).
MAX_TIR_BYTES = 1_000_000


def read_tir_bytes(path):
    """The bytes of tyre property file ``path``: a regular file of at most MAX_TIR_BYTES, read
    no further than that (a device, a FIFO, a folder or a bigger file: TirFileError)."""
    return read_input_file(path, "tyre property file", limit=MAX_TIR_BYTES,
                           is_text="plain text (a .tir file)", error=TirFileError)


def format_tir(tir, header=""):
    """Writes a ``PropertyFile``'s sections (SI values, so [UNITS] is written as SI) and tables."""
    lines = [f"$ {line}" if line else "$" for line in header.splitlines()]
    for section, entries in tir.sections.items():
        lines.append(f"[{section}]")
        if section == "UNITS":
            entries = {k: _SI_NAMES[k] for k in entries if k in _SI_NAMES}
        for key, value in entries.items():
            text = f"'{value}'" if isinstance(value, str) else repr(float(value))
            lines.append(f"{key:<25s} = {text}")
        for row in tir.tables.get(section, []):
            lines.append("  ".join(repr(x) for x in row))
    return "\n".join(lines) + "\n"
