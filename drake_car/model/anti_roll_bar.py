"""The anti-roll bars: a linear coupling of the left and right wheels' travel, applied as
generalized forces on the suspension arms' pivot joints.

A bar of roll stiffness K_φ (N m/rad) across a track t stores V = ½ k_w (z_L - z_R)² with
k_w = K_φ / t², z the wheel-centre travels; with z = r q near the design position (r the
travel per arm angle, from the closed-loop kinematics), the arms' generalized forces are
τ = -∂V/∂q, linear in the positions: one matrix from the plant's state, applied by a Drake
MatrixGain into the plant's applied-generalized-force port (no Python in the step). The bar
acts on the body through the arms' pivots, as a real bar's bushings do. Applied explicitly,
it is stable for dt < 2/ω with ω = sqrt(2 k_w / m), m the corner's unsprung mass (about 0.1 s
here: ``time_step_limit_s``)."""

import math

import numpy as np

from drake_car.model.geometry import SIDES
from drake_car.model.kinematics import SuspensionKinematics

# The joint whose angle carries each axle's wheel travel.
ARM_JOINTS = {"front": "lower_arm_pivot_{side}", "rear": "trailing_arm_pivot_{side}"}


def _stiffness(params, axle):
    group = params.front if axle == "front" else params.rear
    return group.anti_roll_bar_Nm_per_rad / group.track_m ** 2


def arm_rates(params, source):
    """(axle, side) -> wheel-centre travel per arm angle r = dz/dq (m/rad) at design."""
    kin = SuspensionKinematics(source, params.front.guide_length_l_m)
    rates = {}
    for axle, pattern in ARM_JOINTS.items():
        for side in SIDES:
            rates[(axle, side)] = 1.0 / kin.joint_rate(axle, side, pattern.format(side=side))
    return rates


def anti_roll_bar_gain(plant, car, rates):
    """The matrix G with τ = G x (x the plant's state [q; v], τ its generalized forces), or
    None when the car has no bar."""
    params = car.params
    nq, nv = plant.num_positions(), plant.num_velocities()
    gain = np.zeros((nv, nq + nv))
    any_bar = False
    for axle, pattern in ARM_JOINTS.items():
        k = _stiffness(params, axle)
        if k == 0:
            continue
        any_bar = True
        joints = [car.joint(pattern.format(side=side)) for side in SIDES]
        r = [rates[(axle, side)] for side in SIDES]
        for i, joint_i in enumerate(joints):
            for j, joint_j in enumerate(joints):
                sign = -1.0 if i == j else 1.0
                gain[joint_i.velocity_start(), joint_j.position_start()] += sign * k * r[i] * r[j]
    return gain if any_bar else None


def time_step_limit_s(params):
    """The explicit bar's largest stable step: 2/ω, ω = sqrt(2 k_w / m) per axle."""
    limits = []
    m = params.mass
    corner = {"front": m.front_wheel_kg + m.front_knuckle_kg + m.front_lower_arm_kg,
              "rear": m.rear_wheel_kg + m.rear_carrier_kg}
    for axle in ("front", "rear"):
        k = _stiffness(params, axle)
        if k > 0:
            limits.append(2.0 / math.sqrt(2 * k / corner[axle]))
    return min(limits) if limits else math.inf
