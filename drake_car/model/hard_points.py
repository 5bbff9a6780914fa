"""A car from its hard points: the form a suspension engineer fills from their drawings, as
Adams/Car's templates and Chrono's ``ChMacPhersonStrut`` (its ``PointId`` list, a JSON file per
car) take it, and what the model derives from it.

The car file (YAML, loaded by ``scene.car_file``) states every value:

- ``front``: the left front McPherson corner's hard points (the right one is its mirror image
  in y) — the wheel centre, the lower arm's front and rear pivots and its ball joint, the
  strut's top mount (on the body) and lower mount (its clamp on the knuckle), the spring's upper
  and lower seats, the tie rod's inner (rack) and outer (steering arm) ends —, the damper's
  inside (rod guide below the top mount, guide length ``l``, rod radius ``r``: no drawing point
  shows them), and the rates at the wheel with their units in the names;
- ``mass``: the whole car's mass, centre of gravity (``cog_behind_front_axle_m``,
  ``cog_height_m`` above the ground) and moments of inertia about it — the whole car's, as a
  car is weighed and swung, not the sprung mass's — and the parts' masses;
- ``wheelbase_m``, ``driven_axle``, ``rear`` (the rear axle as trailing arms:
  ``model.parameters.RearSuspensionParameters``; its heights in the car file's frame) and
  ``tyre`` (``TyreVerticalParameters``);
- ``seat_point_m`` (the one key a file may leave out): the floor under the driver's seat,
  where the ride study measures comfort (``model.seat``); left out, it is estimated from the
  car's size [EST] and said so wherever it runs (``scene.borrowed``).

Frame: ISO 8855 / Chrono's, x forward, y left, z up, z = 0 on the ground under the car as
drawn; the x origin anywhere. The model's vehicle frame V (``model.geometry``) has its origin
on the ground under the front axle with the tyres touching the road unloaded, so every point
(and the rear's heights) moves by (-x_wheel_centre, 0, R0 - z_wheel_centre), R0 the tyre's
unloaded radius: drawn at ride height (the wheel centre at the loaded radius), the car settles
back onto the drawing's heights. ``to_parameters`` turns the file into the one type everything
downstream reads (``CarParameters``) exactly: the generator places every point where the file
puts it, to round-off (tests/test_hard_points.py).
"""

import dataclasses
import math
import typing

import numpy as np

from drake_car.law.checks import ParameterError, checked, nonnegative, one_of, positive
from drake_car.model.corners import COG_HEIGHT_MIN_M, highest_cog_m
from drake_car.model.geometry import (
    centre_of_mass, parallel_axis, part_inertias, strut_cross_axes)
from drake_car.model.parameters import (
    DRIVEN_AXLES, MIN_ARM_SPAN_M, CarParameters, FrontSuspensionParameters, MassParameters,
    RearSuspensionParameters, TyreVerticalParameters, check_inertia, check_passenger_car_mass)
from drake_car.model.seat import check_seat_point, estimated_seat_point_m

NAN = float("nan")


def _point():
    return dataclasses.field(default_factory=list)


# The front hard points, in the order an engineer reads them off the drawing.
FRONT_POINTS = ("wheel_centre_m", "lower_arm_front_pivot_m", "lower_arm_rear_pivot_m",
                "ball_joint_m", "strut_top_mount_m", "strut_lower_mount_m",
                "spring_upper_seat_m", "spring_lower_seat_m", "tie_rod_inner_m",
                "tie_rod_outer_m")
# [EST] floors below which a part is no part: a lower arm's two bushes at least 50 mm apart
# (production arms: 200-400 mm); a tie rod at least 100 mm long (rack end at ~0.3 m from the
# centre, steering arm at ~0.6 m).
MIN_BUSH_SPACING_M = 0.05
MIN_TIE_ROD_M = 0.1


