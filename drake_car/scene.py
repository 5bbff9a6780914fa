"""Scenes: what to simulate and which effects to include, as typed dataclasses loaded from YAML
with Drake's ``yaml_load_typed`` (unknown keys are errors naming the key).

Layering: a file (optionally a named child of it), then a ``--scene_text`` string on top. A
scene is saved with every result (``yaml_dump_typed``), so a result says how it was made.
``build_scene`` turns a scene into the arguments of ``drake_car.drive.run_drive`` or
``drake_car.settle.run_settle``; the Diagram then holds only the systems the scene calls for.
"""

import dataclasses
import typing
from pathlib import Path

from pydrake.common.yaml import yaml_dump_typed, yaml_load_typed

from drake_car.assembly import DEFAULT_TIR, LOG_CHANNELS, TyreSetup
from drake_car.law.frd_friction import StrutFrictionParameters
from drake_car.law.road import CosineBump, SampledProfile, flat
from drake_car.law.tyre_slip import SlipOptions
from drake_car.manoeuvre import Timeline
from drake_car.model.parameters import CarParameters
from drake_car.systems.strut_friction import StrutFrictionSetup

REPO_ROOT = Path(__file__).resolve().parents[1]
SCENES_DIR = REPO_ROOT / "scenes"


class SceneError(ValueError):
    """A scene is malformed or asks for something that does not exist; names the key."""


@dataclasses.dataclass
class CarSettings:
    strut_damping_Nspm: float = 1250.0  # paper: 1250 for the lubricated strut, 0 when dry
    ball_joint_offset_b_m: float = CarParameters().front.ball_joint_offset_b_m
    guide_length_l_m: float = CarParameters().front.guide_length_l_m
    spring_inclination_deg: float = 0.0
    spring_offset_m: float = 0.0
    top_mount_stiffness_Npm: float = 0.0  # 0: rigid; > 0: an elastomer mount (N/m)
    top_mount_damping_Nspm: float = CarParameters().front.top_mount_damping_Nspm


@dataclasses.dataclass
class FrictionEffect:
    """The strut-friction effect. The law's fields repeat StrutFrictionParameters' because that
    dataclass is frozen (validated once, shared by the systems) and yaml_load_typed assigns
    fields one by one; ``resolve`` builds (and so validates) the law from them."""

    mode: str = "off"  # off | translation | translation_rotation
    scheme: str = "fast"  # fast | reference
    mu_s: float = 0.2
    mu_d: float = 0.15
    dv_translation_mps: float = 1e-4
    dmax_translation_m: float = 5e-6
    dv_rotation_radps: float = 1e-4
    dmax_rotation_rad: float = 5e-6
    shape: str = "cubic"  # cubic | linear
    normal_force_form: str = "vector"  # vector | magnitude_sum | contact_pair


@dataclasses.dataclass
class TyreEffect:
    model: str = "magic_formula"  # magic_formula | linear (MF linearised at zero slip) | vertical
    combined_slip: bool = True
    relaxation: bool = True
    tir_file: str = str(DEFAULT_TIR.relative_to(REPO_ROOT))


@dataclasses.dataclass
class RoadEffect:
    profile: str = "flat"  # flat | bump | samples (a pothole is a bump of negative height)
    start_x_m: float = 40.0
    length_m: float = 1.5
    height_m: float = 0.05
    samples_x_m: typing.List[float] = dataclasses.field(default_factory=list)
    samples_z_m: typing.List[float] = dataclasses.field(default_factory=list)


@dataclasses.dataclass
class Manoeuvre:
    kind: str = "lane_change"  # settle | straight | lane_change
    case: str = "a"  # a (left turn first) | b (right turn first)
    timeline: Timeline = dataclasses.field(default_factory=Timeline)


@dataclasses.dataclass
class SimulatorSettings:
    time_step_s: float = 1e-3
    end_time_s: float = 0.0  # 0: the whole timeline
    record_period_s: float = 0.01
    # Keep SAP from returning its initial guess near a balance (drake_car/systems/sap_pacer.py).
    sap_pacer: bool = True
    # Where a drive starts: at rest in the lubricated car's static equilibrium (as the study's
    # runs do), or at the model's design position (the car then drops onto its tyres).
    start: str = "static_equilibrium"  # static_equilibrium | design


