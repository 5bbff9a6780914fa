"""The scene: everything a run is made of, one typed dataclass tree (loaded from YAML with
Drake's ``yaml_load_typed``; see ``scene.load``). A run is a pure function of its scene.

Sections, each a loadable dataclass with a ``check()`` that names a bad key:

- ``car_file``: a car file (``model.hard_points``: the car from its hard points, the whole
  car's mass and centre of gravity, the rates), read where the scene is loaded into ``car``
  (``scene.car_file``), beneath the scene's own ``car:`` values; None: the Escort's defaults;
- ``car``: the car's parameters (``model.parameters.CarParameters``: every number with its
  source), from which the model file is generated;
- ``friction``: dry friction in the front struts (None: none; the lubricated strut is the car's
  ``front.strut_damping_Nspm``), with the law's parameters (``law.friction.frd``);
- ``tyres``: ``!MagicFormula`` (default), ``!LinearTyre`` or ``!VerticalOnly``;
- ``road``: ``!Flat`` (default), ``!CosineBump`` or ``!SampledProfile`` (``law.road.profiles``);
- ``manoeuvre``: ``!LaneChange`` (default), ``!Straight``, ``!Settle``, ``!RampSteer``,
  ``!StepSteer`` (``scene.manoeuvres``), ``!DoubleLaneChange``, ``!ConstantRadius``
  (``scene.paths``: defined by a path);
- ``drive``: ``!OpenDifferential`` (default: one torque split equally) or
  ``!PrescribedRotation`` (the paper's: both driven wheels' rotation prescribed), on the car's
  ``driven_axle``;
- ``steering``: ``!HeldRack`` (default: the rack follows the command), ``!HandsOff`` or
  ``!PathFollower`` (a driver follows a path manoeuvre's path);
- ``plant``: Drake's ``MultibodyPlantConfig`` (the time step; the car needs SAP);
- ``simulator``: end time, initial state, the SAP pacer, the divergence monitor's period, the
  events resolved locally (``scene.simulator``);
- ``logging``: which channel groups are logged, how often;
- ``visualization``: ``!NoVisualization`` (default), ``!MeshcatLive``, ``!MeshcatReplay``.
"""

import dataclasses
import typing

from pydrake.multibody.plant import MultibodyPlantConfig

from drake_car.law.checks import ParameterError, checked, nonnegative, one_of, positive
from drake_car.law.friction.frd import StrutFrictionParameters
from drake_car.law.road.profiles import Flat, Road
from drake_car.law.tyre.slip import SlipOptions
from drake_car.model.parameters import CarParameters
from drake_car.scene import manoeuvres
from drake_car.scene.manoeuvres import LaneChange
from drake_car.scene.paths import PATH_MANOEUVRES, PathFollower
from drake_car.scene.simulator import ResolveEvents, Simulator  # noqa: F401 (sections)

DEFAULT_TIR = "tyres/pacejka2006_205_60R15.tir"


@dataclasses.dataclass
class Friction:
    """Dry friction between piston rod and cylinder in both front struts (paper sections 2-3).
    ``pairs``: translation (along the strut) or translation_rotation (also about it).
    ``scheme``: fast (the law's linearisation inside SAP's implicit step; stable at 1 ms) or
    reference (the law applied explicitly; stable only at microsecond steps)."""

    pairs: str = "translation_rotation"
    scheme: str = "fast"
    law: StrutFrictionParameters = dataclasses.field(default_factory=StrutFrictionParameters)

    def check(self):
        one_of(self, "pairs", ("translation", "translation_rotation"))
        one_of(self, "scheme", ("fast", "reference"))
        checked(self.law, "law")
        if self.pairs == "translation":
            default = StrutFrictionParameters()
            for name in ("dv_rotation_radps", "dmax_rotation_rad", "preload_moment_Nm"):
                if getattr(self.law, name) != getattr(default, name):
                    raise ParameterError(f"law.{name}", getattr(self.law, name),
                                         "acts on the rotation pair, which pairs: translation "
                                         "leaves out; remove it or use translation_rotation")
        return self

    @property
    def rotation(self):
        return self.pairs == "translation_rotation"


def _check_slip(slip: SlipOptions):
    checked(slip, "slip")
    default = SlipOptions()
    unused = (("v_floor_mps",) if slip.relaxation else
              ("relaxation_length_long_m", "relaxation_length_lat_m"))
    for name in unused:
        if getattr(slip, name) != getattr(default, name):
            raise ParameterError(f"slip.{name}", getattr(slip, name),
                                 f"has no effect with slip.relaxation = {slip.relaxation}")


