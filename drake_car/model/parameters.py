"""Parameters of the car: one real medium-class front-wheel-drive car with McPherson struts.

The car is the Ford Escort (North American, 1981-90): a C-segment, front-wheel-drive hatchback
with McPherson front struts. Its mass, centre of gravity, inertias, tracks, wheel rates, damping
and tyre stiffness are published in

  [ESC] R. W. Allen et al., "Vehicle Dynamic Stability and Rollover", NHTSA report DOT HS 807 956
        (1992), Table E-5; restated in SI by the CommonRoad vehicle models, "parameters_vehicle1"
        ("values are taken from a Ford Escort") and vehicleModels_commonRoad.pdf, Table 6.

No McPherson hard points of a C-segment car are published in a source we could reach. The hard
points below are therefore an *estimate*, marked [EST]: the strut geometry of

  [E90] SAE paper 2007-01-0818 (BMW E90 front McPherson strut), as tabulated in Project Chrono's
        BMW_E90_MacPhersonStrut model,

scaled laterally to the Escort's front track (factor 1.390/1.500) and with the caster set to the
Escort's published alignment value [ALN] (2.3 deg, 1990 Escort alignment specification).
Quantities the strut friction depends on (ball-joint offset ``b``, guide length ``l``, rod radius
``r``, spring inclination and offset, kingpin and caster angles) are named fields here; the model
file is generated from them (see ``drake_car.model.sdformat``).

Frames: the vehicle frame V has its origin on the ground midway between the front contact points
at the design position, x forward, y left, z up. All lengths in m, masses in kg, angles in degrees
where the name says ``_deg``.
"""

import dataclasses
import typing

from drake_car.law.checks import (
    ParameterError, checked, finite, nonnegative, one_of, positive)
from drake_car.model.seat import ESCORT_SEAT_POINT_M, check_seat_point

GRAVITY_MPS2 = 9.81


def _vector_check(group, name, positive_entries=False):
    values = getattr(group, name)
    if len(values) != 3:
        raise ParameterError(name, values, "must be a list of 3 numbers (x, y, z)")
    for i, value in enumerate(values):
        if not (isinstance(value, (int, float)) and not isinstance(value, bool)
                and value == value and abs(value) != float("inf")):
            raise ParameterError(f"{name}[{i}]", value, "must be a finite number")
        if positive_entries and not value > 0:
            raise ParameterError(f"{name}[{i}]", value, "must be > 0")


def _vector(*values):
    """A default for a list-valued field (YAML lists load into lists, not tuples)."""
    return dataclasses.field(default_factory=lambda: list(values))


@dataclasses.dataclass
class MassParameters:
    """Masses and inertias. Sources: [ESC] unless marked [EST]."""

    # [ESC] total (test) mass 84 slug.
    total_mass_kg: float = 1225.9
    # [ESC] the sprung mass's CoG to the front and rear axle (CommonRoad's parameters_vehicle1:
    # "distance from spring mass center of gravity to front/rear axle"); the whole car's CoG
    # follows with the parts where they are (model.geometry.centre_of_mass: 0.910 m).
    cog_to_front_axle_m: float = 0.884
    cog_to_rear_axle_m: float = 1.509
    # [ESC] CoG height of the sprung mass.
    sprung_cog_height_m: float = 0.594
    # [ESC] sprung-mass roll, pitch, yaw inertia about its CoG.
    sprung_inertia_kgm2: typing.List[float] = _vector(244.0, 1342.0, 1539.0)
    # [EST] split of [ESC]'s 65.7 kg unsprung mass per axle (32.85 kg per corner) among parts.
    front_wheel_kg: float = 15.0
    front_knuckle_kg: float = 13.0  # knuckle, hub, brake, strut cylinder
    front_lower_arm_kg: float = 3.0
    piston_rod_kg: float = 1.0
    strut_slider_kg: float = 0.05  # light link of the cylindrical joint (no physical part)
    tie_rod_kg: float = 0.6
    rack_kg: float = 2.0
    rear_wheel_kg: float = 15.0
    rear_carrier_kg: float = 17.0  # trailing arm, hub, brake
    # [EST] wheel-and-tyre spin inertia (solid-disc estimate 0.5 m R^2 scaled by 0.8).
    wheel_spin_inertia_kgm2: float = 0.6

    def check(self):
        positive(self, "total_mass_kg", "cog_to_front_axle_m", "cog_to_rear_axle_m",
                 "sprung_cog_height_m", "front_wheel_kg", "front_knuckle_kg",
                 "front_lower_arm_kg", "piston_rod_kg", "strut_slider_kg", "tie_rod_kg",
                 "rack_kg", "rear_wheel_kg", "rear_carrier_kg", "wheel_spin_inertia_kgm2")
        check_passenger_car_mass(self, "total_mass_kg")
        check_inertia(self, "sprung_inertia_kgm2")
        return self


