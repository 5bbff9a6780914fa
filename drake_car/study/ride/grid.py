"""The ride study's runs: the car driving straight at constant speed over an ISO
8608 road, for road classes × speeds × strut friction μs, each scene also at half the step (its
numerical error, run by run). Pure: scenes in, scenes out; the sweep runs them.

The base scene is ``scenes/ride.yaml``'s ``ride``. Per run this sets: the road (``law.road.
iso8608.road_profile``, one seed for every class and speed, so the classes' roads are one
shape scaled by sqrt(Gd): class B is twice class A, C twice B, and every μs meets the same
road: paired comparisons), the speed with its launch, the friction (μd = ``mu_d_ratio`` μs;
μs = 0: no dry friction, the car's own strut damper) and the step.

The launch follows the car (``ride_timeline``): the paper's 0.57 g (60 km/h in 3 s, 100 km/h
in 5 s) where the car is predicted at its speed over the whole analysed window, else the
shortest launch its drive allows that it is (``scene.launch.followable_launch``, the launch
adaptation the paper study's scenes get; within ``SPEED_TOLERANCE_KPH`` less the prediction's
error from ``settle_window_s`` after the launch). The analysed window starts
``settle_window_s`` after the launch the car runs; whether the car held its speed there is
measured on each run (``analysis.window_speed_kph``) and a run that did not is flagged
(``report``).

Two strut models for μs > 0 (``strut``): ``damper`` keeps the car's hydraulic damping and adds
the dry friction (a real strut: a damper whose rod seal and guide also rub, as Deubel et al.
measured); ``paper`` removes the viscous damping (Harlecki & Kubas' dry strut, DESIGN 3).
"""

import dataclasses
import functools
import math
import typing

from pydrake.multibody.plant import MultibodyPlantConfig

from drake_car.law.checks import ParameterError
from drake_car.law.road.iso8608 import CLASS_GD_N0_M3, road_profile
from drake_car.scene.launch import followable_launch, holds_after_launch
from drake_car.scene.load import SceneError, check_scene, load_scene, stated
from drake_car.scene.manoeuvres import MAX_SPEED_KPH, Straight
from drake_car.scene.scene import Friction
from drake_car.law.friction.frd import StrutFrictionParameters

# The paper's speed-up (section 4): 60 km/h in 3 s, 0.57 g, asked at every speed (a car whose
# drive cannot follow it gets a longer launch: ``ride_timeline``).
SPEED_UP_KPH_PER_S = 20.0
STRUTS = ("damper", "paper")
# The road's length when the study does not give one: at least DEFAULT_ROAD_M (the length the
# study's runs were made on; with the shipped car's own launch it suffices up to ~127 km/h),
# longer where the fastest run needs it; a run needs its distance plus ROAD_MARGIN_M.
DEFAULT_ROAD_M = 400.0
ROAD_MARGIN_M = 10.0


@dataclasses.dataclass
class RideStudy:
    classes: typing.List[str] = dataclasses.field(default_factory=lambda: ["A", "B", "C"])
    speeds_kph: typing.List[float] = dataclasses.field(default_factory=lambda: [60.0, 100.0])
    mu_s: typing.List[float] = dataclasses.field(
        default_factory=lambda: [0.0, 0.1, 0.2, 0.3, 0.4])
    mu_d_ratio: float = 0.75
    strut: str = "damper"
    seed: int = 2023
    road_length_m: float | None = None  # None: derived from the speeds (``road_m``)
    # after reaching speed: ``settle_window_s`` to let the speed-up's transients decay, then
    # ``window_s`` analysed
    settle_window_s: float = 1.0
    window_s: float = 6.0
    # the tracks' width for the road's coherence (m); None: the car's front track
    track_m: typing.Optional[float] = None

    def check(self):
        """Refuses (ParameterError naming the field) a road class ISO 8608 does not define, a
        speed that is no passenger car's; every speed's run is then possible on ``road_m``."""
        for road_class in self.classes:
            if road_class not in CLASS_GD_N0_M3:
                raise ParameterError("classes", road_class, "must be one of "
                                     f"{', '.join(CLASS_GD_N0_M3)} (ISO 8608)")
        for speed in self.speeds_kph:
            if not 0 < speed <= MAX_SPEED_KPH:
                raise ParameterError("speeds_kph", speed, f"must lie in (0, {MAX_SPEED_KPH:g}] "
                                     "km/h (a passenger car)")
        return self

    def run_distance_m(self, speed_kph, launch_s=None):
        """How far a run at ``speed_kph`` drives: the launch (``launch_s``; None: the asked
        0.57 g), then the settling and the analysed window at constant speed."""
        launch_s = speed_up_s(speed_kph) if launch_s is None else launch_s
        return speed_kph / 3.6 * (0.5 * launch_s + self.settle_window_s + self.window_s)

    def road_m(self, launches=None):
        """The road's length: ``road_length_m``, or derived from the runs' distances
        (``launches``: {speed_kph: the car's launch (s)}; None or a speed left out: the asked
        0.57 g)."""
        if self.road_length_m is not None:
            return self.road_length_m
        launches = launches or {}
        need = max((self.run_distance_m(v, launches.get(float(v))) for v in self.speeds_kph),
                   default=0.0)
        return max(DEFAULT_ROAD_M, float(math.ceil(need + ROAD_MARGIN_M)))


