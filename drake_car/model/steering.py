"""The steering system of a hands-off scene: the steering wheel and column as a body turning
about the body's x axis, geared to the rack (q_rack = c·θ, a SAP coupler constraint), so the
free rack carries the wheel's inertia I/c² and the column's friction. Added in its own model
instance, so the car's generalized positions are those of every other scene."""

import numpy as np
from pydrake.multibody.tree import RevoluteJoint, SpatialInertia, UnitInertia

from drake_car.law.friction.frd import StrutFrictionParameters
from drake_car.model.car import RACK_SERVO_GAINS
from drake_car.systems.friction_pairs import Strut, declare_pairs
from drake_car.systems.gain_schedule import MIN_GAIN

COLUMN_MASS_KG = 1.0  # the column's own mass; only its inertia about its axis matters
# The column's dry friction: the FRD law with μd/μs = 0.8 and a threshold and creep scaled to a
# steering wheel (1 mrad/s, 1 mrad); its static torque is μs N r with N r from the scene.
COLUMN_LAW = StrutFrictionParameters(mu_s=1.0, mu_d=0.8, dv_rotation_radps=1e-3,
                                     dmax_rotation_rad=1e-3)


def add_steering_column(plant, car, hands_off, *, scheme):
    """Adds the column (before Finalize); returns its friction pairs (a list, possibly
    empty)."""
    instance = plant.AddModelInstance("steering_column")
    inertia = hands_off.steering_wheel_inertia_kgm2
    unit = UnitInertia(inertia / COLUMN_MASS_KG, inertia / COLUMN_MASS_KG,
                       inertia / COLUMN_MASS_KG)
    body = plant.AddRigidBody("steering_column", instance,
                              SpatialInertia(COLUMN_MASS_KG, np.zeros(3), unit))
    joint = plant.AddJoint(RevoluteJoint("steering_column", car.body("chassis").body_frame(),
                                         body.body_frame(), [1.0, 0.0, 0.0]))
    plant.AddCouplerConstraint(car.joint("rack_slide"), joint,
                               gear_ratio=hands_off.rack_gain_m_per_rad)
    if hands_off.friction_torque_Nm == 0:
        return []
    return declare_pairs(plant, None, joint, scheme, prefix="steering_column")


def column_strut(pairs, hands_off):
    """The column's friction as a strut of the strut-friction system: its static torque
    μs N r = ``friction_torque_Nm`` (r = 1 m)."""
    return Strut(pairs, "steering", rod_radius_m=1.0,
                 constant_normal_force_N=hands_off.friction_torque_Nm / COLUMN_LAW.mu_s,
                 params=COLUMN_LAW)


def release_schedule(release_s):
    """The rack servo's gains: held until ``release_s``, then let go (gains and effort limit
    at their floor: the servo applies no force)."""
    return [(0.0, RACK_SERVO_GAINS.p, RACK_SERVO_GAINS.d, np.inf),
            (release_s, 0.0, 0.0, MIN_GAIN)]