# A passenger car's mass (kg): heavier than a heavy quadricycle (L7e: at most 450 kg unladen
# for carrying passengers, Regulation (EU) No 168/2013, Annex I) and at most the 3500 kg
# maximum authorised mass a category-B driving licence covers (Directive 2006/126/EC, Art. 4).
PASSENGER_CAR_MASS_KG = (450.0, 3500.0)


def check_passenger_car_mass(group, name):
    low, high = PASSENGER_CAR_MASS_KG
    value = getattr(group, name)
    if not low <= value <= high:
        raise ParameterError(name, value, f"must lie in [{low:g}, {high:g}] kg (a passenger "
                             "car: above a heavy quadricycle's 450 kg, EU 168/2013; within a "
                             "category-B licence's 3500 kg, Directive 2006/126/EC)")


def check_inertia(group, name):
    """Principal moments of inertia (about the x, y, z axes) of a rigid body: each positive and
    none larger than the sum of the other two (the triangle inequality every body's principal
    moments satisfy: I_x + I_y - I_z = 2 ∫ z² dm >= 0, and so on)."""
    _vector_check(group, name, positive_entries=True)
    moments = getattr(group, name)
    for i, axis in enumerate("xyz"):
        others = sum(moments) - moments[i]
        if moments[i] > others:
            raise ParameterError(name, moments, f"violates the triangle inequality: I_{axis} "
                                 f"= {moments[i]:g} exceeds the sum of the other two "
                                 f"({others:g}); no rigid body has such moments")


