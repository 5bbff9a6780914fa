"""Loading, checking, saving and naming scenes: the one validation path of every entry point.

Layering: a file (a named top-level entry of it: each entry is a scene; entries starting with
"_" are templates for YAML merge keys), then a ``scene_text`` YAML string on top. Before Drake's
``yaml_load_typed`` builds the dataclasses, the raw YAML is walked against the schema so that a
wrong key or value is reported with its whole key path; after it, every section's ``check()``
and the cross-checks below run. Every message names where (file and entry, or --scene_text),
the key path, the value and what is allowed, as one line (``SceneError``).
"""

import dataclasses
import hashlib
from pathlib import Path

from pydrake.common.yaml import yaml_dump_typed, yaml_load

from drake_car.data import resource
from drake_car.scene.borrowed import say_borrowed
from drake_car.law.checks import ParameterError, checked, excerpt, one_line
from drake_car.scene.car_file import derived_note, with_car_file
from drake_car.scene.car_limits import check_car
from drake_car.scene.limits import check_limits, check_plant
from drake_car.scene.guard import (
    PLAIN_NAME, announce_large_road, check_entry_name, check_yaml, read_yaml_file)
from drake_car.scene.raw import SceneError, check_raw as _check_raw, guarded as _guarded
from drake_car.scene.raw import typed as _typed
from drake_car.scene.launch import resolve_launch
from drake_car.scene.manoeuvres import MAX_DURATION_S, Settle
from drake_car.scene.scene import HandsOff, Scene
from drake_car.scene.vertical import resolve_vertical

# Every channel group a scene can log.
CHANNEL_GROUPS = ("chassis", "steering", "struts", "tyres", "friction", "energy", "top_mounts",
                  "ride")
# Groups logged only when a scene lists them (not in the default "all it has").
OPT_IN_CHANNELS = ("ride",)
# A run's size: at ~0.5 ms of wall time per step (the paper's hardest run at 1 ms on this
# project's 2-core machine, benchmarks/step_cost.py), 5e6 steps are about 40 minutes.
WALL_PER_STEP_S = 5e-4
MAX_STEPS = 5e6


def _duration(seconds):
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def load_scene(path=None, *, child=None, scene_text=None, base=None,
               text_origin="--scene_text", runs=True) -> Scene:
    """A scene from ``path`` (its top-level entry ``child``; a file with one entry needs none),
    with ``scene_text`` laid on top; checked. ``base``: a Scene to start from instead of the
    defaults (the file's values, then the text's, laid over it: a study's base scene under a
    user's scene file). ``text_origin``: where ``scene_text`` came from, for errors. ``runs``:
    False where only the scene's car (and friction law) is used, not the scene as it stands
    (a rig, the kinematics): its drive and tyres never run, so their borrowed values are not
    said (``scene.borrowed.say_borrowed``)."""
    scene = Scene() if base is None else base
    where = "scene defaults"
    layers = []  # (where, raw YAML, typed-load arguments)
    if path is not None:
        path = Path(path)
        text, data = _read_file(path)
        entries = _entries(path, data)
        if child is None:
            if len(entries) != 1:
                raise SceneError(f"{path}: holds the scenes {excerpt(entries)}; name one "
                                 f"(FILE:ENTRY)")
            child = entries[0]
        elif child not in entries:
            raise SceneError(f"{path}: no scene {excerpt(child)}; it holds "
                             f"{', '.join(entries)[:300]}")
        where = f"{path} [{child}]"
        _check_raw(data[child], Scene, where, "")
        _check_own_name(data[child], where)
        layers.append((where, data[child], {"data": text, "child_name": child}))
    if scene_text:
        where = f"{text_origin} {excerpt(scene_text)}"
        _guarded(check_yaml, scene_text, where)
        try:
            raw = yaml_load(data=scene_text)
        except Exception as e:
            raise SceneError(f"{where}: not YAML: {one_line(e)}") from None
        if raw is None:
            raw = {}
        _check_raw(raw, Scene, where, "")
        _check_own_name(raw, where)
        layers.append((where, raw, {"data": scene_text}))
    # A car file lies beneath every layer's car: values (scene.car_file).
    named = [(w, raw["car_file"]) for w, raw, _ in layers
             if isinstance(raw, dict) and "car_file" in raw]
    if named and named[-1][1] != scene.car_file:
        try:
            scene = with_car_file(scene, named[-1][1])
        except SceneError as e:
            raise SceneError(f"{named[-1][0]}: {e}") from None
    for where, _, arguments in layers:
        scene = _typed(where, schema=Scene, defaults=scene, **arguments)
    return check_scene(scene, where, runs=runs)


def load_scene_file(path, scene_text=None):
    """Every scene of a file (name -> Scene), each with ``scene_text`` on top."""
    return {child: load_scene(path, child=child, scene_text=scene_text)
            for child in _read_entries(Path(path))}


def scene_entries(path):
    """The names of a scene file's entries (its scenes; templates, "_..." entries, left out)."""
    return _read_entries(Path(path))