@dataclasses.dataclass
class FrontHardPoints:
    """The left front corner: points [x, y, z] (m) in the car file's frame."""

    wheel_centre_m: typing.List[float] = _point()
    lower_arm_front_pivot_m: typing.List[float] = _point()
    lower_arm_rear_pivot_m: typing.List[float] = _point()
    ball_joint_m: typing.List[float] = _point()
    strut_top_mount_m: typing.List[float] = _point()
    strut_lower_mount_m: typing.List[float] = _point()
    spring_upper_seat_m: typing.List[float] = _point()
    spring_lower_seat_m: typing.List[float] = _point()
    tie_rod_inner_m: typing.List[float] = _point()
    tie_rod_outer_m: typing.List[float] = _point()
    # The damper inside the strut (paper Fig. 2): the rod guide this far below the top mount
    # along the strut, the guide length l (the overlap d of guide and piston as drawn), the rod
    # radius r.
    guide_below_top_mount_m: float = NAN
    guide_length_l_m: float = NAN
    rod_radius_r_m: float = NAN
    # Rates: the wheel rate (the spring's rate at the wheel centre: the model sets the spring
    # from it and the corner's own motion ratio), the damper's coefficient along the strut,
    # the anti-roll bar (roll moment per roll angle of the axle).
    wheel_rate_Npm: float = NAN
    strut_damping_Nspm: float = NAN
    anti_roll_bar_Nm_per_rad: float = NAN
    # Top mount: 0 N/m is rigid; else an elastomer mount (FrontSuspensionParameters).
    top_mount_stiffness_Npm: float = NAN
    top_mount_damping_Nspm: float = NAN
    top_mount_body_kg: float = NAN
    top_mount_link_kg: float = NAN
    rack_stroke_m: float = NAN
    rack_gain_m_per_rad: float = NAN  # rack travel per steering-wheel radian (c-factor)

    def check(self):
        for name in FRONT_POINTS:
            _point_check(self, name)
        positive(self, "guide_below_top_mount_m", "guide_length_l_m", "rod_radius_r_m",
                 "wheel_rate_Npm", "rack_stroke_m", "top_mount_body_kg", "top_mount_link_kg",
                 "rack_gain_m_per_rad")
        nonnegative(self, "strut_damping_Nspm", "anti_roll_bar_Nm_per_rad",
                    "top_mount_stiffness_Npm", "top_mount_damping_Nspm")
        p = {name: np.array(getattr(self, name), dtype=float) for name in FRONT_POINTS}
        if not p["wheel_centre_m"][1] > 0:
            raise ParameterError("wheel_centre_m", self.wheel_centre_m,
                                 "must have y > 0: the points are the left corner's (y left)")
        ball, top, lower = p["ball_joint_m"], p["strut_top_mount_m"], p["strut_lower_mount_m"]
        if not top[2] - ball[2] >= 0.2:
            raise ParameterError(
                "ball_joint_m", self.ball_joint_m,
                f"lies {top[2] - ball[2]:+.3f} m below strut_top_mount_m: a McPherson strut "
                "carries the knuckle down from the top mount to the ball joint, at least 0.2 m "
                "below it")
        if not ball[2] < lower[2] < top[2]:
            raise ParameterError(
                "strut_lower_mount_m", self.strut_lower_mount_m,
                "must lie between the ball joint and the top mount in height: the strut "
                "clamps onto the knuckle above the ball joint")
        spacing = float(np.linalg.norm(p["lower_arm_rear_pivot_m"] - p["lower_arm_front_pivot_m"]))
        if not spacing >= MIN_BUSH_SPACING_M:
            raise ParameterError(
                "lower_arm_rear_pivot_m", self.lower_arm_rear_pivot_m,
                f"is {spacing:.3f} m from lower_arm_front_pivot_m; the arm's pivot axis needs "
                f"its bushes at least {MIN_BUSH_SPACING_M:g} m apart")
        axis = (p["lower_arm_rear_pivot_m"] - p["lower_arm_front_pivot_m"]) / spacing
        reach = ball - p["lower_arm_front_pivot_m"]
        arm = float(np.linalg.norm(reach - (reach @ axis) * axis))
        if not arm >= MIN_ARM_SPAN_M:
            raise ParameterError(
                "ball_joint_m", self.ball_joint_m,
                f"is {arm:.3f} m from the lower arm's pivot axis; an arm reaches at least "
                f"{MIN_ARM_SPAN_M:g} m from its pivots to its ball joint")
        tie = float(np.linalg.norm(p["tie_rod_outer_m"] - p["tie_rod_inner_m"]))
        if not tie >= MIN_TIE_ROD_M:
            raise ParameterError("tie_rod_outer_m", self.tie_rod_outer_m,
                                 f"is {tie:.3f} m from tie_rod_inner_m; a tie rod is at least "
                                 f"{MIN_TIE_ROD_M:g} m long")
        down = (lower - top) / np.linalg.norm(lower - top)
        if not (p["spring_upper_seat_m"] - top) @ down < (p["spring_lower_seat_m"] - top) @ down:
            raise ParameterError("spring_upper_seat_m", self.spring_upper_seat_m,
                                 "must lie above spring_lower_seat_m along the strut axis")
        if not p["tie_rod_inner_m"][1] > 0:
            raise ParameterError("tie_rod_inner_m", self.tie_rod_inner_m,
                                 "must have y > 0 (the left rack end)")
        return self