def base_scene(scene_text=None, scene=None):
    """``scenes/ride.yaml``'s ``ride`` with the values the scene file ``scene`` ((FILE, ENTRY
    or None): the user's car) states laid over it, then ``scene_text``."""
    from drake_car.data import resource
    base = load_scene(resource("scenes") / "ride.yaml", child="ride")
    if scene is not None:
        base = load_scene(scene[0], child=scene[1], base=base)
        _refuse_what_the_study_sets(stated(scene[0], scene[1]),
                                    f"--scene {':'.join(str(p) for p in scene if p)}")
    if scene_text:
        base = load_scene(scene_text=scene_text, base=base)
        _refuse_what_the_study_sets(stated(scene_text=scene_text), "--scene_text")
    if not isinstance(base.manoeuvre, Straight):
        raise SceneError(f"the ride study drives straight at constant speed; its base scene's "
                         f"manoeuvre must be !Straight, not !{type(base.manoeuvre).__name__} "
                         "from --scene/--scene_text: give the car alone (a scene entry "
                         "without a manoeuvre, or --scene_text \"{car_file: FILE, ...}\")")
    return base


def _refuse_what_the_study_sets(raw, where):
    """A user's scene that states a value of the timeline the study sets per speed (the speed,
    the launch, the window) is refused: it would be replaced without a word. Only ``settle_s``,
    the time at rest before the launch, is the scene's."""
    if "road" in raw:
        raise SceneError(f"{where}: states road; the ride study lays its ISO 8608 road under "
                         "the car (--classes) and would replace it: leave it out")
    if "friction" in raw:
        law = raw["friction"].get("law") if isinstance(raw["friction"], dict) else None
        stated_mu = [k for k in ("mu_s", "mu_d") if isinstance(law, dict) and k in law]
        if raw["friction"] is None or stated_mu:
            what = "friction: null" if raw["friction"] is None else f"friction.law.{stated_mu[0]}"
            raise SceneError(f"{where}: states {what}; the ride study sets the struts' friction "
                             "per run (μs 0, the lubricated strut, to 0.4; μd 0.75 μs) and would "
                             "replace it: leave it out (the law's other values, the scheme and "
                             "the pairs you state run)")
    manoeuvre = raw.get("manoeuvre")
    if not isinstance(manoeuvre, dict) or manoeuvre.get("_tag", "!Straight") != "!Straight":
        return  # none, or another manoeuvre: refused below unless a later layer replaces it
    timeline = manoeuvre.get("timeline")
    for key in RIDE_SETS:
        if isinstance(timeline, dict) and key in timeline:
            raise SceneError(
                f"{where}: states manoeuvre.timeline.{key} ({timeline[key]}); the ride study "
                f"sets it ({RIDE_SETS[key]}) and would replace it: leave it out (of the "
                "timeline only settle_s, the time at rest before the launch, is your scene's)")


RIDE_SETS = {  # what the study sets of a scene's timeline, and how
    "speed_kph": "the speeds: --speeds",
    "speed_up_s": f"the launch: {SPEED_UP_KPH_PER_S:g} km/h per s, or the shortest the car's "
                  "drive allows",
    "straight_s": "none: the window follows the launch",
    "steer_s": "the analysed window: settle_window_s + window_s of the study",
    "calm_s": "none: the run ends with its window",
}


def speed_up_s(speed_kph):
    """The asked launch to ``speed_kph`` (s): the paper's 0.57 g."""
    return speed_kph / SPEED_UP_KPH_PER_S


