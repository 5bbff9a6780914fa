"""Hard points of the car derived from its named parameters (pure numpy, no Drake).

Everything is in the vehicle frame V (origin on the ground midway between the front contact
points at the design position, x forward, y left, z up). ``side`` is +1 for left, -1 for right.
"""

import dataclasses
import math

import numpy as np

from drake_car.model.parameters import GRAVITY_MPS2, CarParameters

SIDES = {"left": 1.0, "right": -1.0}


def _unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


@dataclasses.dataclass
class FrontCornerPoints:
    wheel_centre: np.ndarray
    ball_joint: np.ndarray
    arm_front_pivot: np.ndarray
    arm_rear_pivot: np.ndarray
    top_mount: np.ndarray
    strut_axis_up: np.ndarray  # unit vector along the strut, from cylinder towards top mount
    guide: np.ndarray  # rod guide at the top of the cylinder (fixed to the cylinder)
    piston: np.ndarray  # piston at the design position (fixed to the rod)
    strut_lower_mount: np.ndarray  # strut clamp on the knuckle
    spring_lower_seat: np.ndarray
    spring_upper_seat: np.ndarray
    tie_rod_inner: np.ndarray
    tie_rod_outer: np.ndarray
    top_mount_axes: tuple  # the top mount's two tilt axes, both perpendicular to the strut


@dataclasses.dataclass
class RearCornerPoints:
    wheel_centre: np.ndarray
    pivot: np.ndarray
    spring_lower_seat: np.ndarray
    spring_upper_seat: np.ndarray


def strut_cross_axes(up, side):
    """Two unit vectors perpendicular to the strut axis ``up`` and to each other: ``outward``
    (in the plane of the axis and the car's y axis, pointing away from the car's centre plane)
    and ``ahead`` (pointing forward). The spring's offsets and inclinations are measured along
    them (``FrontSuspensionParameters.spring_*``)."""
    outward = _unit(np.array([0.0, side, 0.0]) - side * up[1] * up)
    return outward, side * _unit(np.cross(outward, up))


def front_corner_points(params: CarParameters, side: float) -> FrontCornerPoints:
    f = params.front
    s = side
    radius = params.tyre.unloaded_radius_m
    half_track = f.track_m / 2
    wheel_centre = np.array([0.0, s * half_track, radius])
    ball_joint = np.array(
        [f.ball_joint_x_m, s * (half_track - f.ball_joint_offset_b_m), f.ball_joint_height_m])
    height = f.top_mount_height_m - f.ball_joint_height_m
    top_mount = np.array([
        ball_joint[0] - height * math.tan(math.radians(f.caster_deg)),
        ball_joint[1] - s * height * math.tan(math.radians(f.kingpin_inclination_deg)),
        f.top_mount_height_m])
    down = _unit([math.tan(math.radians(f.strut_lean_back_deg())),
                  s * math.tan(math.radians(f.strut_inclination_deg)), -1.0])
    up = -down
    outward, ahead = strut_cross_axes(up, s)
    lower = f.spring_lower_seat_below_top_m
    upper = f.spring_upper_seat_below_top_m
    spring_lower_seat = (top_mount + lower * down + f.spring_offset_m * outward
                         + f.spring_offset_fore_aft_m * ahead)
    spring_upper_seat = (top_mount + upper * down
                         + (f.spring_offset_m - (lower - upper)
                            * math.tan(math.radians(f.spring_inclination_deg))) * outward
                         + (f.spring_offset_fore_aft_m - (lower - upper)
                            * math.tan(math.radians(f.spring_inclination_fore_aft_deg)))
                         * ahead)
    forward = _unit(np.array([1.0, 0.0, 0.0]) - up[0] * up)

    def mirror(p):
        return np.array([p[0], s * p[1], p[2]], dtype=float)

    return FrontCornerPoints(
        wheel_centre=wheel_centre,
        ball_joint=ball_joint,
        arm_front_pivot=mirror(f.lower_arm_front_pivot_m),
        arm_rear_pivot=mirror(f.lower_arm_rear_pivot_m),
        top_mount=top_mount,
        strut_axis_up=up,
        guide=top_mount + f.guide_below_top_mount_m * down,
        piston=top_mount + (f.guide_below_top_mount_m + f.guide_length_l_m) * down,
        strut_lower_mount=top_mount + f.strut_lower_mount_below_top_m * down,
        spring_lower_seat=spring_lower_seat,
        spring_upper_seat=spring_upper_seat,
        tie_rod_inner=np.array([f.rack_x_m, s * f.rack_half_length_m, f.rack_height_m]),
        tie_rod_outer=mirror(f.tie_rod_outer_m),
        top_mount_axes=(forward, _unit(np.cross(up, forward))),
    )


