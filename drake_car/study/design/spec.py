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
import typing

import numpy as np
from pydrake.common.yaml import yaml_load_typed

from drake_car.law.road.profiles import SampledProfile
from drake_car.law.checks import one_line
from drake_car.scene.guard import read_yaml_file
from drake_car.scene.load import SceneError, check_scene, hands_off_release_s, load_scene
from drake_car.scene.manoeuvres import LaneChange, speed_profile
from drake_car.scene.scene import HandsOff, Scene
from drake_car.study.paper.claims import place_values


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
    """A 2-D slice: ``points`` × ``points`` runs over two factors, the others at the base
    scene's values (the study's car's)."""

    x: str = ""
    y: str = ""
    points: int = 5


@dataclasses.dataclass
class Line:
    """One factor at a time: scene key ``key`` at each of ``values``, the others at the base
    scene's, at each of the study's ``line_mu_s``, hands off."""

    key: str = ""
    label: str = ""
    values: list[float] = dataclasses.field(default_factory=list)
    reason: str = ""


@dataclasses.dataclass
class MonteCarlo:
    """Jam states: ``samples`` runs with random road unevenness before the manoeuvre, the
    driver letting go after it. The left and right tracks get independent heights, uniform in
    ±``roughness_m`` every ``spacing_m`` from ``start_m`` (the car at rest stands on flat road)
    to ``length_m`` (the rear wheels must leave it before place a: checked), seeded."""

    samples: int = 200
    roughness_m: float = 0.005
    spacing_m: float = 1.0
    start_m: float = 2.0
    length_m: float = 25.0
    seed: int = 2026


@dataclasses.dataclass
class Mitigation:
    """A change a designer can make, as YAML laid over each Monte-Carlo scene."""

    name: str = ""
    scene_text: str = ""
    reason: str = ""


PARTS = ("map", "line", "sobol", "mc", "mitigation")


@dataclasses.dataclass
class Accuracy:
    """Accuracy on demand for the jam cases: every run of ``parts`` whose μs is at least
    ``jam_mu_s`` resolves every slip of its struts locally, at halved steps down to
    ``finest_step_s`` (``--refine local``, ``study.design.resolved_runs``), or is repeated at
    half and a quarter of its step and halved further (down to ``finest_step_s``, within
    ``budget_s`` of wall) until its lasting split and its pull agree within their tolerances
    (``--refine global``, ``sweep.refine``). Where a dry strut jams, its lasting state takes
    one of two branches that the step decides (the paper's study: 5.0 or 6.7 % of the corner
    load). ``jam_mu_s`` [EST]: the paper's "very high" set 3 is μs 0.4, its "practically
    realistic" 0.2; runs below it are spoken for by the half-step noise sample (drawn from
    them). Sobol's sample is a part like the others (its 196 jam points cost 6-16 times their
    runs on the global route)."""

    jam_mu_s: float = 0.3
    parts: list[str] = dataclasses.field(
        default_factory=lambda: ["map", "line", "sobol", "mitigation"])
    # 0.1 % of the corner load: a tenth of the study's 1 % threshold, a seventeenth of the gap
    # between the two branches of a jammed strut's lasting split (5.0 or 6.7 %).
    split_tolerance: float = 1e-3
    # A tenth of the 0.5 deg pull threshold.
    pull_tolerance_deg: float = 0.05
    finest_step_s: float = 1.25e-4
    budget_s: typing.Optional[float] = None


