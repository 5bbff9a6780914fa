"""The driver's stage of the build, car-specific: the path follower of a ``!PathFollower``
scene (``systems.path_driver.PathDriver`` on the manoeuvre's path, its laws from this car's
steering linkage and wheelbase), and the Diagram's ports for a driver connected from outside
(``build_diagram(scene, external_driver=True)``).

Exported ports of an external-driver Diagram (``EXTERNAL_INPUTS``, ``external_outputs``):

inputs
    ``rack_position_m`` (1): the rack's commanded position (m, in the rack's own direction:
    left + turns left for a rack ahead of the front axle, right for one behind it,
    ``model.geometry.steering_sign``; ``rack_per_steer_m_per_rad`` is signed to match, so a
    law built on it steers either car); the rack servo (the driver's hands and the column,
    ``model.car.RACK_SERVO_GAINS``) holds it, its damping acting on the rack's velocity.
    ``drive_torque_Nm`` (1, when the manoeuvre drives): the total drive torque at the driven
    wheels (N m: the front axle's, or the rear's with ``car.driven_axle: rear``), split equally
    by the open differential, clamped to the drive's ``max_wheel_torque_Nm`` and reduced by
    its rev limit.
outputs
    ``car_state``: the car's positions then velocities (the plant's state of the car's model
    instance: the floating chassis' quaternion, position (m), then every joint; its angular
    and translational velocity (rad/s, m/s), then every joint's rate).
    ``chassis_motion`` (11): x_m, y_m, z_m, roll_rad, pitch_rad, yaw_rad, yaw_rate_radps,
    speed_mps, sideslip_rad, ax_mps2, ay_mps2 (``model.channels.CAR_CHANNELS["chassis"]``,
    the chassis log's columns: the reference point on the ground between the front contact
    points).
    ``body_poses``, ``body_spatial_velocities``: the plant's, for any other body.
    ``tyre_loads_N`` (4): the wheels' vertical loads fl, fr, rl, rr (N).
    ``tyre_diagnostics`` (4 x ``systems.tyre.DIAGNOSTIC_FIELDS``): per wheel its slips,
    forces and moments, named by ``CarDiagram.tyre.diagnostic_names()`` ("Fx_fl_N",
    "Fy_fl_N", "Mz_fl_Nm", "kappa_fl", ...).
    ``strut_friction_diagnostics`` (when the scene has strut friction; 8 per pair): per pair
    v, creep, beta, mu1, mu, phase, N, friction, named by
    ``CarDiagram.friction.diagnostic_names()`` (``systems.strut_friction``): the law's values
    at the step's start. In the fast scheme the force the plant applies is the law's
    linearisation solved inside SAP (its PD actuators ``strut_friction_*``):
    ``plant.get_net_actuation_output_port(car.instance)`` gives it.
"""

import numpy as np
from pydrake.systems.primitives import (
    ConstantVectorSource, MatrixGain, Multiplexer, Saturation)

from drake_car.model.car import model_source
from drake_car.model.drive import rolling_radius
from drake_car.model.geometry import SIDES
from drake_car.model.kinematics import SuspensionKinematics
from drake_car.model.channels import CAR_CHANNELS
from drake_car.scene.raw import SceneError
from drake_car.scene.scene import OpenDifferential, PathFollower
from drake_car.scene.launch import drive_torque_limit_Nm
from drake_car.sim.drive_wiring import add_governor
from drake_car.systems.path_driver import (
    PathDriver, SpeedLaw, SteeringLaw, preview_gain_rad_per_m, speed_gains)

EXTERNAL_INPUTS = ("rack_position_m", "drive_torque_Nm")
CHASSIS_COLUMNS = CAR_CHANNELS["chassis"]
# Rack travel either side of centre for the linkage's ratio (m): small against the stroke.
RATIO_RACK_M = 1e-3


_RATIOS = {}


def _ratio(params):
    kinematics = SuspensionKinematics(model_source(params), params.front.guide_length_l_m)
    steer = []
    for rack in (-RATIO_RACK_M, RATIO_RACK_M):
        kinematics.set_rack(rack)
        for side in SIDES:
            kinematics.solve("front", side, 0.0)
        steer.append(np.mean([kinematics.front_state(s, 0.0).steer_deg for s in SIDES]))
    return 2 * RATIO_RACK_M / np.radians(steer[1] - steer[0])


def rack_per_steer_m_per_rad(params):
    """Rack travel per mean road-wheel angle at centre (m/rad; > 0: rack left, wheels left):
    the steering linkage's ratio, by central differences on the closed loops (chassis held,
    wheels at design height). Cached per car."""
    key = repr(params)
    if key not in _RATIOS:
        _RATIOS[key] = float(_ratio(params))
    return _RATIOS[key]


def steering_law(params, follower: PathFollower) -> SteeringLaw:
    """The path follower's law on this car: k = 4 ζ² l / L² (``systems.path_driver``)."""
    wheelbase = params.wheelbase_m
    return SteeringLaw(
        preview_m=follower.preview_m,
        gain_rad_per_m=preview_gain_rad_per_m(follower.preview_m, wheelbase,
                                              follower.damping_ratio),
        wheelbase_m=wheelbase, rack_per_steer_m_per_rad=rack_per_steer_m_per_rad(params),
        rack_limit_m=params.front.rack_stroke_m)


