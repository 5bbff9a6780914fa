"""Suspension kinematics with the chassis fixed: the rig Adams/Car users run first.

Each corner's loop-closure equations (lower ball joint, tie-rod ball joint) plus one
prescribed wheel-centre travel are solved by Newton's method on that corner's joint coordinates,
so the closure error is at round-off level, not at a simulator's constraint regularisation.
"""

import dataclasses
import math

import numpy as np
from pydrake.multibody.plant import MultibodyPlant

from drake_car.model.geometry import SIDES
from drake_car.model.loading import ModelFileError, ModelSource, load_car
from drake_car.law.errors import InputError


class KinematicsError(InputError):
    """The loops of a corner cannot be closed (geometry out of reach)."""


FRONT_JOINTS = ("lower_arm_pivot_{s}", "top_mount_joint_{s}", "strut_revolute_{s}",
                "strut_prismatic_{s}", "tie_rod_inner_{s}")
# Ball constraints that close each front corner's loops: (frame on one body, frame on the other).
LOOP_CLOSURES = (("ball_joint_arm_{side}", "ball_joint_knuckle_{side}"),
                 ("tie_rod_outer_{side}", "tie_rod_end_{side}"))


@dataclasses.dataclass
class CornerState:
    side: str
    wheel_travel_m: float
    camber_deg: float
    toe_deg: float  # toe-in positive
    steer_deg: float  # wheel heading, positive to the left
    caster_deg: float
    kingpin_deg: float
    strut_length_m: float
    overlap_m: float
    closure_error_m: float


