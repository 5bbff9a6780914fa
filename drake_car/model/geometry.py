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
    down = _unit([math.tan(math.radians(f.caster_deg)),
                  s * math.tan(math.radians(f.strut_inclination_deg)), -1.0])
    up = -down
    outward = _unit(np.array([0.0, s, 0.0]) - s * up[1] * up)
    lower = f.spring_lower_seat_below_top_m
    upper = f.spring_upper_seat_below_top_m
    spring_lower_seat = top_mount + lower * down + f.spring_offset_m * outward
    spring_upper_seat = (top_mount + upper * down
                         + (f.spring_offset_m - (lower - upper)
                            * math.tan(math.radians(f.spring_inclination_deg))) * outward)
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


def rpy_z_to(direction):
    """Roll-pitch-yaw (fixed-axis x-y-z) of a frame whose z axis points along ``direction``."""
    d = _unit(direction)
    pitch = math.atan2(math.hypot(d[0], d[1]), d[2])
    yaw = math.atan2(d[1], d[0])
    return (0.0, pitch, yaw)
