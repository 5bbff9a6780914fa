"""A study's scenes file: what ``--scene`` means for ``drake-car-paper`` and
``drake-car-handling`` (every entry one of the study's runs), where for the ride, design and
strut-rig commands it means your car (FILE[:ENTRY] laid over the study's base scene). What a user
of the others gives here, one scene (FILE:ENTRY) or a file that holds only a car (no entry states
a manoeuvre), is refused before any work, in one line that says what this ``--scene`` is and how
to give that car instead: ``--scene_text`` with the entry's own car keys, laid over every run."""

import json
import math
import re

from drake_car.law.checks import excerpt
from drake_car.scene.load import load_scene_file, parse_scene_option, scene_entries, stated
from drake_car.scene.raw import SceneError

# The keys that say which car runs (what --scene_text lays over every run of a study).
CAR_KEYS = ("car_file", "car", "tyres")
# Top-level keys of every car file (``model.hard_points.HardPointCar``).
CAR_FILE_KEYS = ("mass", "wheelbase_m", "front", "rear")
# A YAML string written bare: a path or a name, not a word YAML reads as something else.
_BARE = re.compile(r"^[A-Za-z_./][A-Za-z0-9_./+-]*$")
_WORDS = {"true", "false", "yes", "no", "on", "off", "null", "y", "n"}


def load_study_file(option, scene_text, *, command, holds):
    """name -> Scene of the study's scenes file ``option`` (the ``--scene`` text), each with
    ``scene_text`` on top. ``command``: the console script; ``holds``: what its scenes file
    holds (for the refusal). A FILE:ENTRY of an existing FILE, or a file whose entries state no
    manoeuvre, is a SceneError naming --scene, what it is for and the --scene_text to give."""
    path, child = parse_scene_option(option)
    if child is None or not path.is_file():
        path, child = option, None  # a missing file: its loader says so
    what = f"{command}'s --scene is {holds}"
    if child is not None:
        raise SceneError(f"--scene {option}: {what}, not one scene (FILE:ENTRY); to run it on "
                         f"the car of {option}, lay it over every run: "
                         f"{suggestion(stated(path, child))}")
    entries = scene_entries(path)
    if set(CAR_FILE_KEYS) <= set(entries):
        raise SceneError(f"--scene {option}: a car file (its keys {', '.join(CAR_FILE_KEYS)}, "
                         f"...), not scenes; {what}; to run it on that car, lay it over every "
                         f"run: {suggestion({'car_file': str(option)})}")
    raws = [stated(path, entry) for entry in entries]
    if not any("manoeuvre" in raw for raw in raws):
        car = raws[0] if len(raws) == 1 else {}
        raise SceneError(f"--scene {option}: no entry states a manoeuvre (it holds "
                         f"{excerpt(', '.join(entries))}: a car?); {what}; to run it on "
                         f"{'that' if suggestion(car) != suggestion({}) else 'a'} car, lay it "
                         f"over every run: {suggestion(car)}")
    return load_scene_file(path, scene_text)


def suggestion(raw):
    """``--scene_text '...'`` of the car keys (CAR_KEYS) a scene's raw YAML states, or of
    placeholders when it states none."""
    keys = {k: raw[k] for k in CAR_KEYS if k in raw}
    text = flow_yaml(keys) if keys else "{car_file: FILE, tyres: !MagicFormula {tir_file: FILE}}"
    return f"--scene_text '{text}'" if "'" not in text else f"--scene_text {json.dumps(text)}"


def flow_yaml(value):
    """Raw YAML (``yaml_load``'s: a tag as ``_tag``) as one line of flow YAML."""
    if isinstance(value, dict):
        body = "{" + ", ".join(f"{k}: {flow_yaml(v)}" for k, v in value.items()
                               if k != "_tag") + "}"
        return f"{value['_tag']} {body}" if "_tag" in value else body
    if isinstance(value, list):
        return "[" + ", ".join(flow_yaml(v) for v in value) + "]"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float) and not math.isfinite(value):
        return ".nan" if math.isnan(value) else ".inf" if value > 0 else "-.inf"
    if value is None:
        return "null"
    if isinstance(value, str):
        bare = _BARE.match(value) and value.lower() not in _WORDS and value[0] != "."
        return value if bare else json.dumps(value)
    if isinstance(value, float):  # YAML 1.1 reads 1e-05 as a string: a dot in the mantissa
        text = repr(value)
        mantissa, e, exponent = text.partition("e")
        return (mantissa if "." in mantissa else mantissa + ".0") + e + exponent
    return repr(value)