@dataclasses.dataclass
class FrontSuspensionParameters:
    """Left front McPherson corner; the right one is its mirror image in y."""

    # [ESC] front track.
    track_m: float = 1.390
    # [E90]-scaled [EST]: ball-joint offset b (paper Fig. 4): lateral distance from the ball-joint
    # centre to the line of action of the vertical road reaction (the wheel plane at design).
    ball_joint_offset_b_m: float = 0.080
    ball_joint_height_m: float = 0.2095  # [E90] 0.104 m below the wheel centre
    ball_joint_x_m: float = 0.026
    # [E90]-scaled [EST]: lower-arm pivots (front, rear) in V. Their x and y are [E90]'s
    # scaled; their heights are set for a front-drive car (the E90 is rear-driven): the axis
    # rises 22 mm towards the rear (the E90's falls 66 mm), so the wheel centre moves forward
    # 0.053 m per m of bump and the front axle has 21 % anti-lift under drive (torque reacted
    # by the body): [EST] production front-drive McPherson fronts have a small anti-lift
    # (0-30 %) rather than the E90-derived 75 % pro-lift, which lifted the struts ~26 mm in the
    # speed-up by the drive force alone. Mean height kept (0.221 m). Measured by
    # tests/test_car.py (kinematics rig).
    lower_arm_front_pivot_m: typing.List[float] = _vector(0.251, 0.320, 0.210)
    lower_arm_rear_pivot_m: typing.List[float] = _vector(-0.040, 0.346, 0.232)
    # [E90] kingpin inclination ~12 deg; [ALN] caster 2.3 deg. Top mount height [E90].
    kingpin_inclination_deg: float = 12.0
    caster_deg: float = 2.3
    top_mount_height_m: float = 0.7825
    # [E90] strut (damper) axis lateral inclination; it leans back by the caster angle.
    strut_inclination_deg: float = 9.5
    # The strut axis's lean back in the side view (deg): None leans it back by caster_deg (the
    # steering axis's, as here); a car given by hard points states its own.
    strut_caster_deg: typing.Optional[float] = None
    # [EST] strut internals (paper Fig. 2): guide 0.20 m below the top mount along the axis; guide
    # length l = overlap d between guide and piston at the design position; rod radius r (22 mm rod).
    guide_below_top_mount_m: float = 0.20
    guide_length_l_m: float = 0.14
    rod_radius_r_m: float = 0.011
    strut_lower_mount_below_top_m: float = 0.47  # strut clamp on the knuckle (strut length)
    # Coil spring: rate chosen so that the wheel rate equals [ESC]'s 21 898 N/m.
    wheel_rate_Npm: float = 21898.0
    spring_lower_seat_below_top_m: float = 0.26
    spring_upper_seat_below_top_m: float = 0.02
    spring_offset_m: float = 0.0  # lateral offset of the spring line from the strut axis (outboard +)
    spring_inclination_deg: float = 0.0  # spring line vs strut axis, lateral plane (top inboard +)
    # The same in the side view: the spring line's offset ahead of the strut axis (forward +)
    # and its inclination against it (top rearward +); zero here, a hard-point car's own.
    spring_offset_fore_aft_m: float = 0.0
    spring_inclination_fore_aft_deg: float = 0.0
    # Damper in the cylindrical joint: [ESC] 1459 N s/m at the wheel ÷ MR², MR = 0.938 the
    # strut's extension per unit wheel travel at design (the kinematics rig). The paper's
    # lubricated strut has 1250 N s/m and its dry struts none (scenes/paper_study.yaml).
    strut_damping_Nspm: float = 1657.0
    # [ESC] front auxiliary roll stiffness K_tsf = -9,500 ft lbf/rad, restated by CommonRoad's
    # parameters_vehicle1 as -12880.27 N m/rad (negative in its convention: roll stiffness
    # added to the springs' K_sf T²/2): the anti-roll bar, roll moment per roll angle (N m/rad).
    anti_roll_bar_Nm_per_rad: float = 12880.27
    # Top mount: 0 = rigid (the strut's universal joint hangs from the body, the paper's
    # model); > 0 = an elastomer mount of this translational stiffness (N/m, all directions),
    # three prismatic joints held by SAP's implicit PD (so a stiff mount stays stable at the
    # car's step). [EST] damping: 2000 N s/m, of the order of a rubber mount's loss factor
    # (~0.2) at the strut's ~10 Hz wheel hop with a 1e6 N/m mount.
    top_mount_stiffness_Npm: float = 0.0
    top_mount_damping_Nspm: float = 2000.0
    # [EST] the mount's inner sleeve and bearing; two light links carry the joints.
    top_mount_body_kg: float = 0.5
    top_mount_link_kg: float = 0.05

    def top_mount_mass_kg(self):
        """Mass of one compliant mount's moving parts (0 for the rigid mount)."""
        if self.top_mount_stiffness_Npm == 0.0:
            return 0.0
        return self.top_mount_body_kg + 2 * self.top_mount_link_kg

    def check(self):
        positive(self, "track_m", "ball_joint_height_m", "top_mount_height_m",
                 "guide_below_top_mount_m", "guide_length_l_m", "rod_radius_r_m",
                 "strut_lower_mount_below_top_m", "wheel_rate_Npm",
                 "spring_lower_seat_below_top_m", "rack_half_length_m", "rack_stroke_m",
                 "top_mount_body_kg", "top_mount_link_kg")
        finite(self, "ball_joint_offset_b_m", "ball_joint_x_m", "spring_offset_m",
               "spring_offset_fore_aft_m", "spring_upper_seat_below_top_m", "rack_x_m",
               "rack_height_m")
        nonnegative(self, "strut_damping_Nspm", "top_mount_stiffness_Npm",
                    "top_mount_damping_Nspm", "anti_roll_bar_Nm_per_rad")
        for name in ("lower_arm_front_pivot_m", "lower_arm_rear_pivot_m", "tie_rod_outer_m"):
            _vector_check(self, name)
        for name, limit, why in (
                ("kingpin_inclination_deg", 30.0, "production McPherson fronts: 8-16 deg"),
                ("strut_inclination_deg", 30.0, "production McPherson fronts: 5-15 deg"),
                ("caster_deg", 15.0, "production cars: 0-10 deg"),
                ("spring_inclination_deg", 20.0,
                 "beyond it the spring line leaves the strut's tower"),
                ("spring_inclination_fore_aft_deg", 20.0,
                 "beyond it the spring line leaves the strut's tower"),
                ("strut_caster_deg", 15.0, "production cars: 0-10 deg")):
            value = getattr(self, name)
            if value is None and name == "strut_caster_deg":
                continue
            finite(self, name)
            if not -limit < value < limit:
                raise ParameterError(name, value, f"must lie in (-{limit:g}, {limit:g}) deg "
                                     f"({why})")
        if not self.rod_radius_r_m < 0.05:
            raise ParameterError("rod_radius_r_m", self.rod_radius_r_m,
                                 "must be < 0.05 m (passenger-car rods: 10-14 mm)")
        if not 0.002 <= self.rack_gain_m_per_rad <= 0.05:
            raise ParameterError("rack_gain_m_per_rad", self.rack_gain_m_per_rad,
                                 "must lie in [0.002, 0.05] m/rad (passenger-car steering: "
                                 "rack travel per steering-wheel radian)")
        for name in ("spring_offset_m", "spring_offset_fore_aft_m"):
            if not abs(getattr(self, name)) < 0.1:
                raise ParameterError(name, getattr(self, name),
                                     "must lie in (-0.1, 0.1) m (the spring seat's radius)")
        return self

    def strut_lean_back_deg(self):
        """The strut axis's lean back in the side view (deg)."""
        return self.caster_deg if self.strut_caster_deg is None else self.strut_caster_deg
    # [EST] steering: rack ahead of the axle ("front steer"), tie rods from rack ends to arms.
    rack_x_m: float = 0.15
    # [EST] tie-rod inner (rack end) and outer points chosen by least squares over ±75 mm of
    # wheel travel for a small, monotone bump steer with toe-out in bump (roll understeer, as
    # production fronts are set up): toe -0.12 deg at +50 mm and +0.12 deg at -50 mm
    # (tests/test_car.py). The E90-derived points gave toe-out in both bump and rebound.
    rack_height_m: float = 0.2793
    rack_half_length_m: float = 0.29
    rack_stroke_m: float = 0.07
    tie_rod_outer_m: typing.List[float] = _vector(0.15, 0.595, 0.2646)
    # [EST] rack travel per steering-wheel radian (the pinion's pitch radius; 50 mm of rack per
    # pinion turn, within the 40-55 mm of unassisted passenger-car racks: the 0.07 m stroke in
    # 1.4 turns to lock). The steering wheel's torque is the rack's force times it; with the
    # linkage's road-wheel angle per rack travel it sets the overall steering ratio
    # (drake-car-handling reports it).
    rack_gain_m_per_rad: float = 0.008