class SuspensionKinematics:
    """Closes the front and rear loops of the car with its chassis welded to the world."""

    def __init__(self, source: ModelSource, guide_length_l_m: float):
        self.plant = MultibodyPlant(time_step=1e-3)
        self.instance = load_car(self.plant, source, fixed_chassis=True)
        self.plant.Finalize()
        self.context = self.plant.CreateDefaultContext()
        self.guide_length_l_m = guide_length_l_m
        plant, inst = self.plant, self.instance
        self._frame = lambda name: plant.GetFrameByName(name, inst)
        self._world = plant.world_frame()
        self._q_index = {}
        for side in SIDES:
            idx = []
            for pattern in FRONT_JOINTS:
                joint = plant.GetJointByName(pattern.format(s=side), inst)
                idx += range(joint.position_start(), joint.position_start() + joint.num_positions())
            self._q_index[("front", side)] = np.array(idx)
            joint = plant.GetJointByName(f"trailing_arm_pivot_{side}", inst)
            self._q_index[("rear", side)] = np.array([joint.position_start()])
        self._rack = plant.GetJointByName("rack_slide", inst)
        self.q = plant.GetPositions(self.context).copy()
        for side in SIDES:
            error = float(np.max(np.abs(self.closure_residual(side))))
            if error > 1e-6:
                raise ModelFileError(
                    f"{source.path or source.label}: the {side} front corner's loops do not close "
                    f"at the design position (error {error:.2e} m > 1e-6 m): the ball-joint or "
                    "tie-rod points of the two bodies they join do not coincide")
        self._design_wheel_z = {
            (axle, side): self._point(f"wheel_{axle}_{side}")[2]
            for axle in ("front", "rear") for side in SIDES}

    # -- evaluation ---------------------------------------------------------------------------
    def _point(self, frame_name):
        return self.plant.CalcPointsPositions(
            self.context, self._frame(frame_name), np.zeros(3), self._world).ravel()

    def _set(self, q):
        self.plant.SetPositions(self.context, q)

    def closure_residual(self, side):
        """The 6 loop-closure residuals of a front corner (m)."""
        return np.concatenate([
            self._point(a.format(side=side)) - self._point(b.format(side=side))
            for a, b in LOOP_CLOSURES])

    def _residual(self, axle, side, travel):
        z = self._point(f"wheel_{axle}_{side}")[2] - self._design_wheel_z[(axle, side)] - travel
        if axle == "rear":
            return np.array([z])
        return np.concatenate([self.closure_residual(side), [z]])

    def closure_jacobian(self, side, step=1e-7):
        """d(closure residual)/d(corner coordinates) at the current configuration."""
        idx = self._q_index[("front", side)]
        q0 = self.q.copy()
        self._set(q0)
        r0 = self.closure_residual(side)
        jac = np.zeros((r0.size, idx.size))
        for k, i in enumerate(idx):
            q = q0.copy()
            q[i] += step
            self._set(q)
            jac[:, k] = (self.closure_residual(side) - r0) / step
        self._set(q0)
        return jac

    # -- solving ------------------------------------------------------------------------------
    def set_rack(self, rack_m):
        self.q[self._rack.position_start()] = rack_m

    def solve(self, axle, side, travel_m, tol=1e-12, max_iterations=30):
        """Closes the corner's loops at the given wheel-centre travel (bump positive)."""
        idx = self._q_index[(axle, side)]
        step = 1e-7
        for _ in range(max_iterations):
            self._set(self.q)
            r = self._residual(axle, side, travel_m)
            if np.max(np.abs(r)) < tol:
                return self.q
            jac = np.zeros((r.size, idx.size))
            for k, i in enumerate(idx):
                q = self.q.copy()
                q[i] += step
                self._set(q)
                jac[:, k] = (self._residual(axle, side, travel_m) - r) / step
            dq = np.linalg.lstsq(jac, -r, rcond=None)[0]
            self.q[idx] += dq
        self._set(self.q)
        r = self._residual(axle, side, travel_m)
        if np.max(np.abs(r)) > 1e-9:
            raise KinematicsError(
                f"{axle} {side} corner: the loops do not close at wheel travel {travel_m:+.3f} m "
                f"(residual {np.max(np.abs(r)):.2e} m): the suspension geometry is out of reach")
        return self.q

    # -- measurements -------------------------------------------------------------------------
    def front_state(self, side, travel_m):
        plant, ctx = self.plant, self.context
        self._set(self.q)
        s = SIDES[side]
        wheel = plant.GetBodyByName(f"wheel_front_{side}", self.instance)
        axis = plant.EvalBodyPoseInWorld(ctx, wheel).rotation().matrix()[:, 1]  # spin axis
        outboard = s * axis
        camber = -math.degrees(math.asin(np.clip(outboard[2], -1, 1)))
        steer = math.degrees(math.atan2(-axis[0], axis[1]))
        ball = self._point(f"ball_joint_knuckle_{side}")
        top = self._point(f"top_mount_{side}")
        caster = math.degrees(math.atan2(ball[0] - top[0], top[2] - ball[2]))
        kingpin = math.degrees(math.atan2(s * (ball[1] - top[1]), top[2] - ball[2]))
        strut_length = float(np.linalg.norm(
            self._point(f"top_mount_{side}") - self._point(f"strut_lower_mount_{side}")))
        prismatic = plant.GetJointByName(f"strut_prismatic_{side}", self.instance)
        overlap = self.guide_length_l_m - prismatic.get_translation(ctx)
        return CornerState(side, travel_m, camber, -s * steer, steer, caster, kingpin,
                           strut_length, overlap, float(np.max(np.abs(self.closure_residual(side)))))

    def joint_rate(self, axle, side, joint_name, delta=1e-3):
        """d(joint position)/d(wheel-centre travel) at the design position (rad/m or m/m),
        by central differences on the closed loops."""
        joint = self.plant.GetJointByName(joint_name, self.instance)
        values = []
        for travel in (-delta, delta):
            self.solve(axle, side, travel)
            values.append(self.q[joint.position_start()])
        self.solve(axle, side, 0.0)
        return (values[1] - values[0]) / (2 * delta)

    def spring_length(self, axle, side):
        prefix = "" if axle == "front" else "rear_"
        return float(np.linalg.norm(self._point(f"{prefix}spring_upper_seat_{side}")
                                    - self._point(f"{prefix}spring_lower_seat_{side}")))

    def corner_bodies(self, axle, side):
        names = ([f"lower_arm_{side}", f"knuckle_{side}", f"strut_slider_{side}",
                  f"piston_rod_{side}", f"wheel_front_{side}", f"tie_rod_{side}"]
                 if axle == "front" else [f"trailing_arm_{side}", f"wheel_rear_{side}"])
        return [self.plant.GetBodyByName(n, self.instance) for n in names]

    def corner_centre_of_mass_z(self, axle, side):
        """Sum of m_i z_i over the corner's moving bodies (kg m)."""
        total = 0.0
        for body in self.corner_bodies(axle, side):
            pose = self.plant.EvalBodyPoseInWorld(self.context, body)
            p_com = pose.multiply(body.CalcCenterOfMassInBodyFrame(self.context))
            total += body.get_mass(self.context) * p_com[2]
        return total

    def motion_ratios(self, axle, side, delta=1e-3):
        """(dL_spring/dz_wheel, d(sum m z)/dz_wheel) at the design position, central differences."""
        values = []
        for travel in (-delta, delta):
            self.solve(axle, side, travel)
            values.append((self.spring_length(axle, side),
                           self.corner_centre_of_mass_z(axle, side)))
        self.solve(axle, side, 0.0)
        (l0, m0), (l1, m1) = values
        return (l1 - l0) / (2 * delta), (m1 - m0) / (2 * delta)