@dataclasses.dataclass
class DesignStudy:
    base: Scene = dataclasses.field(default_factory=Scene)
    factors: list[Factor] = dataclasses.field(default_factory=list)
    mu_d_ratio: float = 0.75  # μd = ratio · μs wherever μs varies (the paper's 0.15/0.2, 0.3/0.4)
    maps: list[MapSpec] = dataclasses.field(default_factory=list)
    lines: list[Line] = dataclasses.field(default_factory=list)
    line_mu_s: list[float] = dataclasses.field(default_factory=lambda: [0.2, 0.4])
    sobol_base_samples: int = 64
    monte_carlo: MonteCarlo = dataclasses.field(default_factory=MonteCarlo)
    mitigations: list[Mitigation] = dataclasses.field(default_factory=list)
    mitigation_samples: int = 40
    # The μs the mitigations are compared at (μd by mu_d_ratio), over a baseline of their own
    # at it; None: the base scene's. A mitigation matters where the struts jam.
    mitigation_mu_s: typing.Optional[float] = None
    noise_samples: int = 16  # runs repeated at half the step
    split_threshold: float = 0.01  # the lasting split that matters, of the static corner load
    pull_distance_m: float = 50.0  # the heading drift is taken over this distance
    # [EST] the pull a driver notices: 0.5 deg of heading over the pull distance (a lateral
    # drift of ~0.2 m in 50 m).
    pull_threshold_deg: float = 0.5
    accuracy: Accuracy = dataclasses.field(default_factory=Accuracy)
    # The calibrated rack amplitude the spec's manoeuvre.amplitude_m values (its factor's range,
    # its lines) are stated for: on another car they are scaled by that car's own rack over this
    # (study.design.base_car.severity_scaled). None: run as given, in metres on every car.
    rack_reference_m: typing.Optional[float] = None


def load_study(path, child=None, scene_text=None, scene=None) -> DesignStudy:
    """The study at ``path`` (its entry ``child``) around the user's car: the scene file
    ``scene`` ((FILE, ENTRY or None): the values it states laid over the study's base scene)
    and ``scene_text`` (YAML, e.g. another tyre: ``"{tyres: !MagicFormula {tir_file:
    FILE}}"``) laid over that, so over every run's; checked: the base must change lanes (the
    study's runs do), every factor's range, line and mitigation must still make valid
    scenes."""
    text = read_yaml_file(path, "study file")  # a regular file, bounded, before Drake's parser
    try:
        study = yaml_load_typed(schema=DesignStudy, data=text, child_name=child,
                                defaults=DesignStudy())
    except Exception as e:
        raise SceneError(f"{path}: {one_line(e)}") from None
    if scene is not None:
        study = dataclasses.replace(study, base=load_scene(scene[0], child=scene[1],
                                                           base=study.base))
    if scene_text:
        study = dataclasses.replace(study, base=load_scene(scene_text=scene_text,
                                                           base=study.base))
    check_scene(study.base, f"{path}: base")
    if not isinstance(study.base.manoeuvre, LaneChange):
        raise SceneError(f"{path}: base: the design study's runs change lanes (the paper's "
                         "lane change, then hands off); its base scene's manoeuvre must be "
                         f"!LaneChange, not !{type(study.base.manoeuvre).__name__} from "
                         "--scene/--scene_text: give the car alone (a scene entry without a "
                         "manoeuvre, or --scene_text \"{car_file: FILE, tyres: ...}\") or a "
                         "!LaneChange")
    try:
        check_values(study)
    except SceneError as e:
        raise SceneError(f"{path}: {e}") from None
    _check_rough_road(study, path)
    _check_accuracy(study.accuracy, path, study.base.plant.time_step)
    ref = study.rack_reference_m
    if ref is not None and not (math.isfinite(ref) and 0 < ref <= 0.1):
        raise SceneError(f"{path}: rack_reference_m = {ref} must be a rack amplitude in (0, "
                         "0.1] m (or left out: the amplitudes run as given)")
    return study