@dataclasses.dataclass
class RearSuspensionParameters:
    """Rear axle: a twist beam modelled as two independent trailing arms (a simplification that
    leaves out the beam's roll stiffness)."""

    track_m: float = 1.423  # [ESC]
    pivot_ahead_of_axle_m: float = 0.45  # [EST]
    pivot_y_m: float = 0.55  # [EST]
    pivot_height_m: float = 0.30  # [EST]
    spring_ahead_of_axle_m: float = 0.05  # [EST] vertical spring, this far ahead of the axle
    spring_y_m: float = 0.55
    spring_lower_height_m: float = 0.25
    spring_upper_height_m: float = 0.60
    wheel_rate_Npm: float = 21898.0  # [ESC]
    wheel_damping_Nspm: float = 1459.0  # [ESC] damping at the wheel
    # [ESC] rear auxiliary roll stiffness K_tsr = 0 (the twist beam's share is in its rates).
    anti_roll_bar_Nm_per_rad: float = 0.0

    def check(self):
        positive(self, "track_m", "pivot_ahead_of_axle_m", "pivot_height_m", "wheel_rate_Npm",
                 "spring_upper_height_m")
        finite(self, "pivot_y_m", "spring_ahead_of_axle_m", "spring_y_m",
               "spring_lower_height_m")
        nonnegative(self, "wheel_damping_Nspm", "anti_roll_bar_Nm_per_rad")
        return self