def load_scene_text(text, where):
    """The scene of a scene file's text holding one entry (``dump_scene_file``'s), checked."""
    return check_scene(parse_scene_text(text, where), where)


def parse_scene_text(text, where):
    """The scene of a scene file's text holding one entry, not checked: for a text whose
    checksum says it is what a checked scene was saved as (a sweep's run read back)."""
    _guarded(check_yaml, text, where)
    try:
        data = yaml_load(data=text)
    except Exception as e:
        raise SceneError(f"{where}: not a YAML scene file: {one_line(e)}") from None
    if not isinstance(data, dict) or len(data) != 1:
        raise SceneError(f"{where}: must hold one scene")
    (child,) = data
    _check_raw(data[child], Scene, where, "")
    return _typed(where, schema=Scene, data=text, child_name=child)


def load_section(schema, key, text, where):
    """The section ``key`` of a scene (e.g. ``scene.Friction``, "friction") from its YAML
    ``text``, checked by its own ``check()`` alone: for a rig that takes a scene's section but
    no car."""
    _guarded(check_yaml, text, where)
    try:
        raw = yaml_load(data=f"value: {text}")["value"]
    except Exception as e:
        raise SceneError(f"{where}: not YAML: {one_line(e)}") from None
    if raw is None:
        text = "{}"
    _check_raw({} if raw is None else raw, schema, where, key)
    section = _typed(where, schema=schema, data=f"value: {text}", child_name="value")
    try:
        return checked(section, key)
    except ParameterError as e:
        raise SceneError(f"{where}: {e}") from None


def stated(path=None, child=None, scene_text=None):
    """The raw YAML a user stated (tags as ``_tag``, merge keys applied): of the scene file
    ``path``'s entry ``child`` (its one entry if None), else of ``scene_text``; {} for none. For
    a study that sets some of a scene's values and must refuse, not replace, a stated one."""
    if path is not None:
        data = _read_file(Path(path))[1]
        entries = _entries(path, data)
        raw = data.get(child if child is not None else entries[0])
    else:
        raw = yaml_load(data=scene_text) if scene_text else None
    return raw if isinstance(raw, dict) else {}


def parse_scene_option(text):
    """``FILE`` or ``FILE:ENTRY`` -> (path, entry or None)."""
    if ":" in text and not Path(text).exists():
        path, child = text.rsplit(":", 1)
        return Path(path), child
    return Path(text), None


def dump_scene(scene: Scene) -> str:
    """The scene as YAML: every value, defaults included (what ran)."""
    return yaml_dump_typed(scene)


def dump_scene_file(scene: Scene, command="drake-car-run") -> str:
    """A scene file holding ``scene`` as its one entry ("scene"): what a run saves beside its
    results (``command``: the command that reruns it); ``load_scene`` reads it back to the
    same scene."""
    body = "\n".join("  " + line if line else line for line in dump_scene(scene).splitlines())
    return f"# The scene as it ran (drake_car). Rerun: {command} --scene THIS\n" \
           f"scene:\n{body}\n"


def scene_hash(scene: Scene) -> str:
    """The scene's content hash (its name left out): equal scenes make equal runs."""
    return hashlib.sha256(dump_scene(dataclasses.replace(scene, name="")).encode()).hexdigest()[:16]


def shipped_scenes():
    """(path, entry) of every scene shipped in the package's ``scenes/`` folder."""
    found = []
    folder = resource("scenes")
    for item in sorted(folder.iterdir(), key=lambda p: p.name):
        if item.name.endswith(".yaml"):
            path = Path(str(item))
            found += [(path, child) for child in _read_entries(path)]
    return found


def _check_own_name(raw, where):
    """A scene's own ``name:`` from outside (a file's entry, --scene_text) names folders and
    files: a plain name only (the package's own scenes may name themselves freely)."""
    if not isinstance(raw, dict) or "name" not in raw:
        return
    name = raw["name"]
    if not isinstance(name, str) or not PLAIN_NAME.match(name) or ".." in name:
        raise SceneError(f"{where}: name = {excerpt(name)} is not a plain name (letters, digits, "
                         "_ . + = -; not starting with . or -; at most 100 characters); it "
                         "names folders and files")


def check_scene(scene: Scene, where="scene", runs=True) -> Scene:
    """Every section's check, the cross-checks and the limits (``scene.limits``): the one place
    a scene's values are checked; raises SceneError naming the key. The values derived from
    others are set here, so the saved scene shows them: the tyres' vertical data from their
    file (``scene.vertical``), a launch left out (``scene.launch``)."""
    try:
        for section in ("car", "friction", "tyres", "road", "manoeuvre", "drive", "simulator",
                        "logging", "visualization"):
            value = getattr(scene, section)
            if value is not None:
                checked(value, section)
        try:
            check_car(scene.car)
        except ParameterError as e:
            raise e.within("car") from None
        check_plant(scene.plant)
        _check_cross(scene)
        scene = resolve_vertical(scene)
        check_limits(scene)
        scene = resolve_launch(scene)
    except ParameterError as e:
        raise SceneError(f"{where}: {e}{derived_note(scene, e.key)}") from None
    announce_large_road(scene, where)
    if runs:  # a borrowed value is said where it runs
        say_borrowed(scene, where)
    return scene



