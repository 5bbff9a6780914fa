"""What a drive logs about the car body, the steering and the struts, as a LeafSystem whose
outputs feed Drake VectorLogSinks (the tyres' and the friction's own diagnostics ports are
logged directly). Only the groups a scene asks for get an output port and a logger."""

import math

from pydrake.common.value import Value
from pydrake.math import RigidTransform
from pydrake.multibody.math import SpatialVelocity
from pydrake.systems.framework import LeafSystem

from drake_car.model.geometry import SIDES

# Channel groups computed here, with their columns (SI units in the names).
CAR_CHANNELS = {
    "chassis": ("x_m", "y_m", "yaw_rad", "yaw_rate_radps", "speed_mps"),
    "steering": ("rack_m", "steer_fl_deg", "steer_fr_deg"),
    "struts": tuple(f"d_{s}_m" for s in SIDES) + tuple(f"rot_{s}_rad" for s in SIDES),
}


class CarChannels(LeafSystem):
    """Body, steering and strut channels of the car, one output port per group asked for.

    .. pydrake_system::

        name: CarChannels
        input_ports:
        - body_poses
        - body_spatial_velocities
        - plant_state
        output_ports:
        - chassis (if asked for)
        - steering (if asked for)
        - struts (if asked for)

    ``chassis``: x, y of the body origin (m), yaw (rad), yaw rate (rad/s, about world z),
    horizontal speed (m/s).
    ``steering``: rack position (m), steer angle of the front-left and front-right wheels
    relative to the body (deg, positive to the left). ``struts``: overlap d = l - s of the left
    and right strut (m) and the rod's rotation angle in its cylinder (rad).
    """

    def __init__(self, plant, car, groups, guide_length_l_m):
        super().__init__()
        unknown = [g for g in groups if g not in CAR_CHANNELS]
        if unknown:
            raise ValueError(f"CarChannels: unknown channel groups {unknown}; "
                             f"known: {list(CAR_CHANNELS)}")
        self._chassis = int(car.body("chassis").index())
        self._wheels = [int(car.body(f"wheel_front_{side}").index()) for side in SIDES]
        self._rack = car.joint("rack_slide").position_start()
        self._prismatic = [car.joint(f"strut_prismatic_{s}").position_start() for s in SIDES]
        self._revolute = [car.joint(f"strut_revolute_{s}").position_start() for s in SIDES]
        self._guide = float(guide_length_l_m)
        self._poses = self.DeclareAbstractInputPort("body_poses", Value[list[RigidTransform]]())
        self._velocities = self.DeclareAbstractInputPort(
            "body_spatial_velocities", Value[list[SpatialVelocity]]())
        self._state = self.DeclareVectorInputPort("plant_state", plant.num_multibody_states())
        calc = {"chassis": self._calc_chassis, "steering": self._calc_steering,
                "struts": self._calc_struts}
        for group in groups:
            self.DeclareVectorOutputPort(group, len(CAR_CHANNELS[group]), calc[group])

    def connect(self, builder, plant):
        builder.Connect(plant.get_body_poses_output_port(), self._poses)
        builder.Connect(plant.get_body_spatial_velocities_output_port(), self._velocities)
        builder.Connect(plant.get_state_output_port(), self._state)

    def _calc_chassis(self, context, output):
        pose = self._poses.Eval(context)[self._chassis]
        r = pose.rotation().matrix()
        p = pose.translation()
        wx, wy, wz, vx, vy, vz = self._velocities.Eval(context)[self._chassis].get_coeffs()
        output.SetFromVector([p[0], p[1], math.atan2(r[1, 0], r[0, 0]), wz,
                              math.hypot(vx, vy)])

    def _calc_steering(self, context, output):
        poses = self._poses.Eval(context)
        body = poses[self._chassis].rotation().matrix()
        values = [self._state.Eval(context)[self._rack]]
        for wheel in self._wheels:
            axis = body.T @ poses[wheel].rotation().matrix()[:, 1]  # spin axis in the body
            values.append(math.degrees(math.atan2(-axis[0], axis[1])))
        output.SetFromVector(values)

    def _calc_struts(self, context, output):
        x = self._state.Eval(context)
        output.SetFromVector([self._guide - x[i] for i in self._prismatic]
                             + [x[i] for i in self._revolute])