@dataclasses.dataclass
class WholeCarMass:
    """The whole car's mass, centre of gravity and inertia (as weighed and swung), and its
    parts' masses (the parts of ``MassParameters``)."""

    total_mass_kg: float = NAN
    cog_behind_front_axle_m: float = NAN
    cog_height_m: float = NAN  # above the ground, in the car file's frame
    # About the whole car's centre of gravity, about axes parallel to x, y, z (roll, pitch,
    # yaw); the products of inertia are taken as zero.
    inertia_kgm2: typing.List[float] = _point()
    front_wheel_kg: float = NAN
    front_knuckle_kg: float = NAN
    front_lower_arm_kg: float = NAN
    piston_rod_kg: float = NAN
    strut_slider_kg: float = NAN
    tie_rod_kg: float = NAN
    rack_kg: float = NAN
    rear_wheel_kg: float = NAN
    rear_carrier_kg: float = NAN
    wheel_spin_inertia_kgm2: float = NAN

    def check(self):
        positive(self, *PART_MASSES, "total_mass_kg", "cog_behind_front_axle_m",
                 "cog_height_m")
        check_passenger_car_mass(self, "total_mass_kg")
        check_inertia(self, "inertia_kgm2")
        return self


PART_MASSES = ("front_wheel_kg", "front_knuckle_kg", "front_lower_arm_kg", "piston_rod_kg",
               "strut_slider_kg", "tie_rod_kg", "rack_kg", "rear_wheel_kg", "rear_carrier_kg",
               "wheel_spin_inertia_kgm2")
# FrontHardPoints' values CarParameters.front takes as they are.
FRONT_AS_GIVEN = ("guide_below_top_mount_m", "guide_length_l_m", "rod_radius_r_m",
                  "wheel_rate_Npm", "strut_damping_Nspm", "anti_roll_bar_Nm_per_rad",
                  "top_mount_stiffness_Npm", "top_mount_damping_Nspm", "top_mount_body_kg",
                  "top_mount_link_kg", "rack_stroke_m", "rack_gain_m_per_rad")


