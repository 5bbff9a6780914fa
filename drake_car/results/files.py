"""The results' files: one atomic writer (``write_text``: a temporary file beside the target,
renamed over it, so a reader never sees half a file), JSON made from numpy values, lossless
CSV (floats in their shortest exact form), and a run's own files (``write_run``)."""

import contextlib
import csv
import io
import json
import math
import os
import shutil
import uuid
from pathlib import Path

import numpy as np

from drake_car.results.diagram import diagram_overview_dot, diagram_svg
from drake_car.results.provenance import provenance
from drake_car.results.signals import signals_held


def write_text(path, text):
    """Writes ``text`` to ``path`` atomically (a temporary file beside it, then renamed); an
    OSError names ``path`` (a full disk's, raised by the write, names no file)."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{uuid.uuid4().hex[:8]}.tmp")
    try:
        with named(path):
            tmp.write_text(text)
            os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


@contextlib.contextmanager
def named(path):
    """An OSError that names no file (a write's or a close's: a full disk) names ``path``."""
    try:
        yield
    except OSError as e:
        if e.filename is not None:
            raise
        raise type(e)(e.errno, e.strerror or str(e), str(path)) from None


@contextlib.contextmanager
def files_into(folder):
    """Yields a temporary folder inside ``folder`` (one that is added to, as a sweep's, not
    replaced whole); on success each file written there replaces its namesake in ``folder``,
    whole (a reader never sees half a file); on any error none is moved. The temporary folder
    is removed either way."""
    folder = Path(folder)
    staging = folder / f".partial-{os.getpid()}-{uuid.uuid4().hex[:8]}"
    staging.mkdir()
    try:
        yield staging
        with signals_held():  # all files or none: Ctrl-C or SIGTERM waits for the renames
            for path in sorted(staging.iterdir()):
                os.replace(path, folder / path.name)
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def plain(value):
    """``value`` with numpy types and non-finite floats made JSON-ready."""
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return plain(value.tolist())
    if isinstance(value, (np.floating, np.integer, np.bool_)):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def json_text(data):
    """``data`` (numpy values and non-finite floats made JSON-ready) as indented JSON."""
    return json.dumps(plain(data), indent=2, sort_keys=False) + "\n"


def write_json(path, data):
    """``data`` (numpy values and non-finite floats made JSON-ready) as indented JSON."""
    write_text(path, json_text(data))


def write_csv(path, columns: dict):
    """``columns``: name -> sequence (all the same length); strings or numbers. Floats are
    written with ``repr`` (shortest round-trip form): the CSV carries the run's bits."""
    write_text(path, csv_text(columns))


def csv_text(columns: dict):
    """The text ``write_csv`` writes."""
    names = list(columns)
    lengths = {len(columns[n]) for n in names}
    if len(lengths) > 1:
        raise ValueError(f"columns of different lengths: "
                         f"{ {n: len(columns[n]) for n in names} }")
    rows = zip(*(columns[n] for n in names))
    buffer = io.StringIO(newline="")
    writer = csv.writer(buffer)
    writer.writerow(names)
    for row in rows:
        writer.writerow([repr(float(x)) if isinstance(x, (float, np.floating)) else x
                         for x in row])
    return buffer.getvalue()


def read_csv(path):
    """Reads a CSV written by ``write_csv``: name -> numpy array (or list of str)."""
    with open(path, newline="") as f:
        return parse_csv(f.read())


def parse_csv(text):
    """``csv_text``'s text back: name -> numpy array (or list of str). Rows of another length
    than the header (a truncated file) raise ValueError."""
    rows = list(csv.reader(io.StringIO(text, newline="")))
    if not rows:
        raise ValueError("empty CSV")
    names, data = rows[0], rows[1:]
    for number, row in enumerate(data, start=2):
        if len(row) != len(names):
            raise ValueError(f"row {number} has {len(row)} values, not {len(names)}")
    out = {}
    for i, name in enumerate(names):
        values = [r[i] for r in data]
        try:
            out[name] = np.array([float(v) for v in values])
        except ValueError:
            out[name] = values
    return out


def write_run(run, folder, *, diagram=True):
    """A run's own files: history.csv, scene.yaml (the scene as it ran), run.json (how it went,
    provenance; its stick-slip events and their resolution), events.csv (the events, one row
    each, when the scene has strut friction), diagram.svg and replay.html when there is one."""
    folder = Path(folder)
    for name, text in run_texts(run).items():
        if name != "diagram.dot":
            write_text(folder / name, text)
    if getattr(run, "events", None):
        write_csv(folder / "events.csv", {k: v for k, v in run.events.items()
                                          if isinstance(v, list)})
    if diagram:
        write_diagram_svg(run.diagram_dot, folder / "diagram.svg")


def write_diagram_svg(dot_text, path):
    """Graphviz ``dot_text`` drawn as SVG at ``path``, the .dot kept beside it."""
    write_text(path, diagram_svg(dot_text))
    write_text(Path(path).with_suffix(".dot"), dot_text)


def write_diagram_overview_svg(dot_text, path):
    """``results.diagram.diagram_overview_dot`` of Drake's Graphviz text, drawn as SVG."""
    write_text(path, diagram_svg(diagram_overview_dot(dot_text)))


def run_texts(run, **extra):
    """name -> text of ``run``'s files; ``extra`` goes into run.json's provenance."""
    record = run.record() | {"final_positions": run.final["positions"],
                             "provenance": provenance(**extra)}
    texts = {"history.csv": csv_text(run.history), "scene.yaml": run.scene_file_text,
             "run.json": json_text(record), "diagram.dot": run.diagram_dot}
    if run.replay_html is not None:
        texts["replay.html"] = run.replay_html
    return texts
