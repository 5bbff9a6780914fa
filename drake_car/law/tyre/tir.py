"""Reads and writes tyre property files (``.tir``), the format Adams, Chrono and MF-Tyre read.

A ``.tir`` file is a sequence of ``[SECTION]`` headers and ``KEY = value`` lines; ``$`` and
``!`` start comments (whole lines, or trailing a value); values are numbers or quoted strings.
``read_tir`` returns {KEY: value} over all sections (keys are unique across the sections of a
Magic Formula file) and raises ``TirFileError`` naming the file and the line for anything it
cannot read.
"""

import math
import os
import re
import stat
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
    try:
        text = read_tir_bytes(path).decode("utf-8")
    except UnicodeDecodeError as e:
        raise TirFileError(f"{path}: not a text file (byte {e.start} is not UTF-8); a .tir "
                           "file is plain text") from None
    return parse_tir(text, str(path))


# A .tir file's size limit: a Magic Formula file is 10-30 kB (the shipped one 13 kB).
MAX_TIR_BYTES = 1_000_000


def read_tir_bytes(path):
    """The bytes of tyre property file ``path``: a regular file of at most MAX_TIR_BYTES, read
    no further than that (a device, a FIFO, a folder or a bigger file: TirFileError)."""
    path = Path(path)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    except FileNotFoundError:
        raise TirFileError(f"{path}: tyre property file not found") from None
    except OSError as e:
        raise TirFileError(f"{path}: cannot be opened: {e.strerror or e}") from None
    kind = os.fstat(fd).st_mode
    if not stat.S_ISREG(kind):
        os.close(fd)
        raise TirFileError(f"{path}: is a folder, not a tyre property file" if stat.S_ISDIR(kind)
                           else f"{path}: not a regular file; a .tir file is plain text")
    with os.fdopen(fd, "rb") as f:
        try:
            data = f.read(MAX_TIR_BYTES + 1)
        except OSError as e:
            raise TirFileError(f"{path}: cannot be read: {e.strerror or e}") from None
    if len(data) > MAX_TIR_BYTES:
        raise TirFileError(f"{path}: over {MAX_TIR_BYTES} bytes; a .tir file is at most "
                           f"{MAX_TIR_BYTES} bytes (Magic Formula files are 10-30 kB)")
    return data


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