def rear_corner_points(params: CarParameters, side: float) -> RearCornerPoints:
    r = params.rear
    s = side
    x_axle = -params.wheelbase_m
    return RearCornerPoints(
        wheel_centre=np.array([x_axle, s * r.track_m / 2, params.tyre.unloaded_radius_m]),
        pivot=np.array([x_axle + r.pivot_ahead_of_axle_m, s * r.pivot_y_m, r.pivot_height_m]),
        spring_lower_seat=np.array(
            [x_axle + r.spring_ahead_of_axle_m, s * r.spring_y_m, r.spring_lower_height_m]),
        spring_upper_seat=np.array(
            [x_axle + r.spring_ahead_of_axle_m, s * r.spring_y_m, r.spring_upper_height_m]),
    )


# Moments of inertia of the parts about their centres of mass (kg m², about axes parallel to
# V's x, y, z) where the model file gives constants: [EST] of the order of the parts' sizes.
PART_INERTIA_KGM2 = {
    "steering_rack": (0.03, 0.001, 0.03),
    "lower_arm": (0.02, 0.02, 0.04),
    "knuckle": (0.15, 0.15, 0.08),
    "strut_slider": (1e-5, 1e-5, 1e-5),
    "top_mount": (1e-4, 1e-4, 1e-4),  # each of the compliant mount's three bodies
    "trailing_arm": (0.1, 0.3, 0.3),
}


def wheel_inertia_kgm2(params: CarParameters):
    """A wheel's moments about its centre (x, y = spin axis, z)."""
    spin = params.mass.wheel_spin_inertia_kgm2
    return (0.5 * spin + 0.02, spin, 0.5 * spin + 0.02)


def rod_inertia_kgm2(params: CarParameters):
    """The piston rod's moments about its centre, about its own axes (transverse, transverse,
    along the strut): a slender rod from the top mount to the piston."""
    m, f = params.mass, params.front
    length = f.guide_below_top_mount_m + f.guide_length_l_m
    transverse = m.piston_rod_kg * length ** 2 / 12
    return (transverse, transverse, 0.5 * m.piston_rod_kg * f.rod_radius_r_m ** 2)


def tie_rod_inertia_kgm2(params: CarParameters, points: "FrontCornerPoints"):
    """A tie rod's moments about its centre (as the model file gives them: about V's axes)."""
    length = float(np.linalg.norm(points.tie_rod_outer - points.tie_rod_inner))
    bending = params.mass.tie_rod_kg * length ** 2 / 12
    return (bending, 1e-4, bending)


def part_inertias(params: CarParameters):
    """(mass, centre of mass, 3x3 inertia about it in V) of every body but the chassis, in the
    order of ``part_centres_of_mass``, with the moments the model file gives each body."""
    def diagonal(moments, rotation=None):
        inertia = np.diag(np.asarray(moments, dtype=float))
        return inertia if rotation is None else rotation @ inertia @ rotation.T

    f = params.front
    inertias = [np.diag(PART_INERTIA_KGM2["steering_rack"])]
    for side in SIDES.values():
        p = front_corner_points(params, side)
        inertias += [diagonal(PART_INERTIA_KGM2["lower_arm"]),
                     diagonal(PART_INERTIA_KGM2["knuckle"]),
                     diagonal(PART_INERTIA_KGM2["strut_slider"]),
                     diagonal(rod_inertia_kgm2(params), _rotation_z_to(p.strut_axis_up)),
                     diagonal(wheel_inertia_kgm2(params)),
                     diagonal(tie_rod_inertia_kgm2(params, p))]
        if f.top_mount_stiffness_Npm > 0:
            inertias.append(3 * diagonal(PART_INERTIA_KGM2["top_mount"]))
        inertias += [diagonal(PART_INERTIA_KGM2["trailing_arm"]),
                     diagonal(wheel_inertia_kgm2(params))]
    return [(mass, com, inertia) for (mass, com), inertia
            in zip(part_centres_of_mass(params), inertias)]


