"""The car as a discrete (SAP) MultibodyPlant: model file + loop closures + springs + steering servo.

Build order follows Drake's hardware_sim: ``add_car`` parses the model and adds the force
elements and constraints that the file cannot express, *before* ``plant.Finalize()``.
"""

import dataclasses
from pathlib import Path

import numpy as np
from pydrake.multibody.tree import LinearSpringDamper, PdControllerGains

from drake_car.model.anti_roll_bar import arm_rates
from drake_car.model.geometry import SIDES, design_axle_loads_N
from drake_car.model.kinematics import LOOP_CLOSURES, SuspensionKinematics
from drake_car.model.loading import ModelSource, frame_point, load_car
from drake_car.model.parameters import GRAVITY_MPS2, CarParameters
from drake_car.model.sdformat import generate_sdformat
from drake_car.systems.sap_ballast import sap_momentum_scale

# Steering servo on the rack: SAP's implicit PD, standing for the steering column held by the
# driver. 1e7 N/m keeps the rack within ~0.05 mm of its command under the ~500 N tie-rod loads
# of a lane change; the damping makes it critically damped for the rack's ~5 kg reflected mass.
RACK_SERVO_GAINS = PdControllerGains(p=1.0e7, d=1.4e4)


@dataclasses.dataclass
class SpringSetting:
    stiffness_Npm: float
    free_length_m: float
    design_length_m: float
    motion_ratio: float  # |dL_spring / dz_wheel| at the design position
    design_force_N: float


@dataclasses.dataclass
class CarModel:
    """Handles to the car inside a plant."""

    params: CarParameters
    plant: object
    instance: object
    source: ModelSource
    springs: dict  # (axle, side) -> SpringSetting
    rack_actuator: object
    # The compliant top mounts' spring-damper actuators (x, y, z per side; empty when rigid),
    # added right after the rack servo; their desired state is zero.
    top_mount_actuators: list = dataclasses.field(default_factory=list)
    # The front wheels' drive actuators (model.drive), when the car drives.
    drive_actuators: list = dataclasses.field(default_factory=list)
    # (axle, side) -> wheel-centre travel per arm angle at design (model.anti_roll_bar).
    arm_rates: dict = dataclasses.field(default_factory=dict)

    def joint(self, name):
        return self.plant.GetJointByName(name, self.instance)

    def body(self, name):
        return self.plant.GetBodyByName(name, self.instance)

    def strut_joints(self, side):
        """(prismatic, revolute) joints of the strut's cylindrical pair."""
        return (self.joint(f"strut_prismatic_{side}"), self.joint(f"strut_revolute_{side}"))

    def wheel_bodies(self):
        return {"fl": self.body("wheel_front_left"), "fr": self.body("wheel_front_right"),
                "rl": self.body("wheel_rear_left"), "rr": self.body("wheel_rear_right")}


def model_source(params: CarParameters, model_path=None) -> ModelSource:
    if model_path is not None:
        return ModelSource(path=Path(model_path), label=str(model_path))
    return ModelSource(text=generate_sdformat(params))


_SPRING_CACHE = {}
_RATE_CACHE = {}


def cached_arm_rates(params, source):
    """``model.anti_roll_bar.arm_rates``, cached per (parameters, model file)."""
    key = (repr(params), source.text, str(source.path))
    if key not in _RATE_CACHE:
        _RATE_CACHE[key] = arm_rates(params, source)
    return _RATE_CACHE[key]


def spring_settings(params: CarParameters, source: ModelSource):
    """Spring rates (from the wheel rates and the motion ratios) and free lengths chosen so that
    the design position is the static equilibrium under the design axle loads. Cached per
    (parameters, model file), since it closes the loops with Newton's method."""
    key = (repr(params), source.text, str(source.path))
    if key not in _SPRING_CACHE:
        _SPRING_CACHE[key] = _compute_spring_settings(params, source)
    return _SPRING_CACHE[key]


def _compute_spring_settings(params, source):
    kin = SuspensionKinematics(source, params.front.guide_length_l_m)
    loads = design_axle_loads_N(params)
    settings = {}
    for axle, wheel_rate, axle_load in (("front", params.front.wheel_rate_Npm, loads["front"]),
                                        ("rear", params.rear.wheel_rate_Npm, loads["rear"])):
        for side in SIDES:
            ratio, dmz_dz = kin.motion_ratios(axle, side)
            ratio = abs(ratio)
            design_length = kin.spring_length(axle, side)
            # Virtual work at the design position, chassis fixed: the road's wheel load W moves
            # with the wheel centre, gravity acts on the corner's parts at their mass centres,
            # the spring along its length:  W - g d(sum m z)/dz - F_spring |dL/dz| = 0.
            force = (axle_load / 2 - GRAVITY_MPS2 * dmz_dz) / ratio
            stiffness = wheel_rate / ratio ** 2
            settings[(axle, side)] = SpringSetting(
                stiffness_Npm=stiffness, free_length_m=design_length + force / stiffness,
                design_length_m=design_length, motion_ratio=ratio, design_force_N=force)
    return settings


