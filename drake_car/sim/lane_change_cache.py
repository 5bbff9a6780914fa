"""Where a lane change's rack calibration is found again (``sim.lane_change_calibration``):

1. **shipped**: the package's calibration of the shipped Escort
   (``drake_car/scene/lane_change_profile.json``), used when the content of the inputs it
   records (``inputs.content_sha256``) is the scene's: its profile is what every shipped scene
   has run since it was made, so the Escort's histories stay what they were;
2. **on disk**: an entry named by the SHA-256 of the inputs' content and of drake_car's code
   and versions (``sim.equilibrium_cache.code_fingerprint``: an edit to the code calibrates
   again), in the cache folder beside the equilibria's (``$DRAKE_CAR_CACHE_DIR`` or the
   platform's cache folder, + ``drake_car/lane_change``; ``DRAKE_CAR_CACHE_DIR=off``: none),
   written atomically, read back only whole (its own key, finite numbers), else ignored;
3. in this process: what was found or calibrated, by content (a study's six runs share one).

The inputs' content (``content_sha256``) is what the calibration scene holds of the scene that
asked (``sim.lane_change_calibration.calibration_scene``), as YAML: its car, tyres (the tyre
file named by its bytes' SHA-256 instead of its path: the same file anywhere is the same input,
an edited file under the same name is another), road, drive, the timeline to the end of phase
III and the shift asked (not the car's seat point, which only measures); not the sections the
calibration scene sets alike for every car (the step, the simulator, the logging: Drake's own
configs dump differently in other versions).
Clearing: ``python -m drake_car.sim.lane_change_cache --clear`` (or delete the folder).
"""

import dataclasses
import functools
import hashlib
import importlib.resources
import json
import math

from pydrake.common.yaml import yaml_dump_typed

from drake_car.law.tyre.tir import read_tir_bytes
from drake_car.model.loading import tir_path
from drake_car.model.seat import ESCORT_SEAT_POINT_M
from drake_car.sim import equilibrium_cache

FORMAT = 1  # bump when an entry's layout changes
SHIPPED = "lane_change_profile.json"
_memory = {}


def shipped_path():
    return importlib.resources.files("drake_car.scene").joinpath(SHIPPED)


def cache_folder():
    root = equilibrium_cache.cache_root()
    return None if root is None else root / "lane_change"


def content_sha256(calibration_scene):
    """The SHA-256 of what a calibration depends on (see the module)."""
    scene = calibration_scene
    tyres = scene.tyres
    if hasattr(tyres, "tir_file"):
        tir = hashlib.sha256(read_tir_bytes(tir_path(tyres.tir_file))).hexdigest()
        tyres = dataclasses.replace(tyres, tir_file=f"sha256:{tir}")
    # the seat point only measures (the ride's comfort): a moved seat is the same calibration
    car = dataclasses.replace(scene.car, seat_point_m=list(ESCORT_SEAT_POINT_M))
    m = scene.manoeuvre
    t = m.timeline
    text = f"lane change calibration {FORMAT}\n"
    for name, value in (("car", car), ("tyres", tyres), ("road", scene.road),
                        ("drive", scene.drive)):
        text += f"{name}: !{type(value).__name__}\n{yaml_dump_typed(value)}\n"
    text += (f"timeline: settle_s {t.settle_s!r}, speed_up_s {t.speed_up_s!r}, straight_s "
             f"{t.straight_s!r}, steer_s {t.steer_s!r}, speed_kph {t.speed_kph!r}\n"
             f"shift_m {m.shift_m!r}\n")
    return hashlib.sha256(text.encode()).hexdigest()


@functools.lru_cache(maxsize=1)
def shipped():
    """The shipped calibration's JSON (a dict)."""
    return json.loads(shipped_path().read_text())


def _entry_key(content):
    return hashlib.sha256(f"{equilibrium_cache.code_fingerprint()}\n{content}".encode()
                          ).hexdigest()


def find(content):
    """The calibration of inputs ``content`` (``content_sha256``): a dict with "profile"
    {"amplitude_m", "second_lobe"}, "residual", "source" (where it was found) ..., or None."""
    if content in _memory:
        return _memory[content]
    data = shipped()
    if data.get("inputs", {}).get("content_sha256") == content:
        found = {"profile": data["profile"], "residual": data.get("residual"),
                 "source": f"the shipped Escort's calibration (drake_car/scene/{SHIPPED}), "
                           "whose recorded inputs are this car's",
                 "cost": data.get("cost"), "content_sha256": content}
        _memory[content] = found
        return found
    folder = cache_folder()
    if folder is None:
        return None
    key = _entry_key(content)
    try:
        entry = json.loads((folder / f"{key}.json").read_text())
        profile = entry["profile"]
        whole = (entry.get("key") == key and entry.get("content_sha256") == content
                 and all(isinstance(profile[k], float) and math.isfinite(profile[k])
                         for k in ("amplitude_m", "second_lobe")))
    except (OSError, ValueError, TypeError, KeyError, AttributeError):
        return None
    if not whole:
        return None
    found = entry | {"source": f"found in the calibration cache ({folder / (key + '.json')})"}
    _memory[content] = found
    return found


def store(content, calibration: dict):
    """Keeps ``calibration`` ({"profile", "residual", "iterations", "cost", ...}) for inputs
    ``content``: in this process, and on disk when the cache is on."""
    _memory[content] = calibration | {"content_sha256": content}
    folder = cache_folder()
    if folder is None:
        return
    key = _entry_key(content)
    equilibrium_cache.write_entry(folder, key, json.dumps(
        {"key": key, "content_sha256": content} | calibration, indent=1))


def clear():
    """Deletes every entry on disk (and forgets this process's); returns how many."""
    _memory.clear()
    return equilibrium_cache.clear_folder(cache_folder())