@dataclasses.dataclass
class HardPointCar:
    """A car file: the car from its hard points (module docstring)."""

    mass: WholeCarMass = dataclasses.field(default_factory=WholeCarMass)
    wheelbase_m: float = NAN
    driven_axle: str = "front"
    front: FrontHardPoints = dataclasses.field(default_factory=FrontHardPoints)
    rear: RearSuspensionParameters = dataclasses.field(default_factory=RearSuspensionParameters)
    tyre: TyreVerticalParameters = dataclasses.field(default_factory=TyreVerticalParameters)
    # [x, y, z] (m) in the file's frame; [] or left out: estimated (``model.seat``). A list,
    # not Optional[List]: drake 1.51's YAML reader cannot make an Optional list.
    seat_point_m: typing.List[float] = dataclasses.field(default_factory=list)

    def check(self):
        """The values one by one and the points as a McPherson corner; the derived car is
        checked with the scene (``CarParameters.check``, ``scene.car_limits``)."""
        for group in ("mass", "front", "rear", "tyre"):
            checked(getattr(self, group), group)
        positive(self, "wheelbase_m")
        one_of(self, "driven_axle", DRIVEN_AXLES)
        if self.seat_point_m:
            _point_check(self, "seat_point_m")
        if not self.mass.cog_behind_front_axle_m < self.wheelbase_m:
            raise ParameterError(
                "mass.cog_behind_front_axle_m", self.mass.cog_behind_front_axle_m,
                f"must lie inside the wheelbase_m = {self.wheelbase_m:g} m (else the front "
                "axle load is negative)")
        highest = highest_cog_m(2 * self.front.wheel_centre_m[1], self.rear.track_m)
        if not COG_HEIGHT_MIN_M <= self.mass.cog_height_m <= highest:
            raise ParameterError(
                "mass.cog_height_m", self.mass.cog_height_m,
                f"must lie in [{COG_HEIGHT_MIN_M:g}, {highest:.3f}] m: a road car's centre of "
                "gravity, at most half its mean track high (a static stability factor T/(2h) "
                ">= 1: full-size vans average 1.12, passenger cars 1.41, NHTSA DOT HS 809 868)")
        params = to_parameters(self)
        if params.parts_mass_kg() >= self.mass.total_mass_kg:
            raise ParameterError("mass.total_mass_kg", self.mass.total_mass_kg,
                                 f"must exceed the parts' mass {params.parts_mass_kg():.1f} kg")
        sprung = params.mass.sprung_inertia_kgm2
        if not all(value > 0 for value in sprung) or any(
                value > sum(sprung) - value for value in sprung):
            raise ParameterError(
                "mass.inertia_kgm2", self.mass.inertia_kgm2,
                f"leaves the body (the car less its parts, which add their own inertia about "
                f"the centre of gravity) {[round(v, 1) for v in sprung]} kg m², not a rigid "
                "body's moments: the whole car's inertia is too small for its parts")
        if self.seat_point_m:
            check_seat_point(params, given=self.seat_point_m)
        return self


MAX_POINT_M = 10.0  # no road car's hard point lies this far from its file's origin (m)


def _point_check(group, name):
    value = getattr(group, name)
    if not isinstance(value, list) or len(value) != 3:
        raise ParameterError(name, value, "must be given as [x, y, z] (m)")
    for i, entry in enumerate(value):
        if not (isinstance(entry, (int, float)) and not isinstance(entry, bool)
                and math.isfinite(entry)):
            raise ParameterError(f"{name}[{i}]", entry, "must be a finite number")
        if abs(entry) > MAX_POINT_M:
            raise ParameterError(f"{name}[{i}]", entry, f"lies more than {MAX_POINT_M:g} m "
                                 "from the car file's origin: hard points are in m (in mm?)")


def frame_shift_m(car: HardPointCar):
    """What moves the car file's frame to the model's V: (-x_wc, 0, R0 - z_wc) (m)."""
    wheel = car.front.wheel_centre_m
    return np.array([-float(wheel[0]), 0.0, car.tyre.unloaded_radius_m - float(wheel[2])])