def hands_off_release_s(scene: Scene):
    """When a !HandsOff scene lets go of the rack (s)."""
    release = scene.steering.release_s
    return scene.manoeuvre.timeline.boundaries()[2] if release is None else release


def available_channels(scene: Scene):
    """The channel groups this scene has."""
    groups = ["chassis", "steering", "struts", "tyres", "energy"]
    if scene.friction is not None:
        groups.append("friction")
    if scene.car.front.top_mount_stiffness_Npm > 0:
        groups.append("top_mounts")
    return groups


def channels_of(scene: Scene):
    """The channel groups the scene logs (``logging.channels``, or all it has)."""
    if scene.logging.channels is None:
        return available_channels(scene)
    return list(scene.logging.channels)


# -- checks ---------------------------------------------------------------------------------

def _check_cross(scene: Scene):
    m, sim = scene.manoeuvre, scene.simulator
    end = scene.end_time_s
    steps = end / scene.time_step_s
    estimate = f"{steps:.3g} steps, about {_duration(steps * WALL_PER_STEP_S)} of wall time here"
    if sim.end_time_s is not None and sim.end_time_s > MAX_DURATION_S:
        raise ParameterError("simulator.end_time_s", sim.end_time_s,
                             f"must be <= {MAX_DURATION_S:g} s of simulated time ({estimate})")
    if steps > MAX_STEPS:
        raise ParameterError("plant.time_step", scene.time_step_s,
                             f"makes the {end:g} s run {estimate}; runs are limited to "
                             f"{MAX_STEPS:.0e} steps")
    if sim.end_time_s is not None and sim.end_time_s > m.end_s:
        raise ParameterError("simulator.end_time_s", sim.end_time_s,
                             f"must be <= the manoeuvre's {m.end_s:g} s (lengthen the "
                             "manoeuvre instead)")
    if scene.logging.record_period_s > end:
        raise ParameterError("logging.record_period_s", scene.logging.record_period_s,
                             f"must be <= the run's {end:g} s")
    if sim.resolve_events is not None and scene.friction is None:
        raise ParameterError("simulator.resolve_events", "set", "has nothing to resolve: the "
                             "scene has no strut friction (friction: null); leave it out")
    if sim.resolve_events is not None and sim.resolve_events.finest_step_s > (
            scene.time_step_s / 2 * (1 + 1e-9)):
        raise ParameterError("simulator.resolve_events.finest_step_s",
                             sim.resolve_events.finest_step_s,
                             f"must be <= half of plant.time_step = {scene.time_step_s:g} s")
    if sim.monitor_period_s < scene.time_step_s:
        raise ParameterError("simulator.monitor_period_s", sim.monitor_period_s,
                             f"must be >= plant.time_step = {scene.time_step_s:g} s")
    steering = scene.steering
    if isinstance(steering, HandsOff):
        if not m.drives:
            raise ParameterError("steering", "HandsOff", "needs a driving manoeuvre")
        release = hands_off_release_s(scene)
        if not 0 < release < end:
            raise ParameterError("steering.release_s", release,
                                 f"must lie inside the run (0, {end:g}) s")
    if isinstance(m, Settle) and scene.drive != Scene().drive:
        raise ParameterError("drive", type(scene.drive).__name__,
                             "has no effect on a Settle manoeuvre (no drive); leave it out")
    if scene.logging.channels is not None:
        have = available_channels(scene) + list(OPT_IN_CHANNELS)
        for i, group in enumerate(scene.logging.channels):
            if group not in CHANNEL_GROUPS:
                raise ParameterError(f"logging.channels[{i}]", group,
                                     f"must be one of {', '.join(CHANNEL_GROUPS)}")
            if group not in have:
                raise ParameterError(f"logging.channels[{i}]", group,
                                     f"is not in this scene (it has {', '.join(have)})")


# -- raw YAML against the schema ------------------------------------------------------------

def _read_file(path: Path):
    """(text, parsed YAML) of a scene file, bounded (``scene.guard``) before parsing."""
    text = _guarded(read_yaml_file, path)
    try:
        data = yaml_load(data=text)
    except Exception as e:
        raise SceneError(f"{path}: not a YAML scene file: {one_line(e)}") from None
    return text, data


def _entries(path, data):
    if not isinstance(data, dict) or not data:
        raise SceneError(f"{path}: must map scene names to scenes")
    names = [name for name in data if not str(name).startswith("_")]
    for name in names:
        _guarded(check_entry_name, name, str(path))
    return names


def _read_entries(path: Path):
    return _entries(path, _read_file(path)[1])
