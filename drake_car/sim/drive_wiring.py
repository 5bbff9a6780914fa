"""The drive's stage of the build: the drive torque on the driven axle's wheels (an open
differential's speed controller and rev limit, or the paper's prescribed rotation), all in
Drake's C++ primitives, and the driveshafts whose reaction the tyre system applies to the body."""

import numpy as np
from pydrake.systems.primitives import (
    Adder, ConstantVectorSource, MatrixGain, Multiplexer, Saturation, TrajectorySource)

from drake_car.model.drive import (
    differential_speed_gain, driven_axle, driven_wheel_carriers, open_differential_gain,
    rolling_radius)
from drake_car.scene.launch import drive_torque_limit_Nm
from drake_car.scene.manoeuvres import speed_trajectory, wheel_rotation_trajectory
from drake_car.scene.scene import OpenDifferential, PrescribedRotation
from drake_car.systems.driveshaft import Driveshafts


def driveshafts(plant, car, scene):
    """The driveshafts the tyre system applies (``systems.driveshaft``), or None: the drive
    torque is reacted by the body unless the scene drives no wheel or prescribes the rotation
    with the knuckles reacting it."""
    drive = scene.drive
    if not scene.manoeuvre.drives or (isinstance(drive, PrescribedRotation)
                                       and drive.reaction != "driveshaft"):
        return None
    return Driveshafts(plant, car.instance, car.drive_actuators, driven_wheel_carriers(car),
                       car.body("chassis"))


def add_drive(builder, plant, car, scene, wiring):
    """The drive torque on the driven wheels (the tyre system reacts it through the
    driveshafts, ``driveshafts``)."""
    timeline = scene.manoeuvre.timeline
    drive = scene.drive
    axle, _ = driven_axle(scene.car)
    if isinstance(drive, PrescribedRotation):
        command = builder.AddSystem(TrajectorySource(
            wheel_rotation_trajectory(timeline, rolling_radius(scene.car, axle)), 1))
        command.set_name("drive_command")
        wiring.connect("drive", desired=command.get_output_port(0))
    else:
        assert isinstance(drive, OpenDifferential)
        # Speed controller (all Drake C++ primitives): [plant state; v_ref; a_ref] -> the two
        # wheels' torques, each half the total, clamped.
        profile = builder.AddSystem(TrajectorySource(speed_trajectory(timeline)))
        profile.set_name("speed_profile")
        stack = builder.AddSystem(Multiplexer([plant.num_multibody_states(), 2]))
        stack.set_name("speed_controller_inputs")
        builder.Connect(plant.get_state_output_port(), stack.get_input_port(0))
        builder.Connect(profile.get_output_port(0), stack.get_input_port(1))
        gain = builder.AddSystem(MatrixGain(open_differential_gain(
            plant, car, speed_gain_Nm_per_mps=drive.speed_gain_Nm_per_mps)))
        gain.set_name("open_differential")
        limit = 0.5 * drive_torque_limit_Nm(scene)
        clamp = builder.AddSystem(Saturation(np.full(2, -limit), np.full(2, limit)))
        clamp.set_name("drive_torque_limit")
        builder.Connect(stack.get_output_port(0), gain.get_input_port())
        builder.Connect(gain.get_output_port(), clamp.get_input_port())
        torque = add_governor(builder, plant, car, scene, drive, clamp.get_output_port())
        wiring.connect("drive", feedforward=torque)


def add_governor(builder, plant, car, scene, drive, torque):
    """The rev limit: each wheel's torque less K/2 max(0, ω_diff - ω_limit)."""
    speed = builder.AddSystem(MatrixGain(differential_speed_gain(plant, car)))
    speed.set_name("differential_speed")
    builder.Connect(plant.get_state_output_port(), speed.get_input_port())
    top = scene.manoeuvre.timeline.speed_mps / rolling_radius(scene.car, driven_axle(scene.car)[0])
    offset = builder.AddSystem(ConstantVectorSource([-drive.rev_limit_ratio * top]))
    offset.set_name("rev_limit")
    over = builder.AddSystem(Adder(2, 1))
    over.set_name("overspeed")
    builder.Connect(speed.get_output_port(), over.get_input_port(0))
    builder.Connect(offset.get_output_port(0), over.get_input_port(1))
    positive = builder.AddSystem(Saturation([0.0], [np.inf]))
    positive.set_name("overspeed_positive")
    builder.Connect(over.get_output_port(0), positive.get_input_port())
    pull = builder.AddSystem(MatrixGain(np.full((2, 1), -0.5 * drive.governor_gain_Nm_per_radps)))
    pull.set_name("governor")
    builder.Connect(positive.get_output_port(), pull.get_input_port())
    total = builder.AddSystem(Adder(2, 2))
    total.set_name("drive_torque")
    builder.Connect(torque, total.get_input_port(0))
    builder.Connect(pull.get_output_port(), total.get_input_port(1))
    return total.get_output_port(0)