def to_parameters(car: HardPointCar) -> CarParameters:
    """The car in the parameters everything downstream reads: the points turned into the
    angles and lengths ``model.geometry`` places them from (the inverse of
    ``geometry.front_corner_points``, exact to round-off), the whole car's centre of gravity
    and inertia into the sprung mass's (the parts where the model puts them)."""
    h = car.front
    shift = frame_shift_m(car)
    p = {name: np.array(getattr(h, name), dtype=float) + shift for name in FRONT_POINTS}
    wheel, ball = p["wheel_centre_m"], p["ball_joint_m"]
    top, lower = p["strut_top_mount_m"], p["strut_lower_mount_m"]
    height = top[2] - ball[2]
    axis = lower - top
    length = float(np.linalg.norm(axis))
    down = axis / length
    outward, ahead = strut_cross_axes(-down, 1.0)
    seat_low, seat_up = p["spring_lower_seat_m"] - top, p["spring_upper_seat_m"] - top
    below_low, below_up = float(seat_low @ down), float(seat_up @ down)
    offset, offset_fa = float(seat_low @ outward), float(seat_low @ ahead)
    front = FrontSuspensionParameters(
        track_m=2.0 * float(wheel[1]),
        ball_joint_offset_b_m=float(wheel[1] - ball[1]),
        ball_joint_height_m=float(ball[2]),
        ball_joint_x_m=float(ball[0]),
        lower_arm_front_pivot_m=[float(v) for v in p["lower_arm_front_pivot_m"]],
        lower_arm_rear_pivot_m=[float(v) for v in p["lower_arm_rear_pivot_m"]],
        kingpin_inclination_deg=math.degrees(math.atan2(ball[1] - top[1], height)),
        caster_deg=math.degrees(math.atan2(ball[0] - top[0], height)),
        top_mount_height_m=float(top[2]),
        strut_inclination_deg=math.degrees(math.atan2(axis[1], -axis[2])),
        strut_caster_deg=math.degrees(math.atan2(axis[0], -axis[2])),
        strut_lower_mount_below_top_m=length,
        spring_lower_seat_below_top_m=below_low,
        spring_upper_seat_below_top_m=below_up,
        spring_offset_m=offset,
        spring_inclination_deg=math.degrees(math.atan2(
            offset - float(seat_up @ outward), below_low - below_up)),
        spring_offset_fore_aft_m=offset_fa,
        spring_inclination_fore_aft_deg=math.degrees(math.atan2(
            offset_fa - float(seat_up @ ahead), below_low - below_up)),
        rack_x_m=float(p["tie_rod_inner_m"][0]),
        rack_height_m=float(p["tie_rod_inner_m"][2]),
        rack_half_length_m=float(p["tie_rod_inner_m"][1]),
        tie_rod_outer_m=[float(v) for v in p["tie_rod_outer_m"]],
        **{name: getattr(h, name) for name in FRONT_AS_GIVEN})
    rear = dataclasses.replace(car.rear, **{
        name: getattr(car.rear, name) + float(shift[2])
        for name in ("pivot_height_m", "spring_lower_height_m", "spring_upper_height_m")})
    m = car.mass
    params = CarParameters(
        mass=MassParameters(total_mass_kg=m.total_mass_kg,
                            cog_to_front_axle_m=m.cog_behind_front_axle_m,
                            cog_to_rear_axle_m=car.wheelbase_m - m.cog_behind_front_axle_m,
                            **{name: getattr(m, name) for name in PART_MASSES}),
        front=front, rear=rear, tyre=dataclasses.replace(car.tyre),
        driven_axle=car.driven_axle)
    cog, inertia = sprung_mass_of(params, m.total_mass_kg, np.array(
        [-m.cog_behind_front_axle_m, 0.0, m.cog_height_m + shift[2]]), m.inertia_kgm2)
    params.mass.cog_to_front_axle_m = float(-cog[0])
    params.mass.cog_to_rear_axle_m = car.wheelbase_m - float(-cog[0])
    params.mass.sprung_cog_height_m = float(cog[2])
    params.mass.sprung_inertia_kgm2 = [float(v) for v in inertia]
    params.seat_point_m = (
        estimated_seat_point_m(params, CarParameters()) if not car.seat_point_m
        else [float(v) for v in np.array(car.seat_point_m, dtype=float) + shift])
    return params