def _check_accuracy(a: Accuracy, path, step_s):
    if not isinstance(a.parts, list) or len(set(a.parts)) != len(a.parts):
        raise SceneError(f"{path}: accuracy.parts = {a.parts!r} must be a list of distinct "
                         f"parts (of {', '.join(PARTS)})")
    unknown = [p for p in a.parts if p not in PARTS]
    if unknown:
        raise SceneError(f"{path}: accuracy.parts: {', '.join(map(repr, unknown))} not a part "
                         f"of the study (the parts: {', '.join(PARTS)})")
    for key in ("jam_mu_s", "split_tolerance", "pull_tolerance_deg", "finest_step_s"):
        value = getattr(a, key)
        if not (math.isfinite(value) and value > 0):
            raise SceneError(f"{path}: accuracy.{key} = {value} must be a positive number")
    if a.finest_step_s > step_s / 4 * (1 + 1e-9):
        raise SceneError(f"{path}: accuracy.finest_step_s = {a.finest_step_s:g} s must be at "
                         f"most a quarter of the base scene's step ({step_s:g} s): the first "
                         "round already runs every refined run at 1/2 and 1/4 of it")
    if a.budget_s is not None and not a.budget_s > 0:
        raise SceneError(f"{path}: accuracy.budget_s = {a.budget_s} must be positive (or "
                         "left out: no budget)")


def check_values(study):
    """Every factor's ends, every line's values, the mitigations' μs and scenes make valid
    scenes."""
    for factor in study.factors:
        with_value(study, {factor.key: factor.low})
        with_value(study, {factor.key: factor.high})
        if not factor.low < factor.high:
            raise SceneError(f"factor {factor.key}: low {factor.low} must be below high "
                             f"{factor.high}")
    for line in study.lines:
        if not line.values:
            raise SceneError(f"line {line.key}: values must not be empty")
        for value in line.values:
            for mu_s in study.line_mu_s:
                with_value(study, {line.key: value, "friction.law.mu_s": mu_s})
    if study.mitigation_mu_s is not None:
        with_value(study, {"friction.law.mu_s": study.mitigation_mu_s})
    for i, m in enumerate(study.mitigations):
        load_scene(scene_text=m.scene_text, base=study.base,
                   text_origin=f"mitigations[{i}] ({m.name}): scene_text")


def _check_rough_road(study, path):
    """The rough stretch must lie ahead of the car at rest and behind its rear wheels when
    place a begins (at the commanded speed; the car lags it, which only adds margin)."""
    mc, timeline = study.monte_carlo, study.base.manoeuvre.timeline
    if not 1.0 <= mc.start_m < mc.length_m:
        raise SceneError(f"{path}: monte_carlo.start_m = {mc.start_m} must be >= 1 m (the car "
                         f"at rest stands on flat road) and below length_m = {mc.length_m}")
    place_a = timeline.boundaries()[1] - 0.3
    _, front_at_place_a, _ = speed_profile(np.array([place_a]), timeline)
    rear = float(front_at_place_a[0]) - study.base.car.wheelbase_m
    if mc.length_m > rear:
        raise SceneError(f"{path}: monte_carlo.length_m = {mc.length_m} m: the rear wheels are "
                         f"only at {rear:.1f} m when place a begins ({place_a:.2f} s); the rough "
                         "stretch must end before")


def paper_value(study, f: Factor):
    """The factor's value for the paper's car (``paper``; NaN: the base scene's value where
    the base is the paper's car, else not known: NaN. A user's car on the base scene has
    its own values there, a launch and a rack adapted to it)."""
    if not math.isnan(f.paper) or not is_paper_car(study):
        return f.paper
    return value_of(study.base, f.key)


def is_paper_car(study):
    """Whether the study's base car is the shipped car on its shipped tyre (the paper's car as
    this project models it; the base's strut damping aside, which the study sets)."""
    from drake_car.study.car.describe import is_shipped_car, on_shipped_tyre
    return is_shipped_car(study.base.car) and on_shipped_tyre(study.base)


def car_value(study, f: Factor):
    """The factor's value for the study's car, the base scene's (the user's car from --scene
    or --scene_text, or the shipped one): where the maps draw their star."""
    return value_of(study.base, f.key)


