"""Friction pairs on the joints of any discrete plant: which joints, which actuators, where the
normal force comes from. ``StrutFriction`` (strut_friction.py) works on these."""

import dataclasses

from pydrake.multibody.tree import PdControllerGains

KINDS = ("translation", "rotation")


@dataclasses.dataclass
class FrictionPair:
    kind: str  # "translation" (a PrismaticJoint) or "rotation" (a RevoluteJoint)
    joint: object
    actuator: object


@dataclasses.dataclass
class Strut:
    """One cylindrical joint with friction: its pairs (translation first) and where their normal
    force comes from. ``label`` prefixes the diagnostics' names ("left" -> "left_translation_v").

    Normal force (eq. 4) comes from the reaction of ``normal_force_joint`` (default: the first
    pair's joint); ``overlap_m`` = (d0, d1) and ``moment_arm_offset_m`` = (a0, a1) give the
    overlap d(q) = d0 + d1·q and the offset a(q) = a0 + a1·q from the joint frame Jc to the
    overlap's middle, q that joint's position. ``rod_radius_m`` is r of eq. (6) (the rotation
    pair's moment arm). ``constant_normal_force_N`` replaces the reaction (rigs);
    ``initial_normal_force_N`` is used before the first step, when Drake's sampled reaction port
    still reads zero. ``mirrored``: the strut is the mirror image of a reference strut (a car's
    right strut of its left), so eq. (4) is evaluated in the reference's reflected frame: the
    moment enters with the opposite sign (``law.friction.frd`` says why: the paper's vector form
    is not invariant under a reflection)."""

    pairs: list
    label: str = ""
    normal_force_joint: object = None
    overlap_m: tuple = (0.1, 0.0)
    moment_arm_offset_m: tuple = (0.0, 0.0)
    rod_radius_m: float = 0.011
    constant_normal_force_N: float | None = None
    initial_normal_force_N: float | None = None
    params: object = None
    mirrored: bool = False


def declare_pairs(plant, prismatic=None, revolute=None, scheme="fast", prefix="friction"):
    """Adds one actuator per pair to ``plant`` (before Finalize); fast-scheme actuators get PD
    gains (overwritten every step by the system). Returns the list of FrictionPair."""
    pairs = []
    for kind, joint in zip(KINDS, (prismatic, revolute)):
        if joint is None:
            continue
        actuator = plant.AddJointActuator(f"{prefix}_{kind}", joint)
        if scheme == "fast":
            actuator.set_controller_gains(PdControllerGains(p=1.0, d=1.0))
        pairs.append(FrictionPair(kind, joint, actuator))
    return pairs