@dataclasses.dataclass
class Logging:
    """Channel groups logged every ``simulator.record_period_s`` (drives; a settle records its
    own few quantities): chassis, steering, struts, tyres, friction. A group not listed has no
    logger in the Diagram."""

    channels: typing.List[str] = dataclasses.field(default_factory=lambda: list(LOG_CHANNELS))


@dataclasses.dataclass
class Visualization:
    """none: no visualiser in the Diagram; meshcat_live: a Meshcat server on localhost (its URL
    is printed) shows the run as it goes, paced at ``realtime_rate`` (0: as fast as it can);
    meshcat_html: the run is recorded and saved as a self-contained replay page."""

    mode: str = "none"  # none | meshcat_live | meshcat_html
    realtime_rate: float = 1.0  # meshcat_live only


@dataclasses.dataclass
class Scene:
    name: str = "scene"
    car: CarSettings = dataclasses.field(default_factory=CarSettings)
    friction: FrictionEffect = dataclasses.field(default_factory=FrictionEffect)
    tyres: TyreEffect = dataclasses.field(default_factory=TyreEffect)
    road: RoadEffect = dataclasses.field(default_factory=RoadEffect)
    manoeuvre: Manoeuvre = dataclasses.field(default_factory=Manoeuvre)
    simulator: SimulatorSettings = dataclasses.field(default_factory=SimulatorSettings)
    logging: Logging = dataclasses.field(default_factory=Logging)
    visualization: Visualization = dataclasses.field(default_factory=Visualization)


CHOICES = {
    ("friction", "mode"): ("off", "translation", "translation_rotation"),
    ("friction", "scheme"): ("fast", "reference"),
    ("friction", "shape"): ("cubic", "linear"),
    ("friction", "normal_force_form"): ("vector", "magnitude_sum", "contact_pair"),
    ("tyres", "model"): ("magic_formula", "linear", "vertical"),
    ("road", "profile"): ("flat", "bump", "samples"),
    ("manoeuvre", "kind"): ("settle", "straight", "lane_change"),
    ("manoeuvre", "case"): ("a", "b"),
    ("visualization", "mode"): ("none", "meshcat_live", "meshcat_html"),
    ("simulator", "start"): ("static_equilibrium", "design"),
}


def load_scene(path=None, *, child=None, scene_text=None) -> Scene:
    """A scene from ``path`` (its ``child`` entry if given), with ``scene_text`` on top."""
    scene = Scene()
    where = "scene"
    try:
        if path is not None:
            path = Path(path)
            if not path.is_file():
                raise SceneError(f"{path}: scene file not found")
            where = f"{path}" + (f" [{child}]" if child else "")
            scene = yaml_load_typed(schema=Scene, filename=str(path), child_name=child,
                                    defaults=scene)
        if scene_text:
            where = f"--scene_text {scene_text!r}"
            scene = yaml_load_typed(schema=Scene, data=scene_text, defaults=scene)
    except SceneError:
        raise
    except Exception as e:  # yaml errors name the unknown key or the bad value
        raise SceneError(f"{where}: {e}") from e
    validate(scene, where)
    return scene


def validate(scene: Scene, where="scene"):
    for (group, key), allowed in CHOICES.items():
        value = getattr(getattr(scene, group), key)
        if value not in allowed:
            raise SceneError(f"{where}: {group}.{key} = {value!r} must be one of {allowed}")
    for key in ("time_step_s", "record_period_s"):
        if not getattr(scene.simulator, key) > 0:
            raise SceneError(f"{where}: simulator.{key} must be > 0")
    if scene.simulator.end_time_s < 0:
        raise SceneError(f"{where}: simulator.end_time_s must be >= 0")
    if not scene.visualization.realtime_rate >= 0:
        raise SceneError(f"{where}: visualization.realtime_rate must be >= 0")
    for channel in scene.logging.channels:
        if channel not in LOG_CHANNELS:
            raise SceneError(f"{where}: logging.channels: {channel!r} must be one of "
                             f"{LOG_CHANNELS}")
    if len(set(scene.logging.channels)) != len(scene.logging.channels):
        raise SceneError(f"{where}: logging.channels {scene.logging.channels} repeats a group")
    return scene