def sprung_mass_of(params: CarParameters, total_mass_kg, whole_cog, whole_inertia):
    """(centre of mass, principal moments) of the body (the sprung mass: the whole car less
    every part ``geometry.part_inertias`` lists) from the whole car's: c_s = (M G - Σ m_i c_i)
    / m_s, I_s = I_G - Σ (I_i + m_i [|d_i|² 1 - d_i d_iᵀ]) - m_s [|d_s|² 1 - d_s d_sᵀ] with d
    the offsets from G; its diagonal (the body's products of inertia are not modelled)."""
    parts = part_inertias(params)
    parts_mass = sum(mass for mass, _, _ in parts)
    sprung_mass = total_mass_kg - parts_mass
    cog = (total_mass_kg * whole_cog - sum(mass * com for mass, com, _ in parts)) / sprung_mass
    inertia = np.diag(np.asarray(whole_inertia, dtype=float))
    for mass, com, own in parts:
        inertia = inertia - own - parallel_axis(mass, com - whole_cog)
    inertia = inertia - parallel_axis(sprung_mass, cog - whole_cog)
    return cog, np.diag(inertia)


def from_parameters(params: CarParameters) -> HardPointCar:
    """The car file of a car given by today's parameters: its points where the generator
    places them (in V: the wheel centre at the tyre's unloaded radius), the whole car's centre
    of gravity and inertia from the body's and the parts'. ``to_parameters`` of it gives
    ``params`` back to round-off."""
    from drake_car.model.geometry import front_corner_points
    points = front_corner_points(params, 1.0)
    m, f = params.mass, params.front
    given = {
        "wheel_centre_m": points.wheel_centre, "lower_arm_front_pivot_m": points.arm_front_pivot,
        "lower_arm_rear_pivot_m": points.arm_rear_pivot, "ball_joint_m": points.ball_joint,
        "strut_top_mount_m": points.top_mount, "strut_lower_mount_m": points.strut_lower_mount,
        "spring_upper_seat_m": points.spring_upper_seat,
        "spring_lower_seat_m": points.spring_lower_seat,
        "tie_rod_inner_m": points.tie_rod_inner, "tie_rod_outer_m": points.tie_rod_outer}
    cog = centre_of_mass(params)
    return HardPointCar(
        mass=WholeCarMass(total_mass_kg=m.total_mass_kg, cog_behind_front_axle_m=float(-cog[0]),
                          cog_height_m=float(cog[2]),
                          inertia_kgm2=[float(v) for v in whole_car_inertia_kgm2(params)],
                          **{name: getattr(m, name) for name in PART_MASSES}),
        wheelbase_m=params.wheelbase_m, driven_axle=params.driven_axle,
        front=FrontHardPoints(**{name: [float(v) for v in value] for name, value in given.items()},
                              **{name: getattr(f, name) for name in FRONT_AS_GIVEN}),
        rear=dataclasses.replace(params.rear), tyre=dataclasses.replace(params.tyre),
        seat_point_m=[float(v) for v in params.seat_point_m])


def whole_car_inertia_kgm2(params: CarParameters):
    """The whole car's moments of inertia about its centre of gravity at the design position
    (the diagonal: roll, pitch, yaw), from the body's and the parts'."""
    from drake_car.model.geometry import chassis_mass_and_com
    centre = centre_of_mass(params)
    mass, com = chassis_mass_and_com(params)
    inertia = np.diag(params.mass.sprung_inertia_kgm2) + parallel_axis(mass, com - centre)
    for mass, com, own in part_inertias(params):
        inertia = inertia + own + parallel_axis(mass, com - centre)
    return np.diag(inertia)
