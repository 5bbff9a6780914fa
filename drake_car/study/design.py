"""The design study's pure parts: the study's spec (a typed YAML file: the base scene, the
factors with their ranges and reasons, the maps, the sampling sizes), scenes from factor values,
and the outcomes of a run (the lasting change of the front load split, the share of time each
rod is stuck, the rods at places a and b, the rack-force imbalance after the manoeuvre, the pull
when the driver lets go).

Where friction decides anything here is the split of the front wheel loads after a manoeuvre:
a strut that sticks at a different extension left and right leaves the coil springs loaded
differently, so the car carries its weight unequally on the front wheels (the paper's claim 3),
the tie rods pull unequally on the rack, and a car whose driver lets go of the wheel turns.
"""

import dataclasses
import math

import numpy as np
from pydrake.common.yaml import yaml_load_typed

from drake_car.scene.load import SceneError, check_scene, hands_off_release_s
from drake_car.scene.scene import HandsOff, Scene
from drake_car.study.paper import place_values


@dataclasses.dataclass
class Factor:
    """A scene value the study varies: ``key`` its path in the scene (``friction.law.mu_s``),
    sampled in [low, high] (on a log scale with ``log``); ``paper`` the value of the paper's
    car, marked on the maps; ``reason`` where the range comes from."""

    key: str = ""
    label: str = ""
    low: float = 0.0
    high: float = 1.0
    paper: float = 0.0
    log: bool = False
    reason: str = ""


@dataclasses.dataclass
class MapSpec:
    """A 2-D slice: ``points`` × ``points`` runs over two factors, the others at ``paper``."""

    x: str = ""
    y: str = ""
    points: int = 5


@dataclasses.dataclass
class MonteCarlo:
    """Jam states: ``samples`` runs with random road unevenness before the manoeuvre (heights
    uniform in ±``roughness_m`` every ``spacing_m`` up to ``length_m``, seeded), the driver
    letting go after it."""

    samples: int = 200
    roughness_m: float = 0.005
    spacing_m: float = 1.0
    length_m: float = 60.0
    seed: int = 2026


@dataclasses.dataclass
class Mitigation:
    """A change a designer can make, as YAML laid over each Monte-Carlo scene."""

    name: str = ""
    scene_text: str = ""
    reason: str = ""


@dataclasses.dataclass
class DesignStudy:
    base: Scene = dataclasses.field(default_factory=Scene)
    factors: list[Factor] = dataclasses.field(default_factory=list)
    mu_d_ratio: float = 0.75  # μd = ratio · μs wherever μs varies (the paper's 0.15/0.2, 0.3/0.4)
    maps: list[MapSpec] = dataclasses.field(default_factory=list)
    sobol_base_samples: int = 64
    monte_carlo: MonteCarlo = dataclasses.field(default_factory=MonteCarlo)
    mitigations: list[Mitigation] = dataclasses.field(default_factory=list)
    mitigation_samples: int = 40
    noise_samples: int = 16  # runs repeated at half the step
    split_threshold: float = 0.01  # the lasting split that matters, of the static corner load
    pull_distance_m: float = 50.0  # the heading drift is taken over this distance
    # [EST] the pull a driver notices: 0.5 deg of heading over the pull distance (a lateral
    # drift of ~0.2 m in 50 m).
    pull_threshold_deg: float = 0.5


def load_study(path, child=None) -> DesignStudy:
    try:
        study = yaml_load_typed(schema=DesignStudy, filename=str(path), child_name=child,
                                defaults=DesignStudy())
    except Exception as e:
        raise SceneError(f"{path}: {' '.join(str(e).split())}") from None
    check_scene(study.base, f"{path}: base")
    for factor in study.factors:
        with_value(study, {factor.key: factor.low})
        with_value(study, {factor.key: factor.high})
        if not factor.low < factor.high:
            raise SceneError(f"{path}: factor {factor.key}: low {factor.low} must be below high "
                             f"{factor.high}")
    return study


def paper_value(study, f: Factor):
    """The factor's value for the paper's car (``paper``; NaN: the base scene's value)."""
    if not math.isnan(f.paper):
        return f.paper
    value = study.base
    for part in f.key.split("."):
        value = getattr(value, part)
    return float(value)


def factor(study, key) -> Factor:
    for f in study.factors:
        if f.key == key:
            return f
    raise SceneError(f"the study has no factor {key!r} (it has "
                     f"{', '.join(f.key for f in study.factors)})")


