"""A sweep's scenes: every entry of a scenes file (or FILE:ENTRY), a YAML text laid over each,
then each point of a grid of scene keys and their values (their product); all checked before
anything runs, the product's size announced or refused first."""

import itertools
import math
import sys

from pydrake.common.yaml import yaml_dump, yaml_load

from drake_car.law.checks import one_line
from drake_car.scene.load import SceneError, load_scene, load_scene_file, parse_scene_option
from drake_car.sim.simulate import estimate_wall_s

# A --grid product's size, checked before it is expanded: announced (with its estimate) past
# GRID_ANNOUNCE_SCENES, refused past GRID_MAX_SCENES unless --large. Expanding costs about
# GRID_SCENE_S and GRID_SCENE_BYTES a scene [EST: 28 ms and 15 kB (peak RSS growth) a scene,
# measured for a 100-scene grid of paper_study a_1 on a loaded 2-core machine; a review found
# ~7 ms a scene, 10^6 scenes in ~2 h].
GRID_ANNOUNCE_SCENES = 1_000
GRID_MAX_SCENES = 20_000
GRID_SCENE_S, GRID_SCENE_BYTES = 0.03, 15e3


def check_grid_size(path, bases, scene_text, grid, *, large=False):
    """Refuses (SceneError) a product of more than GRID_MAX_SCENES scenes unless ``large``,
    and announces one of more than GRID_ANNOUNCE_SCENES on stderr, each with an estimate of
    the time and memory to expand it and of its runs' wall time."""
    sizes = [len(values) for _, values in grid]
    n = len(bases) * math.prod(sizes)
    if n <= GRID_ANNOUNCE_SCENES:
        return
    runs_s = n * estimate_wall_s(load_scene(path, child=bases[0], scene_text=scene_text or None))
    what = (f"--grid: {n} scenes ({' x '.join(map(str, sizes))}"
            + (f" x {len(bases)} entries" if len(bases) > 1 else "") + f"): about "
            f"{_duration(n * GRID_SCENE_S)} and {n * GRID_SCENE_BYTES / 1e9:.2g} GB to expand, "
            f"then about {_duration(runs_s)} of runs (one worker) [EST]")
    if n > GRID_MAX_SCENES and not large:
        raise SceneError(f"{what}: over the limit of {GRID_MAX_SCENES} scenes; give fewer "
                         "values, or --large to go on")
    print(f"{what}; going on", file=sys.stderr)


def _duration(seconds):
    return (f"{seconds:.0f} s" if seconds < 120 else f"{seconds / 60:.0f} min"
            if seconds < 7200 else f"{seconds / 3600:.0f} h")


def build_scenes(scenes_option, scene_text, grid, *, large=False):
    """name -> Scene: every entry of the scenes file (or FILE:ENTRY), ``scene_text`` laid over
    each, then each point of ``grid`` ([(key, [value, ...])], their product); all checked.
    ``large``: go on with a product over GRID_MAX_SCENES (``check_grid_size``)."""
    path, child = parse_scene_option(scenes_option)
    if not grid and child is None:
        return load_scene_file(path, scene_text or None)
    if not grid:
        return {child: load_scene(path, child=child, scene_text=scene_text or None)}
    bases = [child] if child is not None else list(load_scene_file(path))
    check_grid_size(path, bases, scene_text, grid, large=large)
    scenes = {}
    for point in itertools.product(*[[(key, v) for v in values] for key, values in grid]):
        text = overlay(scene_text, point)
        for base in bases:
            name = f"{base}[{','.join(f'{k}={v}' for k, v in point)}]"
            try:
                scenes[name] = load_scene(path, child=base, scene_text=text)
            except SceneError as e:
                raise SceneError(f"scene {name}: {e}") from None
    return scenes


def overlay(scene_text, point):
    """YAML text: ``scene_text`` with each (dotted key, YAML value) of ``point`` laid in."""
    try:
        data = yaml_load(data=scene_text) if scene_text.strip() else {}
    except Exception as e:
        raise SceneError(f"--scene_text {scene_text!r}: not YAML: {one_line(e)}") from None
    if not isinstance(data, dict):
        raise SceneError(f"--scene_text {scene_text!r}: must be a mapping of scene keys")
    for key, value in point:
        node, parts = data, key.split(".")
        for i, part in enumerate(parts):
            here = ".".join(parts[:i + 1])
            last = i == len(parts) - 1
            if part in node and (last or not isinstance(node[part], dict)):
                raise SceneError(f"--grid {key}: --scene_text sets {here} too; give it in one "
                                 "of them")
            if last:
                node[part] = yaml_load(data=f"value: {value}")["value"]
            else:
                node = node.setdefault(part, {})
    return yaml_dump(data)
