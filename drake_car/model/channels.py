"""What a run logs about the car body, the steering, the struts, the energy and the compliant top
mounts, as a LeafSystem whose outputs feed Drake VectorLogSinks (the tyres' and the friction's
own diagnostics ports are logged directly). Only the groups asked for get an output port; its
calc runs only when a logger samples it."""

import math

import numpy as np

from pydrake.common.value import Value
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.multibody.math import SpatialAcceleration, SpatialVelocity
from pydrake.systems.framework import LeafSystem

from drake_car.model.geometry import SIDES, steering_sign

# Channel groups computed here, with their columns (SI units in the names).
CAR_CHANNELS = {
    "chassis": ("x_m", "y_m", "z_m", "roll_rad", "pitch_rad", "yaw_rad", "yaw_rate_radps",
                "speed_mps", "sideslip_rad", "ax_mps2", "ay_mps2"),
    "steering": ("rack_m", "rack_force_N", "steer_fl_rad", "steer_fr_rad",
                 "steering_wheel_torque_Nm"),
    "struts": tuple(f"d_{s}_m" for s in SIDES) + tuple(f"rot_{s}_rad" for s in SIDES),
    "energy": ("kinetic_J", "potential_J"),
    "top_mounts": tuple(f"top_mount_{a}_{s}_m" for s in SIDES for a in "xyz"),
    "ride": ("az_seat_mps2", "roll_acc_radps2", "pitch_acc_radps2"),
}
# Below this speed the sideslip angle is not defined (reported as 0).
SIDESLIP_MIN_SPEED_MPS = 0.5