@dataclasses.dataclass
class TyreVerticalParameters:
    # Unloaded radius of the 205/60R15 tyre of Pacejka, Tyre and Vehicle Dynamics, 2nd ed.
    # (2006), Table A3.1, whose Magic Formula data the project uses (urdf/tyres/).
    unloaded_radius_m: float = 0.313
    width_m: float = 0.205
    radial_stiffness_Npm: float = 189800.0  # [ESC]
    radial_damping_Nspm: float = 250.0  # [EST] ~5 % of critical for 33 kg unsprung mass

    def check(self):
        positive(self, "unloaded_radius_m", "width_m", "radial_stiffness_Npm")
        nonnegative(self, "radial_damping_Nspm")
        if not 0.1 <= self.unloaded_radius_m <= 1.0:
            raise ParameterError("unloaded_radius_m", self.unloaded_radius_m,
                                 "must lie in [0.1, 1] m (a road tyre)")
        return self


# The least lateral span of a front lower arm from its pivots to the ball joint (m).
MIN_ARM_SPAN_M = 0.1
# [EST] The least travel of the strut each way from its design position (m): a passenger
# car's wheel travels at least ±50 mm (the kinematics rig sweeps ±80 mm), the strut about as
# much at a motion ratio near 1.
MIN_STRUT_TRAVEL_M = 0.05
DRIVEN_AXLES = ("front", "rear")