@dataclasses.dataclass
class TirTyre:
    """What the tyres read from a property file share (not loadable itself): the file
    ``tir_file`` (a path, or a name in the package's ``urdf/`` data such as the default), the
    slip options (relaxation lengths, low-speed damping) and whether the radial spring and
    damper are the file's (``vertical_from_file``)."""

    tir_file: str = DEFAULT_TIR
    slip: SlipOptions = dataclasses.field(default_factory=SlipOptions)
    # Take the radial stiffness and damping from the file's VERTICAL_STIFFNESS and
    # VERTICAL_DAMPING instead of car.tyre's (set into car.tyre where the scene is loaded:
    # ``scene.vertical``); the unloaded radius stays the car's (its geometry).
    vertical_from_file: bool = False

    def check(self):
        _check_slip(self.slip)
        return self


@dataclasses.dataclass
class MagicFormula(TirTyre):
    """Pacejka's Magic Formula (the book's 2006 form) with the coefficients of ``tir_file``,
    combined slip or pure slip."""

    combined_slip: bool = True


@dataclasses.dataclass
class LinearTyre(TirTyre):
    """The Magic Formula tyre of ``tir_file`` linearised about zero slip (no saturation)."""


@dataclasses.dataclass
class VerticalOnly:
    """The tyres' radial spring and damper only (no horizontal forces): for a car at rest."""

    def check(self):
        return self


Tyres = typing.Union[MagicFormula, LinearTyre, VerticalOnly]


@dataclasses.dataclass
class PrescribedRotation:
    """The paper's drive (section 4): both driven wheels' rotation prescribed by stiff servos
    (a locked driven axle: the front on the Escort, the rear on a rear-drive car's
    ``car.driven_axle``). ``reaction``:
    driveshaft (the torque is reacted by the body, as in a car) or knuckle (reacted at the wheel
    joint's carrier, as a joint motion in Adams)."""

    reaction: str = "driveshaft"

    def check(self):
        one_of(self, "reaction", ("driveshaft", "knuckle"))
        return self


@dataclasses.dataclass
class OpenDifferential:
    """One drive torque split equally between the driven wheels (an open differential on the
    car's ``driven_axle``: the front wheels of a front-drive car), from a speed controller:
    T = m R a_ref(t) + K (v_ref(t) - v), v the car's speed measured at the free-rolling wheels
    of the other axle, clamped to ±``max_wheel_torque_Nm`` (both wheels together). The torque
    is reacted by the body (driveshafts)."""

    # [EST] τ = m R / K = 0.2 s: the car follows its speed profile within a few tenths of a
    # second without exciting the wheels' spin (their own time constant is ~10 ms).
    speed_gain_Nm_per_mps: float = 1800.0
    # [EST] the 1.9 l Escort's ~150 N m through first gear (3.23) and final drive (3.59):
    # 1740 N m at the wheels; the tyres' grip limits the launch first.
    max_wheel_torque_Nm: float = 1740.0
    # [EST] the engine's rev limit as a governor: above ``rev_limit_ratio`` times the wheel
    # speed of the manoeuvre's top speed, the differential's mean speed is pulled back with
    # ``governor_gain_Nm_per_radps`` (an open differential sends the torque to a lifted wheel,
    # which would otherwise spin up without bound). Explicit: stable for dt < 4 I / K (24 ms;
    # ``scene.limits`` refuses a gain unstable at the scene's step).
    rev_limit_ratio: float = 1.3
    governor_gain_Nm_per_radps: float = 100.0
    # The clamp no more than the driven tyres transmit in the launch (``scene.launch.
    # drive_torque_limit_Nm``: 0.9 of their peak grip at the launch's axle load, what the
    # launch is planned for), as a driver's foot or a traction control holds a launch at the
    # tyres' grip [EST]. Without it a speed controller that lags asks its whole clamp and, on a
    # tyre whose grip falls past its peak, spins the wheels up without bound (a 1500 kg
    # rear-drive car with 3500 N m on Chrono's Generic_Pac02Tire: κ 16, 39 instead of 60 km/h
    # at place a; with it κ <= 0.073, 59.4 km/h). A car whose drive is below its tyres' grip
    # (the shipped Escort: 1740 < 1952 N m) runs as without it.
    torque_within_grip: bool = True

    def check(self):
        positive(self, "speed_gain_Nm_per_mps", "max_wheel_torque_Nm",
                 "governor_gain_Nm_per_radps")
        if not 1.0 < self.rev_limit_ratio <= 3.0:
            raise ParameterError("rev_limit_ratio", self.rev_limit_ratio, "must lie in (1, 3]")
        return self


# The default (first) is the physical one: a front-drive car has an open differential. The
# paper's prescribed rotation locks the driven axle (on the Escort the front: about 3 deg/g of
# understeer).
Drive = typing.Union[OpenDifferential, PrescribedRotation]