def speed_law(params, target_mps, *, time_constant_s=0.5, max_torque_Nm=None):
    """A speed-holding law for this car (``systems.path_driver.speed_gains``): the car's mass
    with its wheels' spin inertia on the front wheels' rolling radius; the torque clamp the
    default drive's (``OpenDifferential.max_wheel_torque_Nm``) unless given."""
    radius = rolling_radius(params)
    mass = params.mass.total_mass_kg + 4 * params.mass.wheel_spin_inertia_kgm2 / radius ** 2
    gain, integral = speed_gains(mass, radius, time_constant_s)
    limit = OpenDifferential().max_wheel_torque_Nm if max_torque_Nm is None else max_torque_Nm
    return SpeedLaw(target_mps=target_mps, gain_Nm_per_mps=float(gain), integral_time_s=integral,
                    max_torque_Nm=limit)


def add_path_driver(builder, scene, motion_port):
    """The scene's ``!PathFollower`` on its manoeuvre's path; returns the driver (its rack
    output commands the rack; the drive follows the timeline's speed profile)."""
    follower = scene.steering
    driver = builder.AddSystem(PathDriver(
        scene.manoeuvre.centre_line(), steering_law(scene.car, follower),
        motion_columns=CHASSIS_COLUMNS, period_s=follower.period_s))
    driver.set_name("path_follower")
    builder.Connect(motion_port, driver.chassis_motion_input_port())
    return driver


def rack_command(builder, position_port=None):
    """The rack servo's desired state [position; 0] from a position; returns (the
    multiplexer's position input, its output). The zero desired velocity makes the servo's
    damping act on the rack's velocity (a hand on the wheel)."""
    stack = builder.AddSystem(Multiplexer([1, 1]))
    stack.set_name("rack_command")
    zero = builder.AddSystem(ConstantVectorSource([0.0]))
    zero.set_name("rack_command_rate")
    builder.Connect(zero.get_output_port(0), stack.get_input_port(1))
    if position_port is not None:
        builder.Connect(position_port, stack.get_input_port(0))
    return stack.get_input_port(0), stack.get_output_port(0)


def drive_torque_input(builder, plant, car, scene, wiring):
    """The open differential on a torque from outside; returns the input to export."""
    drive = scene.drive
    if not isinstance(drive, OpenDifferential):
        raise SceneError("build_diagram(external_driver=True): the drive must be "
                         f"!OpenDifferential (a driver gives a torque); the scene's is "
                         f"!{type(drive).__name__}")
    split = builder.AddSystem(MatrixGain(np.full((2, 1), 0.5)))
    split.set_name("open_differential")
    limit = 0.5 * drive_torque_limit_Nm(scene)
    clamp = builder.AddSystem(Saturation(np.full(2, -limit), np.full(2, limit)))
    clamp.set_name("drive_torque_limit")
    builder.Connect(split.get_output_port(), clamp.get_input_port())
    torque = add_governor(builder, plant, car, scene, drive, clamp.get_output_port())
    wiring.connect("drive", feedforward=torque)
    return split.get_input_port()


def _loads(builder, tyre):
    """The tyre system's vertical loads alone (its ``tyre_loads`` holds the radial deflections
    (m) after them)."""
    port = tyre.GetOutputPort("tyre_loads")
    wheels = port.size() // 2
    select = builder.AddSystem(MatrixGain(np.eye(wheels, port.size())))
    select.set_name("tyre_loads_N")
    builder.Connect(port, select.get_input_port())
    return select.get_output_port()


def external_outputs(builder, plant, car, tyre, friction, motion_port):
    """name -> output port of what an external driver or controller reads (module
    docstring)."""
    ports = {"car_state": plant.get_state_output_port(car.instance),
             "chassis_motion": motion_port,
             "body_poses": plant.get_body_poses_output_port(),
             "body_spatial_velocities": plant.get_body_spatial_velocities_output_port(),
             "tyre_loads_N": _loads(builder, tyre),
             "tyre_diagnostics": tyre.GetOutputPort("tyre_diagnostics")}
    if friction is not None:
        ports["strut_friction_diagnostics"] = friction.GetOutputPort("diagnostics")
    return ports


def manoeuvre_outcome(scene, history, log):
    """What a path manoeuvre's run did against what it asks (``outcome`` of
    ``scene.paths``), or None for other manoeuvres; a warning on ``log`` when it failed."""
    judge = getattr(scene.manoeuvre, "outcome", None)
    if judge is None:
        return None
    outcome = judge(scene, history)
    if not (outcome.get("inside") or outcome.get("within")):
        log.warning("%s: the run did not do what its !%s asks: %s", scene.name,
                    outcome["manoeuvre"], {k: v for k, v in outcome.items() if k != "manoeuvre"})
    return outcome