def ride_timeline(study: RideStudy, base, speed_kph):
    """The timeline of the runs at ``speed_kph`` on ``base``'s car: at rest for the base's
    ``settle_s``, the launch, then ``settle_window_s`` and ``window_s`` straight on (one phase
    III). The launch: ``speed_up_s`` (0.57 g) if the car is predicted within the speed's
    tolerance over the analysed window, else the shortest launch its drive allows that it is
    (``scene.launch.followable_launch``; see the module)."""
    timeline = dataclasses.replace(
        base.manoeuvre.timeline, speed_kph=float(speed_kph), straight_s=0.0,
        steer_s=study.settle_window_s + study.window_s, calm_s=0.0)
    return followable_launch(base, timeline, speed_up_s(speed_kph),
                             test=holds_after_launch(study.settle_window_s))


def ride_timelines(study: RideStudy, base):
    """{speed_kph: ``ride_timeline``} of every speed of the study."""
    return {float(v): ride_timeline(study, base, v) for v in study.speeds_kph}


@functools.lru_cache(maxsize=16)
def _road(road_class, seed, length_m, track_m):
    """The road of a class (one object shared by its runs: a scene's road is not changed)."""
    return road_profile(road_class, seed=seed, length_m=length_m, track_m=track_m)


def scene_name(road_class, speed_kph, mu_s, strut, half):
    name = f"{road_class}_{speed_kph:g}kph_mu{mu_s:.2f}"
    if mu_s > 0:
        name += f"_{strut}"
    return name + ("_half" if half else "")


def ride_scene(study: RideStudy, road_class, speed_kph, mu_s, *, half=False, base=None,
               timelines=None):
    """One run's scene; ``timelines``: ``ride_timelines(study, base)`` (None: found here; a
    speed not among the study's gets its own)."""
    base = base or base_scene()
    timelines = timelines or ride_timelines(study, base)
    timeline = timelines.get(float(speed_kph)) or ride_timeline(study, base, speed_kph)
    manoeuvre = dataclasses.replace(base.manoeuvre, timeline=timeline)
    track = base.car.front.track_m if study.track_m is None else study.track_m
    launches = {v: t.speed_up_s for v, t in timelines.items()}
    road_m = study.road_m(launches)
    road = _road(road_class, study.seed, road_m, track)
    car, friction = base.car, None
    if mu_s > 0:  # the base scene's friction (its law's other values, scheme, pairs) at μs
        stated = base.friction or Friction(law=StrutFrictionParameters())
        law = dataclasses.replace(stated.law, mu_s=float(mu_s),
                                  mu_d=study.mu_d_ratio * float(mu_s))
        friction = dataclasses.replace(stated, law=law)
        if study.strut == "paper":
            car = dataclasses.replace(car, front=dataclasses.replace(car.front,
                                                                     strut_damping_Nspm=0.0))
    plant = MultibodyPlantConfig(**{f.name: getattr(base.plant, f.name)
                                    for f in MultibodyPlantConfig.__fields__})
    if half:
        plant.time_step = base.plant.time_step / 2
    logging = base.logging
    if friction is not None:
        logging = dataclasses.replace(logging, channels=[*logging.channels, "friction"])
    scene = dataclasses.replace(base, name=scene_name(road_class, speed_kph, mu_s, study.strut,
                                                      half),
                                manoeuvre=manoeuvre, road=road, car=car, friction=friction,
                                plant=plant, logging=logging)
    scene = check_scene(scene, f"ride study {scene.name}")
    need = study.run_distance_m(speed_kph, timeline.speed_up_s) + ROAD_MARGIN_M
    if road_m < need:
        raise ParameterError("road_length_m", road_m, f"is shorter than the run "
                             f"at {speed_kph:g} km/h needs ({need:.0f} m: its distance plus "
                             f"{ROAD_MARGIN_M:g} m); give at least that, or none (derived "
                             "from the speeds)")
    return scene


def analysed_from_s(scene, study: RideStudy):
    """The start of the analysed window of ``scene`` (s)."""
    t = scene.manoeuvre.timeline
    return t.settle_s + t.speed_up_s + study.settle_window_s


def ride_scenes(study: RideStudy, order=None, scene_text=None, scene=None):
    """{name: scene} of every run and its half-step twin; ``order``: a list of (class, speed)
    to run first (the rest follow); ``scene`` and ``scene_text`` laid over the base scene
    (``base_scene``)."""
    study.check()
    base = base_scene(scene_text, scene)
    timelines = ride_timelines(study, base)
    cells = [(c, v) for v in study.speeds_kph for c in study.classes]
    if order:
        cells = [c for c in order if c in cells] + [c for c in cells if c not in order]
    scenes = {}
    for road_class, speed in cells:
        for mu_s in study.mu_s:
            for half in (False, True):
                scene = ride_scene(study, road_class, speed, mu_s, half=half, base=base,
                                   timelines=timelines)
                scenes[scene.name] = scene
    return scenes