def _set(obj, path, value):
    head, _, rest = path.partition(".")
    if not dataclasses.is_dataclass(obj) or head not in {f.name for f in dataclasses.fields(obj)}:
        raise SceneError(f"factor key {path!r}: no field {head!r} in {type(obj).__name__}")
    if not rest:
        return dataclasses.replace(obj, **{head: value})
    return dataclasses.replace(obj, **{head: _set(getattr(obj, head), rest, value)})


def with_value(study: DesignStudy, values: dict, *, name=None, base=None) -> Scene:
    """The base scene with factor values set (key path -> value); μd follows μs by the
    study's ratio. Checked like any scene."""
    scene = base or study.base
    for key, value in values.items():
        if key == "friction.law.mu_s":
            if scene.friction is None:
                raise SceneError("factor friction.law.mu_s: the base scene has no friction")
            law = dataclasses.replace(scene.friction.law, mu_s=float(value),
                                      mu_d=study.mu_d_ratio * float(value))
            scene = dataclasses.replace(scene, friction=dataclasses.replace(scene.friction,
                                                                            law=law))
        else:
            scene = _set(scene, key, float(value))
    if name is not None:
        scene = dataclasses.replace(scene, name=name)
    return check_scene(scene, f"design study values {values}")


def rough_road(study: DesignStudy, sample: int):
    """A seeded random road: (x_m, z_m) lists, heights uniform in ±roughness up to
    ``length_m``, flat beyond (so the manoeuvre itself is on a flat road)."""
    mc = study.monte_carlo
    rng = np.random.default_rng([mc.seed, sample])
    x = np.arange(0.0, mc.length_m + 1e-9, mc.spacing_m)
    z = rng.uniform(-mc.roughness_m, mc.roughness_m, x.size)
    z[0] = z[-1] = 0.0
    x = np.concatenate([x, [mc.length_m + 10.0]])
    z = np.concatenate([z, [0.0]])
    return [float(v) for v in x], [float(v) for v in z]


# -- outcomes of a run ---------------------------------------------------------------------

OUTCOMES = ("split_change_N", "split_change_rel", "stuck_left", "stuck_right",
            "dd_left_a_m", "dd_left_b_m", "dd_right_a_m", "dd_right_b_m",
            "rack_force_change_N", "pull_deg", "pull_lateral_m")


def outcomes(history, scene: Scene, study: DesignStudy):
    """The study's outcomes of one run (OUTCOMES; NaN where a run cannot say: the pull needs
    !HandsOff)."""
    h = history
    timeline = scene.manoeuvre.timeline
    static = 0.5 * (h["Fz_fl_N"][0] + h["Fz_fr_N"][0])
    split = np.asarray(h["Fz_fl_N"]) - np.asarray(h["Fz_fr_N"])
    columns = dict(h, split_N=split)
    if isinstance(scene.steering, HandsOff):
        # Place b: the 0.5 s of straight running before the driver lets go (hands on).
        release = hands_off_release_s(scene)
        columns = {k: np.asarray(v)[h["t"] < release] if k != "phase" else v
                   for k, v in columns.items()}
    a, b = place_values(columns, timeline, "split_N")
    out = {"split_change_N": b - a, "split_change_rel": (b - a) / static}
    started = h["t"] >= timeline.settle_s
    for side in ("left", "right"):
        phase = h.get(f"friction_{side}_translation_phase")
        out[f"stuck_{side}"] = (float(np.mean(phase[started] == 0.0)) if phase is not None
                                else 0.0)
        d = np.asarray(columns[f"d_{side}_m"])
        columns[f"dd_{side}_m"] = d - d[0]
        out[f"dd_{side}_a_m"], out[f"dd_{side}_b_m"] = place_values(columns, timeline,
                                                                    f"dd_{side}_m")
    fa, fb = place_values(columns, timeline, "rack_force_N")
    out["rack_force_change_N"] = fb - fa
    out["pull_deg"] = out["pull_lateral_m"] = math.nan
    if isinstance(scene.steering, HandsOff):
        release = hands_off_release_s(scene)
        t, yaw, y = h["t"], h["yaw_rad"], h["y_m"]
        speed = float(np.interp(release, t, h["speed_mps"]))
        until = min(release + study.pull_distance_m / max(speed, 1e-3), t[-1])
        out["pull_deg"] = math.degrees(float(np.interp(until, t, yaw) - np.interp(release, t, yaw)))
        out["pull_lateral_m"] = float(np.interp(until, t, y) - np.interp(release, t, y))
    return {k: float(v) for k, v in out.items()}


def pull_span_s(scene: Scene, study: DesignStudy):
    """How long after letting go a run must last to measure the pull (s), at the cruising
    speed."""
    return study.pull_distance_m / scene.manoeuvre.timeline.speed_mps

