"""Reads and writes tyre property files (``.tir``), the format Adams, Chrono and MF-Tyre read.

A ``.tir`` file is a sequence of ``[SECTION]`` headers and ``KEY = value`` lines; ``$`` and
``!`` start comments (whole lines, or trailing a value); values are numbers or quoted strings.
``read_tir`` returns {KEY: value} over all sections (keys are unique across the sections of a
Magic Formula file) and raises ``TirFileError`` naming the file and the line for anything it
cannot read.
"""

import math
import re
from pathlib import Path

_SECTION = re.compile(r"^\[([A-Za-z0-9_]+)\]$")
_ENTRY = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)\s*=\s*(.+)$")


class TirFileError(ValueError):
    """A tyre property file is missing, malformed or lacks a required coefficient."""


def _strip_comment(line):
    quoted = False
    for i, ch in enumerate(line):
        if ch in "'\"":
            quoted = not quoted
        elif ch in "$!" and not quoted:
            return line[:i]
    return line


def parse_tir(text, name="<tir text>"):
    """Parses .tir text; returns (values {KEY: float | str}, sections {KEY: section})."""
    values, sections = {}, {}
    section = None
    for number, raw in enumerate(text.splitlines(), start=1):
        line = _strip_comment(raw).strip()
        if not line:
            continue
        match = _SECTION.match(line)
        if match:
            section = match.group(1).upper()
            continue
        match = _ENTRY.match(line)
        if not match:
            raise TirFileError(f"{name}:{number}: cannot read line {raw.strip()!r} "
                               "(expected [SECTION] or KEY = value)")
        if section is None:
            raise TirFileError(f"{name}:{number}: entry {match.group(1)} before any [SECTION]")
        key, value = match.group(1).upper(), match.group(2).strip()
        if value[:1] in "'\"":
            if len(value) < 2 or value[-1] != value[0]:
                raise TirFileError(f"{name}:{number}: unterminated string for {key}")
            parsed = value[1:-1]
        else:
            try:
                parsed = float(value)
            except ValueError:
                raise TirFileError(f"{name}:{number}: {key} = {value!r} is not a number")
            if not math.isfinite(parsed):
                raise TirFileError(f"{name}:{number}: {key} = {value!r} is not finite")
        if key in values:
            raise TirFileError(f"{name}:{number}: {key} is given twice")
        values[key] = parsed
        sections[key] = section
    return values, sections


def read_tir(path):
    path = Path(path)
    if path.is_dir():
        raise TirFileError(f"{path}: is a folder, not a tyre property file")
    if not path.is_file():
        raise TirFileError(f"{path}: tyre property file not found")
    try:
        text = path.read_bytes().decode("utf-8")
    except UnicodeDecodeError as e:
        raise TirFileError(f"{path}: not a text file (byte {e.start} is not UTF-8); a .tir "
                           "file is plain text") from None
    return parse_tir(text, str(path))


def format_tir(values, sections, header=""):
    """Writes {KEY: value} grouped by section (the order of first appearance)."""
    lines = [f"$ {line}" if line else "$" for line in header.splitlines()]
    order = []
    for key in values:
        if sections[key] not in order:
            order.append(sections[key])
    for section in order:
        lines.append(f"[{section}]")
        for key, value in values.items():
            if sections[key] != section:
                continue
            text = f"'{value}'" if isinstance(value, str) else repr(float(value))
            lines.append(f"{key:<25s} = {text}")
    return "\n".join(lines) + "\n"
