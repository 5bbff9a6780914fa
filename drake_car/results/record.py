"""A run as its files and back: what a results folder holds of a run is text (history.csv,
scene.yaml, run.json, diagram.dot, replay.html when there is one), never a pickle; ``run_texts``
makes those texts (in the process that ran the run: its provenance is stamped there) and
``run_from_texts`` / ``read_run`` rebuild the ``sim.simulate.Run`` from them, bit for bit (the
CSV and the JSON carry floats in their shortest exact form). A folder holding a ``*.pkl`` is
refused (``refuse_pickles``): a results folder is shared, and a pickle runs code when loaded."""

import hashlib
import json
import math
from pathlib import Path

from drake_car.model.loading import DataFileError, data_path
from drake_car.results.files import parse_csv
from drake_car.results.folder import OutputError
from drake_car.scene.load import SceneError, load_scene_text, parse_scene_text, stated
from drake_car.sim.simulate import Run

# The files a finished run is made of (replay.html only when the scene asked for one).
RUN_FILES = ("history.csv", "scene.yaml", "run.json", "diagram.dot")
OPTIONAL_FILES = ("replay.html",)


def checksums(texts):
    """name -> sha256 of each text (what a sweep records at commit and checks on resume)."""
    return {name: hashlib.sha256(text.encode()).hexdigest() for name, text in texts.items()}


def run_from_texts(texts, where="run", *, trusted=False):
    """The Run that ``run_texts`` made ``texts`` of; a missing or unreadable file raises
    OutputError naming it. ``trusted``: the texts' checksums say they are what a run of a
    checked scene wrote (a sweep's committed run, a worker's result): the scene is parsed, not
    checked again."""
    for name in RUN_FILES:
        if name not in texts:
            raise OutputError(f"{where}/{name}: missing")
    try:
        record = json.loads(texts["run.json"])
        final = dict(record["final"]) | {"positions": record["final_positions"]}
        history = parse_csv(texts["history.csv"])
        scene = (parse_scene_text if trusted else load_scene_text)(texts["scene.yaml"],
                                                                   f"{where}/scene.yaml")
        return Run(scene=scene, history=history, wall_s=record["wall_s"],
                   frozen_sap_steps=record["frozen_sap_steps"],
                   first_frozen_sap_step_s=record["first_frozen_sap_step_s"],
                   steps=record["steps"], final=final, diagram_dot=texts["diagram.dot"],
                   replay_html=texts.get("replay.html"),
                   cpu_s=record.get("cpu_s", float("nan")), events=record.get("events"),
                   resolution=with_unknown_errors(record.get("resolution")))
    except SceneError as e:
        raise OutputError(str(e)) from None
    except (ValueError, KeyError, TypeError, IndexError) as e:
        raise OutputError(f"{where}: damaged run files ({type(e).__name__}: {e})"[:300]) \
            from None


# A resolution's error maps (``sim.window.record``): an unknown error (a window whose branch
# depends on what it cannot bound, ``sim.twins``) is infinite in memory and null in run.json.
ERROR_MAPS = ("position_errors", "solver_errors", "inherited_errors", "gap_errors")


def with_unknown_errors(resolution):
    """``resolution`` (a run.json's) with each null of its error maps infinite again."""
    def restored(record):
        return record | {key: {pair: math.inf if e is None else e
                               for pair, e in record[key].items()}
                         for key in ERROR_MAPS if isinstance(record.get(key), dict)}
    if not isinstance(resolution, dict):
        return resolution
    return restored(resolution) | {"windows": [restored(w) for w in
                                               resolution.get("windows") or []]}


def read_texts(folder, names=RUN_FILES + OPTIONAL_FILES):
    """name -> text of those of ``names`` that ``folder`` holds (UTF-8 text only)."""
    folder = Path(folder)
    texts = {}
    for name in names:
        path = folder / name
        if path.is_file():
            try:
                with open(path, encoding="utf-8", newline="") as f:  # bytes as written
                    texts[name] = f.read()
            except (OSError, UnicodeDecodeError) as e:
                raise OutputError(f"{path}: cannot be read ({type(e).__name__}: {e})") from None
    return texts


def read_run(folder):
    """The Run whose files ``folder`` holds (``refuse_pickles`` first)."""
    refuse_pickles(folder)
    return run_from_texts(read_texts(folder), str(folder))


def refuse_pickles(folder):
    """Refuses ``folder`` if it or a folder in it holds a ``*.pkl`` (named)."""
    folder = Path(folder)
    for path in sorted(folder.rglob("*.pkl")) if folder.is_dir() else ():
        raise OutputError(f"{path}: a pickle in a results folder; drake_car never loads one "
                          "(loading it could run code): remove it")


def rerun_note(scene_path, child=None):
    """For a run's saved scene (``scene_path``, run.json beside it) naming files relative to the
    folder the run was made in (run.json's ``provenance.working_folder``) that this working
    folder lacks: "; ..." saying where to rerun it from; else ""."""
    scene_path = Path(scene_path)
    try:
        made_in = json.loads((scene_path.parent / "run.json").read_text())[
            "provenance"]["working_folder"]
        raw = stated(scene_path, child)
    except (OSError, ValueError, KeyError, TypeError, SceneError):
        return ""
    if not isinstance(made_in, str) or Path(made_in) == Path.cwd():
        return ""
    tyres = raw.get("tyres")
    names = [raw.get("car_file"), tyres.get("tir_file") if isinstance(tyres, dict) else None]
    names = [n for n in names if isinstance(n, str) and not Path(n).is_absolute()]
    missing = [n for n in names if not _found(n) and (Path(made_in) / n).is_file()]
    if not missing:
        return ""
    return (f"; {scene_path} was run in {made_in}, where its {', '.join(missing)} are: rerun "
            f"it from there (cd {made_in})")


def _found(name):
    try:
        return data_path(name).exists()
    except DataFileError:
        return True