def add_car(plant, params: CarParameters | None = None, *, model_path=None,
            fixed_chassis=False) -> CarModel:
    """Adds the car to a discrete ``plant`` (not yet finalized) and returns its handles.
    ``params`` are trusted: checked where they entered (a scene's load)."""
    params = params or CarParameters()
    source = model_source(params, model_path)
    instance = load_car(plant, source, fixed_chassis=fixed_chassis)
    springs = spring_settings(params, source)
    for (axle, side), setting in springs.items():
        prefix = "" if axle == "front" else "rear_"
        body_a, p_a = frame_point(plant, f"{prefix}spring_upper_seat_{side}", instance)
        body_b, p_b = frame_point(plant, f"{prefix}spring_lower_seat_{side}", instance)
        plant.AddForceElement(LinearSpringDamper(
            body_a, p_a, body_b, p_b, setting.free_length_m, setting.stiffness_Npm, 0.0))
    for side in SIDES:
        for name_a, name_b in LOOP_CLOSURES:
            body_a, p_a = frame_point(plant, name_a.format(side=side), instance)
            body_b, p_b = frame_point(plant, name_b.format(side=side), instance)
            plant.AddBallConstraint(body_a, p_a, body_b, p_b)
    rack = plant.GetJointByName("rack_slide", instance)
    rack_actuator = plant.AddJointActuator("rack_servo", rack)
    rack_actuator.set_controller_gains(RACK_SERVO_GAINS)
    mount_actuators = []
    f = params.front
    if f.top_mount_stiffness_Npm > 0:
        gains = PdControllerGains(p=f.top_mount_stiffness_Npm, d=f.top_mount_damping_Nspm)
        for side in SIDES:
            for axis in "xyz":
                name = f"top_mount_{axis}_{side}"
                if not plant.HasJointNamed(name, instance):
                    raise ValueError(
                        f"front.top_mount_stiffness_Npm = {f.top_mount_stiffness_Npm} asks for a "
                        f"compliant top mount, but the model {source.label} has no joint "
                        f"'{name}' (generate it from these parameters)")
                actuator = plant.AddJointActuator(name, plant.GetJointByName(name, instance))
                actuator.set_controller_gains(gains)
                mount_actuators.append(actuator)
    rates = cached_arm_rates(params, source) if (
        params.front.anti_roll_bar_Nm_per_rad > 0 or params.rear.anti_roll_bar_Nm_per_rad > 0) \
        else {}
    return CarModel(params=params, plant=plant, instance=instance, source=source,
                    springs=springs, rack_actuator=rack_actuator,
                    top_mount_actuators=mount_actuators, arm_rates=rates)


def strut_overlap(car: CarModel, context, side):
    """Overlap d between guide and piston (m): d = l - s, s the prismatic coordinate."""
    prismatic = car.joint(f"strut_prismatic_{side}")
    return car.params.front.guide_length_l_m - prismatic.get_translation(context)


def loop_closure_error(car: CarModel, plant_context):
    """Largest distance (m) between the points the ball-joint and tie-rod constraints join."""
    plant, world = car.plant, car.plant.world_frame()
    worst = 0.0
    for side in SIDES:
        for a, b in LOOP_CLOSURES:
            pa = plant.CalcPointsPositions(
                plant_context, plant.GetFrameByName(a.format(side=side), car.instance),
                np.zeros(3), world)
            pb = plant.CalcPointsPositions(
                plant_context, plant.GetFrameByName(b.format(side=side), car.instance),
                np.zeros(3), world)
            worst = max(worst, float(np.linalg.norm(pa - pb)))
    return worst


def forward_speed_index(car: CarModel):
    """The entry of the plant's state [q; v] holding the chassis' velocity along world x (its
    floating joint's translational velocity, in the world frame): the car's speed when it
    drives straight along x."""
    plant, chassis = car.plant, car.body("chassis")
    if chassis.index() not in plant.GetFloatingBaseBodies():
        raise ValueError("forward_speed_index: the chassis is not a floating body")
    # A floating body's velocities: [ω_WB; v_WB], both in the world frame.
    return plant.num_positions() + chassis.floating_velocities_start_in_v() + 3


def rolling_momentum_scale(car: CarModel):
    """SAP's momentum scale (``systems.sap_ballast.sap_momentum_scale``) of the car rolling
    straight ahead at 1 m/s in its design position, the wheels spinning at 1/R (√kg): the
    car's ‖p̃‖ per unit speed (38.6 √kg for the default car: 643 √J at 60 km/h)."""
    plant = car.plant
    context = plant.CreateDefaultContext()
    v = np.zeros(plant.num_velocities())
    v[forward_speed_index(car) - plant.num_positions()] = 1.0
    spin = 1.0 / car.params.tyre.unloaded_radius_m
    for axle, side in (("front", "left"), ("front", "right"), ("rear", "left"),
                       ("rear", "right")):
        v[car.joint(f"wheel_{axle}_{side}_spin").velocity_start()] = spin
    plant.SetVelocities(context, v)
    return sap_momentum_scale(plant, context)