def dump_scene(scene: Scene) -> str:
    return yaml_dump_typed(scene)


@dataclasses.dataclass
class BuiltScene:
    """What a scene resolves to: the arguments of the simulation functions."""

    params: CarParameters
    friction: StrutFrictionSetup | None
    tyres: TyreSetup
    road_height: object
    timeline: Timeline
    case: str
    time_step_s: float
    end_time_s: float | None
    record_period_s: float
    log_channels: tuple = LOG_CHANNELS
    sap_pacer: bool = True
    start: str = "static_equilibrium"


def resolve(scene: Scene) -> BuiltScene:
    """Turns a scene into parameters and setups; raises SceneError naming a bad value."""
    try:
        params = CarParameters()
        params.front.strut_damping_Nspm = scene.car.strut_damping_Nspm
        params.front.ball_joint_offset_b_m = scene.car.ball_joint_offset_b_m
        params.front.guide_length_l_m = scene.car.guide_length_l_m
        params.front.spring_inclination_deg = scene.car.spring_inclination_deg
        params.front.spring_offset_m = scene.car.spring_offset_m
        params.front.top_mount_stiffness_Npm = scene.car.top_mount_stiffness_Npm
        params.front.top_mount_damping_Nspm = scene.car.top_mount_damping_Nspm
        params.validate()
        f = scene.friction
        friction = None
        if f.mode != "off":
            law = StrutFrictionParameters(
                mu_s=f.mu_s, mu_d=f.mu_d, dv_translation_mps=f.dv_translation_mps,
                dmax_translation_m=f.dmax_translation_m, dv_rotation_radps=f.dv_rotation_radps,
                dmax_rotation_rad=f.dmax_rotation_rad, beta_shape=f.shape, creep_shape=f.shape,
                rod_radius_m=params.front.rod_radius_r_m, normal_force_form=f.normal_force_form)
            friction = StrutFrictionSetup(law, scheme=f.scheme,
                                          rotation=f.mode == "translation_rotation")
        t = scene.tyres
        tyres = TyreSetup(magic_formula=t.model != "vertical",
                          tir_path=REPO_ROOT / t.tir_file, combined=t.combined_slip,
                          slip=SlipOptions(relaxation=t.relaxation),
                          linear=t.model == "linear")
        r = scene.road
        road = flat
        if r.profile == "bump":
            road = CosineBump(r.start_x_m, r.length_m, r.height_m)
        elif r.profile == "samples":
            road = SampledProfile(tuple(r.samples_x_m), tuple(r.samples_z_m))
        m = scene.manoeuvre
        timeline = Timeline(**dataclasses.asdict(m.timeline))  # validates the loaded values
    except SceneError:
        raise
    except ValueError as e:
        raise SceneError(f"scene {scene.name!r}: {e}") from e
    case = "straight" if m.kind == "straight" else m.case
    end = scene.simulator.end_time_s or None
    return BuiltScene(params, friction, tyres, road, timeline, case,
                      scene.simulator.time_step_s, end, scene.simulator.record_period_s,
                      tuple(scene.logging.channels), scene.simulator.sap_pacer,
                      scene.simulator.start)


def shipped_scenes():
    """(file, child) of every scene in scenes/*.yaml: each top-level entry of a file is a
    scene, except those whose name starts with "_" (templates for YAML merge keys)."""
    from pydrake.common.yaml import yaml_load
    found = []
    for path in sorted(SCENES_DIR.glob("*.yaml")):
        for child in yaml_load(filename=str(path)):
            if not child.startswith("_"):
                found.append((path, child))
    return found