@dataclasses.dataclass
class CarParameters:
    """Everything the model files and the plant are generated from."""

    mass: MassParameters = dataclasses.field(default_factory=MassParameters)
    front: FrontSuspensionParameters = dataclasses.field(default_factory=FrontSuspensionParameters)
    rear: RearSuspensionParameters = dataclasses.field(default_factory=RearSuspensionParameters)
    tyre: TyreVerticalParameters = dataclasses.field(default_factory=TyreVerticalParameters)
    # The axle the engine drives through an open differential (or the paper's prescribed
    # rotation): front for the Escort (a front-drive car), rear for a rear-drive car; the
    # torque is reacted by the body (driveshafts) and the speed measured at the other axle.
    driven_axle: str = "front"
    # The driver's seat point in V (m; the floor under the seat), where the ride study's
    # comfort a_w is measured: the Escort's [EST] (``model.seat``: its frame, source, checks).
    seat_point_m: typing.List[float] = _vector(*ESCORT_SEAT_POINT_M)

    @property
    def wheelbase_m(self):
        return self.mass.cog_to_front_axle_m + self.mass.cog_to_rear_axle_m

    def check(self):
        """Raises ParameterError naming the first parameter out of range (key path from the
        car: ``front.guide_length_l_m``)."""
        for group in ("mass", "front", "rear", "tyre"):
            checked(getattr(self, group), group)
        one_of(self, "driven_axle", DRIVEN_AXLES)
        f = self.front
        b = f.ball_joint_offset_b_m
        # The ball joint (at y = track/2 - b) sits outboard of both lower-arm pivots, the arm
        # spanning at least MIN_ARM_SPAN_M across, and inside the wheel: within the tyre's width
        # inboard of its centre plane, where the rim, hub and brake are [EST: a McPherson
        # ball joint lies in the rim's dish, 40-110 mm in; one tyre width bounds that].
        pivots_y = max(f.lower_arm_front_pivot_m[1], f.lower_arm_rear_pivot_m[1])
        arm_bound = f.track_m / 2 - pivots_y - MIN_ARM_SPAN_M
        bound = min(arm_bound, self.tyre.width_m)
        if not 0.0 <= b < bound:
            raise ParameterError(
                "front.ball_joint_offset_b_m", b,
                f"must lie in [0, {bound:.3f}) m: the ball joint sits inside the wheel (b < "
                f"tyre.width_m = {self.tyre.width_m:g} m) and outboard of the lower-arm pivots "
                f"(y = {pivots_y:g} m) by at least {MIN_ARM_SPAN_M:g} m (b < track/2 - "
                f"{pivots_y:g} - {MIN_ARM_SPAN_M:g} = {arm_bound:.3f} m)")
        if not f.top_mount_height_m > f.ball_joint_height_m + 0.2:
            raise ParameterError("front.top_mount_height_m", f.top_mount_height_m,
                                 "must be at least 0.2 m above front.ball_joint_height_m")
        if not (f.guide_below_top_mount_m + f.guide_length_l_m
                < f.strut_lower_mount_below_top_m + 0.1):
            raise ParameterError(
                "front.guide_length_l_m", f.guide_length_l_m,
                "is too long: the piston (guide + l) must stay within 0.1 m of the strut's "
                f"lower mount ({f.strut_lower_mount_below_top_m} m below the top mount)")
        if not f.guide_below_top_mount_m < f.strut_lower_mount_below_top_m:
            raise ParameterError(
                "front.guide_below_top_mount_m", f.guide_below_top_mount_m,
                "must be less than front.strut_lower_mount_below_top_m = "
                f"{f.strut_lower_mount_below_top_m:g} m: the rod guide tops the cylinder, "
                "which the knuckle clamps below it")
        if not f.guide_length_l_m >= MIN_STRUT_TRAVEL_M:
            raise ParameterError(
                "front.guide_length_l_m", f.guide_length_l_m,
                f"leaves the strut {f.guide_length_l_m:g} m of rebound travel (the piston "
                f"reaches the guide when d = 0); it must be >= {MIN_STRUT_TRAVEL_M:g} m "
                "(a wheel travels at least ±50 mm from its design position, the strut nearly "
                "as much)")
        if not f.spring_upper_seat_below_top_m < f.spring_lower_seat_below_top_m:
            raise ParameterError("front.spring_upper_seat_below_top_m",
                                 f.spring_upper_seat_below_top_m,
                                 "must be above (smaller than) front.spring_lower_seat_below_top_m")
        if not self.rear.spring_upper_height_m > self.rear.spring_lower_height_m:
            raise ParameterError("rear.spring_upper_height_m", self.rear.spring_upper_height_m,
                                 "must exceed rear.spring_lower_height_m")
        if self.parts_mass_kg() >= self.mass.total_mass_kg:
            raise ParameterError(
                "mass.total_mass_kg", self.mass.total_mass_kg,
                f"must exceed the suspension parts' mass {self.parts_mass_kg():.1f} kg")
        check_seat_point(self)
        return self

    def parts_mass_kg(self):
        """Mass of every body except the chassis (sprung body)."""
        m = self.mass
        front_corner = (m.front_wheel_kg + m.front_knuckle_kg + m.front_lower_arm_kg
                        + m.piston_rod_kg + m.strut_slider_kg + m.tie_rod_kg
                        + self.front.top_mount_mass_kg())
        rear_corner = m.rear_wheel_kg + m.rear_carrier_kg
        return 2 * front_corner + 2 * rear_corner + m.rack_kg