def _rotation_z_to(direction):
    """The rotation matrix of ``rpy_z_to(direction)`` (fixed-axis x-y-z: Rz(yaw) Ry(pitch))."""
    _, pitch, yaw = rpy_z_to(direction)
    cy, sy, cp, sp = math.cos(yaw), math.sin(yaw), math.cos(pitch), math.sin(pitch)
    return (np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
            @ np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]]))


def parallel_axis(mass, offset):
    """The inertia a point mass at ``offset`` adds about the origin (3x3)."""
    d = np.asarray(offset, dtype=float)
    return mass * (float(d @ d) * np.eye(3) - np.outer(d, d))


def part_centres_of_mass(params: CarParameters):
    """(mass, centre of mass in V) of every body but the chassis, as the model file places
    them (``model.sdformat`` uses these for its inertial elements)."""
    m, f = params.mass, params.front
    parts = [(m.rack_kg, np.array([f.rack_x_m, 0.0, f.rack_height_m]))]
    for side in SIDES.values():
        p = front_corner_points(params, side)
        parts += [
            (m.front_lower_arm_kg, (p.arm_front_pivot + p.arm_rear_pivot + p.ball_joint) / 3),
            (m.front_knuckle_kg, 0.6 * p.wheel_centre + 0.4 * p.strut_lower_mount),
            (m.strut_slider_kg, p.guide),
            (m.piston_rod_kg, (p.top_mount + p.piston) / 2),
            (m.front_wheel_kg, p.wheel_centre),
            (m.tie_rod_kg, (p.tie_rod_inner + p.tie_rod_outer) / 2)]
        if f.top_mount_stiffness_Npm > 0:
            parts.append((f.top_mount_mass_kg(), p.top_mount))
        r = rear_corner_points(params, side)
        parts += [(m.rear_carrier_kg, 0.3 * r.pivot + 0.7 * r.wheel_centre),
                  (m.rear_wheel_kg, r.wheel_centre)]
    return parts


def chassis_mass_and_com(params: CarParameters):
    """The chassis (the sprung mass) with [ESC]'s CoG: ``cog_to_front_axle_m`` behind the
    front axle and ``sprung_cog_height_m`` high (CommonRoad's restatement gives both for the
    sprung mass); its mass is the total less the parts'."""
    return (params.mass.total_mass_kg - params.parts_mass_kg(),
            np.array([-params.mass.cog_to_front_axle_m, 0.0, params.mass.sprung_cog_height_m]))


def centre_of_mass(params: CarParameters):
    """The whole car's centre of mass in V at the design position."""
    chassis_mass, chassis_com = chassis_mass_and_com(params)
    total = chassis_mass * chassis_com
    for mass, com in part_centres_of_mass(params):
        total = total + mass * com
    return total / params.mass.total_mass_kg


def whole_car_cog_to_front_m(params: CarParameters):
    """The whole car's centre of mass behind the front axle (m), at the design position."""
    return float(-centre_of_mass(params)[0])


def design_axle_loads_N(params: CarParameters):
    """Static axle loads (N) of the car at its design position: its weight shared by the axles
    in proportion to the whole car's centre of mass (the sprung mass at [ESC]'s CoG, the parts
    where they are)."""
    weight = params.mass.total_mass_kg * GRAVITY_MPS2
    behind_front = -centre_of_mass(params)[0]
    return {"front": weight * (params.wheelbase_m - behind_front) / params.wheelbase_m,
            "rear": weight * behind_front / params.wheelbase_m}


def steering_sign(params: CarParameters):
    """+1 where the tie rod's outer end lies ahead of the steering axis (a rack ahead of the
    axle: rack travel to the left steers the wheels left), -1 where it lies behind (a rack
    behind the axle, as the BMW E90's: rack travel to the left steers them right). The rack
    pushes the outer end sideways; its moment about the (near vertical) steering axis has the
    sign of the end's lever ahead of the axis."""
    p = front_corner_points(params, 1.0)
    axis = p.top_mount - p.ball_joint
    at_end = p.ball_joint + (p.tie_rod_outer[2] - p.ball_joint[2]) / axis[2] * axis
    return 1.0 if p.tie_rod_outer[0] > at_end[0] else -1.0


def rpy_z_to(direction):
    """Roll-pitch-yaw (fixed-axis x-y-z) of a frame whose z axis points along ``direction``."""
    d = _unit(direction)
    pitch = math.atan2(math.hypot(d[0], d[1]), d[2])
    yaw = math.atan2(d[1], d[0])
    return (0.0, pitch, yaw)