def value_of(scene, key):
    """The value at a dotted key path of ``scene``."""
    value = scene
    for part in key.split("."):
        value = getattr(value, part)
    return float(value)


def factor(study, key) -> Factor:
    for f in study.factors:
        if f.key == key:
            return f
    raise SceneError(f"the study has no factor {key!r} (it has "
                     f"{', '.join(f.key for f in study.factors)})")


def _set(obj, path, value, key=None):
    head, _, rest = path.partition(".")
    if not dataclasses.is_dataclass(obj) or head not in {f.name for f in dataclasses.fields(obj)}:
        raise SceneError(f"factor key {(key or path)!r}: no field {head!r} in "
                         f"{type(obj).__name__}")
    if not rest:
        return dataclasses.replace(obj, **{head: value})
    return dataclasses.replace(obj, **{head: _set(getattr(obj, head), rest, value,
                                                  key or path)})


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


def rough_road(study: DesignStudy, sample: int) -> SampledProfile:
    """A seeded random road of two tracks: flat up to ``start_m``, heights uniform in
    ±roughness, independent left and right, up to ``length_m``, flat beyond (the manoeuvre
    itself is on a flat road)."""
    mc = study.monte_carlo
    rng = np.random.default_rng([mc.seed, sample])
    x = np.concatenate([[0.0], np.arange(mc.start_m, mc.length_m + 1e-9, mc.spacing_m),
                        [mc.length_m + 10.0]])
    tracks = rng.uniform(-mc.roughness_m, mc.roughness_m, (2, x.size))
    tracks[:, :2] = tracks[:, -2:] = 0.0
    return SampledProfile(x_m=[float(v) for v in x], z_m=[float(v) for v in tracks[0]],
                          z_right_m=[float(v) for v in tracks[1]]).check()


# -- outcomes of a run ---------------------------------------------------------------------

OUTCOMES = ("split_change_N", "split_change_rel", "stuck_left", "stuck_right",
            "dd_left_a_m", "dd_left_b_m", "dd_right_a_m", "dd_right_b_m",
            "rack_force_change_N", "wheel_torque_change_Nm", "pull_deg", "pull_lateral_m")


def outcomes(history, scene: Scene, study: DesignStudy):
    """The study's outcomes of one run (OUTCOMES; NaN where a run cannot say: the pull needs
    !HandsOff), and its speed at place a (``speed_a_kph``, against its timeline's
    ``speed_asked_kph``: whether it ran its manoeuvre)."""
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
    out["speed_a_kph"] = (3.6 * place_values(columns, timeline, "speed_mps")[0]
                          if "speed_mps" in columns else math.nan)
    out["speed_asked_kph"] = timeline.speed_kph
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
    # The torque the driver holds at the steering wheel: the rack force times the car's rack
    # gain (the logged channel, or from the force where a history lacks it).
    if "steering_wheel_torque_Nm" in columns:
        ta, tb = place_values(columns, timeline, "steering_wheel_torque_Nm")
        out["wheel_torque_change_Nm"] = tb - ta
    else:
        out["wheel_torque_change_Nm"] = (fb - fa) * scene.car.front.rack_gain_m_per_rad
    out["pull_deg"] = out["pull_lateral_m"] = math.nan
    if isinstance(scene.steering, HandsOff):
        release = hands_off_release_s(scene)
        t, yaw, y = h["t"], h["yaw_rad"], h["y_m"]
        speed = float(np.interp(release, t, h["speed_mps"]))
        until = release + study.pull_distance_m / max(speed, 1e-3)
        if until <= t[-1]:  # else the run ended before the pull distance: no pull (NaN)
            out["pull_deg"] = math.degrees(float(np.interp(until, t, yaw)
                                                 - np.interp(release, t, yaw)))
            out["pull_lateral_m"] = float(np.interp(until, t, y) - np.interp(release, t, y))
    return {k: float(v) for k, v in out.items()}