class CarChannels(LeafSystem):
    """Body, steering, strut, energy and top-mount channels of the car, one output port per
    group asked for.

    .. pydrake_system::

        name: CarChannels
        input_ports:
        - body_poses
        - body_spatial_velocities
        - body_spatial_accelerations
        - plant_state
        - net_actuation
        output_ports:
        - chassis (if asked for)
        - steering (if asked for)
        - struts (if asked for)
        - energy (if asked for)
        - top_mounts (if asked for)
        - ride (if asked for)

    ``chassis``: position x, y, z of the body origin (m); roll, pitch, yaw (rad, fixed-axis
    x-y-z); yaw rate about world z (rad/s); horizontal speed (m/s); sideslip angle at the body
    origin, atan(v_y / v_x) in the body's heading frame (rad, 0 below 0.5 m/s); longitudinal
    and lateral acceleration of the body origin in the heading frame (m/s², lateral to the
    left +). ``steering``: rack position (m, left +), the force the steering servo applies to
    the rack (N, the steering system's load), steer angles of the front wheels relative to the
    body (rad, left +), and the torque the driver holds at the steering wheel, the rack force
    times the car's rack gain c (``front.rack_gain_m_per_rad``: T ω = F v with v = c ω; N m,
    towards a left turn +: the rack's sign flipped for a rack behind the axle; unassisted
    steering: no power assistance, the column's friction and the wheel's inertia not
    included). ``struts``: overlap d = l - s of the left and right strut (m) and the
    rod's rotation in its cylinder (rad). ``energy``: the plant's kinetic energy and the
    potential energy of gravity and the coil springs (J), the SAP helpers' bodies
    (``helper_instances``: the pacer, the ballast; decoupled from the car) left out.
    ``top_mounts``: the compliant mounts' deflections (m). ``ride``: the world-vertical
    acceleration of the car's seat point ``car.seat_point_m`` (``model.seat``: in V, the
    body's frame; m/s², gravity not included: a = a_o + α × r + ω × (ω × r)), and the body's
    angular acceleration about its own x (roll) and y (pitch) axes (rad/s²).
    """

    def __init__(self, plant, car, groups, *, helper_instances=()):
        super().__init__()
        unknown = [g for g in groups if g not in CAR_CHANNELS]
        if unknown:
            raise ValueError(f"CarChannels: unknown channel groups {unknown}; "
                             f"known: {list(CAR_CHANNELS)}")
        self._plant = plant
        self._car = car
        self._chassis = int(car.body("chassis").index())
        self._wheels = [int(car.body(f"wheel_front_{side}").index()) for side in SIDES]
        self._rack = car.joint("rack_slide").position_start()
        self._rack_actuator = [int(i) for i in plant.GetJointActuatorIndices(car.instance)].index(
            int(car.rack_actuator.index()))
        self._prismatic = [car.joint(f"strut_prismatic_{s}").position_start() for s in SIDES]
        self._revolute = [car.joint(f"strut_revolute_{s}").position_start() for s in SIDES]
        self._guide = float(car.params.front.guide_length_l_m)
        self._seat = np.asarray(car.params.seat_point_m, dtype=float)  # in V (model.seat)
        # The steering wheel turns left (+) as the road wheels do: the rack the same way for a
        # rack ahead of the axle, the other way behind it (geometry.steering_sign).
        self._rack_gain = (float(car.params.front.rack_gain_m_per_rad)
                           * steering_sign(car.params))
        self._mounts = []
        if "top_mounts" in groups:
            self._mounts = [car.joint(f"top_mount_{a}_{s}").position_start()
                            for s in SIDES for a in "xyz"]
        # The helpers' velocities, zeroed for the energies (their blocks of M are their own).
        self._helper_v = [plant.num_positions() + plant.get_joint(j).velocity_start() + k
                          for instance in helper_instances
                          for j in plant.GetJointIndices(instance)
                          for k in range(plant.get_joint(j).num_velocities())]
        self._plant_context = None
        self._poses = self.DeclareAbstractInputPort("body_poses", Value[list[RigidTransform]]())
        self._velocities = self.DeclareAbstractInputPort(
            "body_spatial_velocities", Value[list[SpatialVelocity]]())
        self._accelerations = self.DeclareAbstractInputPort(
            "body_spatial_accelerations", Value[list[SpatialAcceleration]]())
        self._state = self.DeclareVectorInputPort("plant_state", plant.num_multibody_states())
        self._actuation = self.DeclareVectorInputPort(
            "net_actuation", plant.num_actuated_dofs(car.instance))
        calc = {"chassis": self._calc_chassis, "steering": self._calc_steering,
                "struts": self._calc_struts, "energy": self._calc_energy,
                "top_mounts": self._calc_top_mounts, "ride": self._calc_ride}
        for group in groups:
            self.DeclareVectorOutputPort(group, len(CAR_CHANNELS[group]), calc[group])

    def connect(self, builder, plant):
        builder.Connect(plant.get_body_poses_output_port(), self._poses)
        builder.Connect(plant.get_body_spatial_velocities_output_port(), self._velocities)
        builder.Connect(plant.get_body_spatial_accelerations_output_port(),
                        self._accelerations)
        builder.Connect(plant.get_state_output_port(), self._state)
        builder.Connect(plant.get_net_actuation_output_port(self._car.instance),
                        self._actuation)

    def _calc_chassis(self, context, output):
        pose = self._poses.Eval(context)[self._chassis]
        rotation = pose.rotation()
        roll, pitch, yaw = RollPitchYaw(rotation).vector().tolist()
        p = pose.translation()
        wx, wy, wz, vx, vy, vz = self._velocities.Eval(context)[self._chassis].get_coeffs()
        _, _, _, ax, ay, _ = self._accelerations.Eval(context)[self._chassis].get_coeffs()
        c, s = math.cos(yaw), math.sin(yaw)
        forward, lateral = c * vx + s * vy, -s * vx + c * vy
        speed = math.hypot(vx, vy)
        sideslip = math.atan2(lateral, forward) if speed > SIDESLIP_MIN_SPEED_MPS else 0.0
        output.SetFromVector([p[0], p[1], p[2], roll, pitch, yaw, wz, speed, sideslip,
                              c * ax + s * ay, -s * ax + c * ay])

    def _calc_steering(self, context, output):
        poses = self._poses.Eval(context)
        body = poses[self._chassis].rotation().matrix()
        force = self._actuation.Eval(context)[self._rack_actuator]
        values = [self._state.Eval(context)[self._rack], force]
        for wheel in self._wheels:
            axis = body.T @ poses[wheel].rotation().matrix()[:, 1]  # spin axis in the body
            values.append(math.atan2(-axis[0], axis[1]))
        output.SetFromVector(values + [force * self._rack_gain])

    def _calc_ride(self, context, output):
        rotation = self._poses.Eval(context)[self._chassis].rotation().matrix()
        w = self._velocities.Eval(context)[self._chassis].rotational()
        acceleration = self._accelerations.Eval(context)[self._chassis]
        alpha, a_origin = acceleration.rotational(), acceleration.translational()
        r = rotation @ self._seat
        a_seat = a_origin + np.cross(alpha, r) + np.cross(w, np.cross(w, r))
        alpha_body = rotation.T @ alpha
        output.SetFromVector([a_seat[2], alpha_body[0], alpha_body[1]])

    def _calc_struts(self, context, output):
        x = self._state.Eval(context)
        output.SetFromVector([self._guide - x[i] for i in self._prismatic]
                             + [x[i] for i in self._revolute])

    def _calc_energy(self, context, output):
        plant = self._plant
        if self._plant_context is None:
            self._plant_context = plant.CreateDefaultContext()
        pc = self._plant_context
        x = np.array(self._state.Eval(context))
        x[self._helper_v] = 0.0
        plant.SetPositionsAndVelocities(pc, x)
        output.SetFromVector([plant.EvalKineticEnergy(pc), plant.EvalPotentialEnergy(pc)])

    def _calc_top_mounts(self, context, output):
        x = self._state.Eval(context)
        output.SetFromVector([x[i] for i in self._mounts])