@dataclasses.dataclass
class HeldRack:
    """The driver's hands: a stiff servo holds the rack on the manoeuvre's command."""

    def check(self):
        return self


@dataclasses.dataclass
class HandsOff:
    """The rack held on the manoeuvre's command until ``release_s`` (None: the start of phase
    IV, after the manoeuvre), then free: the steering wheel's inertia through the car's rack
    gain (``car.front.rack_gain_m_per_rad``), the steering system's friction, and the tyres'
    and the suspension's own centring (aligning moments, caster and kingpin) move it, so a
    load imbalance shows as a drift of the car's heading."""

    release_s: typing.Optional[float] = None
    # [EST] steering wheel and column about the column: a 0.38 m wheel of ~1.4 kg rim and hub.
    steering_wheel_inertia_kgm2: float = 0.04
    # [EST] static friction of the unassisted column and rack at the steering wheel; a dry
    # contact (the FRD law, μd/μs = 0.8).
    friction_torque_Nm: float = 1.0

    def check(self):
        positive(self, "steering_wheel_inertia_kgm2")
        nonnegative(self, "friction_torque_Nm")
        if self.release_s is not None:
            positive(self, "release_s")
        return self


# The driver following a path manoeuvre's path (scene.paths) is the third way to steer.
Steering = typing.Union[HeldRack, HandsOff, PathFollower]
# The manoeuvres of scene.manoeuvres and those defined by a path (scene.paths).
Manoeuvre = typing.Union[(*typing.get_args(manoeuvres.Manoeuvre), *PATH_MANOEUVRES)]


@dataclasses.dataclass
class Logging:
    """Channel groups logged every ``record_period_s`` by Drake VectorLogSinks. ``channels``:
    None logs every group the scene has; a list logs exactly those (a group whose effect is off
    is refused). Groups: chassis, steering, struts, tyres, friction, energy, top_mounts."""

    channels: typing.Optional[list[str]] = None
    record_period_s: float = 0.01

    def check(self):
        positive(self, "record_period_s")
        if self.channels is not None and len(set(self.channels)) != len(self.channels):
            raise ParameterError("channels", self.channels, "must not repeat a group")
        return self


@dataclasses.dataclass
class NoVisualization:
    """No visualiser in the Diagram."""

    def check(self):
        return self


@dataclasses.dataclass
class MeshcatLive:
    """Meshcat on localhost (its URL is printed) shows the run as it goes, paced at
    ``realtime_rate`` (0: as fast as it can)."""

    realtime_rate: float = 1.0

    def check(self):
        nonnegative(self, "realtime_rate")
        return self


@dataclasses.dataclass
class MeshcatReplay:
    """The run is recorded into a self-contained replay page (``replay.html``) with the road
    and its lane markings drawn. ``camera``: follow (a chase camera behind the car) or overview
    (the whole manoeuvre in view)."""

    frames_per_second: float = 32.0
    camera: str = "follow"

    def check(self):
        positive(self, "frames_per_second")
        one_of(self, "camera", ("follow", "overview"))
        return self


Visualization = typing.Union[NoVisualization, MeshcatLive, MeshcatReplay]


def at_time_step(scene, time_step_s):
    """``scene`` with its plant's time step set to ``time_step_s`` (the rest as it is)."""
    plant = scene.plant
    config = MultibodyPlantConfig(**{f.name: getattr(plant, f.name)
                                     for f in MultibodyPlantConfig.__fields__})
    config.time_step = time_step_s
    return dataclasses.replace(scene, plant=config)


def default_plant_config():
    return MultibodyPlantConfig(time_step=1e-3, discrete_contact_approximation="sap")


@dataclasses.dataclass
class Scene:
    name: str = "scene"
    car_file: typing.Optional[str] = None
    car: CarParameters = dataclasses.field(default_factory=CarParameters)
    friction: typing.Optional[Friction] = None
    tyres: Tyres = dataclasses.field(default_factory=MagicFormula)
    road: Road = dataclasses.field(default_factory=Flat)
    manoeuvre: Manoeuvre = dataclasses.field(default_factory=LaneChange)
    drive: Drive = dataclasses.field(default_factory=OpenDifferential)
    steering: Steering = dataclasses.field(default_factory=HeldRack)
    plant: MultibodyPlantConfig = dataclasses.field(default_factory=default_plant_config)
    simulator: Simulator = dataclasses.field(default_factory=Simulator)
    logging: Logging = dataclasses.field(default_factory=Logging)
    visualization: Visualization = dataclasses.field(default_factory=NoVisualization)

    @property
    def time_step_s(self):
        return self.plant.time_step

    @property
    def end_time_s(self):
        """When the run ends (s)."""
        end = self.simulator.end_time_s
        return self.manoeuvre.end_s if end is None else end
