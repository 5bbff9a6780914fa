"""The steering system of a hands-off scene: the steering wheel and column geared to the rack
(q_rack = c·θ), so the free rack carries the wheel's inertia I/c² and the column's friction.

Two forms with the same dynamics (``COLUMN_FORMS``):

``reflected`` (the default)
    No extra body or constraint: an actuator on the rack joint gets the wheel as its rotor,
    with rotor inertia I and gear ratio ρ = 1/c, and Drake adds the reflected inertia ρ²·I = I/c² to
    the rack's diagonal entry of the mass matrix (``JointActuator.set_default_rotor_inertia``,
    ``set_default_gear_ratio``; SAP steps with that mass matrix). The column's friction torque
    T(ω, Δθ) is the rack force T/c at the rack velocity c·ω (power T·ω = F·v), so it is one
    translation pair on the rack joint with the column's law in rack units: threshold
    velocity c·Δv_θ, creep c·Δmax_θ and static force μs·N' with N' = T_s/(c·μs). It joins the
    car's own StrutFriction system (one more strut), and its actuator is the car's.
``coupler``
    The earlier form, kept as the reference the reflected one is tested against: the wheel as a
    body on a revolute joint in its own model instance ``steering_column``, tied to the rack by a
    SAP coupler constraint, its friction a rotation pair on that joint.
"""

import dataclasses

import numpy as np
from pydrake.multibody.tree import RevoluteJoint, SpatialInertia, UnitInertia

from drake_car.law.friction.frd import StrutFrictionParameters
from drake_car.model.car import RACK_SERVO_GAINS
from drake_car.systems.friction_pairs import Strut, declare_pairs
from drake_car.systems.gain_schedule import MIN_GAIN

COLUMN_FORMS = ("reflected", "coupler")
COLUMN_MASS_KG = 1e-3  # the coupler form's column body: its inertia about its axis is the wheel's;
# its weight (10 mN) is negligible (the earlier 1 kg added 9.8 N at the chassis origin)
# The column's dry friction: the FRD law with μd/μs = 0.8 and a threshold and creep scaled to a
# steering wheel (1 mrad/s, 1 mrad); its static torque is μs N r with N r from the scene.
COLUMN_LAW = StrutFrictionParameters(mu_s=1.0, mu_d=0.8, dv_rotation_radps=1e-3,
                                     dmax_rotation_rad=1e-3)


def column_law_at_rack(c):
    """``COLUMN_LAW`` seen at the rack (the reflected form's translation pair); ``c``: the
    car's rack gain (m of rack per steering-wheel radian)."""
    return dataclasses.replace(COLUMN_LAW, dv_translation_mps=c * COLUMN_LAW.dv_rotation_radps,
                               dmax_translation_m=c * COLUMN_LAW.dmax_rotation_rad)


def add_steering_column(plant, car, hands_off, *, scheme, form="reflected"):
    """Adds the column (before Finalize); returns its friction pairs (a list, possibly
    empty). In the reflected form the pair's actuator belongs to the car's model instance and
    is added right now (after any actuator added before)."""
    if form not in COLUMN_FORMS:
        raise ValueError(f"add_steering_column: form {form!r} must be one of {COLUMN_FORMS}")
    inertia = hands_off.steering_wheel_inertia_kgm2
    gain = car.params.front.rack_gain_m_per_rad
    rack = car.joint("rack_slide")
    if form == "reflected":
        pairs = ([] if hands_off.friction_torque_Nm == 0
                 else declare_pairs(plant, rack, None, scheme, prefix="steering_column"))
        # Drake 1.51 takes a joint's reflected inertia from the last actuator added to the
        # joint (measured: with the rotor on the first of two actuators on a prismatic joint
        # the mass matrix lacks it), so the rotor goes on the last: the column's pair or the
        # servo.
        rotor = pairs[-1].actuator if pairs else car.rack_actuator
        rotor.set_default_rotor_inertia(inertia)
        rotor.set_default_gear_ratio(1.0 / gain)
        return pairs
    instance = plant.AddModelInstance("steering_column")
    unit = UnitInertia(inertia / COLUMN_MASS_KG, inertia / COLUMN_MASS_KG,
                       inertia / COLUMN_MASS_KG)
    body = plant.AddRigidBody("steering_column", instance,
                              SpatialInertia(COLUMN_MASS_KG, np.zeros(3), unit))
    joint = plant.AddJoint(RevoluteJoint("steering_column", car.body("chassis").body_frame(),
                                         body.body_frame(), [1.0, 0.0, 0.0]))
    plant.AddCouplerConstraint(rack, joint, gear_ratio=gain)
    if hands_off.friction_torque_Nm == 0:
        return []
    return declare_pairs(plant, None, joint, scheme, prefix="steering_column")


def column_strut(pairs, hands_off, c):
    """The column's friction as a strut of the strut-friction system: its static torque
    μs N r = ``friction_torque_Nm`` (r = 1 m) on the column, or the force
    ``friction_torque_Nm`` / c on the rack (the reflected form's translation pair; ``c`` the
    car's rack gain)."""
    torque = hands_off.friction_torque_Nm
    if pairs[0].kind == "translation":
        law = column_law_at_rack(c)
        return Strut(pairs, "steering", rod_radius_m=1.0,
                     constant_normal_force_N=torque / (c * law.mu_s),
                     params=law)
    return Strut(pairs, "steering", rod_radius_m=1.0,
                 constant_normal_force_N=torque / COLUMN_LAW.mu_s, params=COLUMN_LAW)


def release_schedule(release_s):
    """The rack servo's gains: held until ``release_s``, then let go (gains and effort limit
    at their floor: the servo applies no force)."""
    return [(0.0, RACK_SERVO_GAINS.p, RACK_SERVO_GAINS.d, np.inf),
            (release_s, 0.0, 0.0, MIN_GAIN)]
