"""The second shipped car: a BMW 320i (E30, 1982-94), a D-segment rear-drive saloon with
McPherson front struts and semi-trailing arms at the rear, given by its hard points. Every
number has its source:

  [CR2] CommonRoad vehicle models, parameter set 2, "values are taken from a BMW 320i"
        (vehiclemodels.parameters_vehicle2; M. Althoff, G. Würsching, "CommonRoad: Vehicle
        Models", 2020, Table 6), from R. W. Allen et al., "Vehicle Dynamic Stability and
        Rollover", NHTSA DOT HS 807 956 (1992), as the shipped Escort's [ESC].
  [E90] SAE paper 2007-01-0818 (BMW E90 330i front McPherson strut), as tabulated in Project
        Chrono's BMW_E90_MacPhersonStrut (the suspension's hard points, its lower arm's and tie
        rod's masses): the same maker's McPherson front of a later generation.
  [EST] an estimate, with its reason.

The front's hard points are [E90]'s scaled laterally to the 320i's front track [CR2] (factor
1.38684 / 1.500124) [EST: no hard points of the E30 are published that we could reach], and
lowered onto the ground under the car at ride height (Chrono's frame has its origin at the wheel
centre). The masses and the centre of gravity are [CR2]'s sprung mass's with the parts where
the model puts them, as the Escort's are [ESC]'s (``model.parameters``); the car file states
the whole car's, derived here. The rear's semi-trailing arms are the model's trailing arms.

``python -m drake_car.model.cars.bmw_320i`` writes the car file ``urdf/cars/bmw_320i.yaml``
from this module (a test checks they agree), each value with its source.
"""

import argparse
import dataclasses
from pathlib import Path

from drake_car.data import resource
from drake_car.model.car import model_source, spring_settings
from drake_car.model.geometry import centre_of_mass
from drake_car.model.hard_points import (
    FrontHardPoints, HardPointCar, WholeCarMass, frame_shift_m, to_parameters,
    whole_car_inertia_kgm2)
from drake_car.model.parameters import RearSuspensionParameters, TyreVerticalParameters

CAR_FILE = Path(str(resource("urdf").joinpath("cars/bmw_320i.yaml")))

# [CR2]
MASS_KG = 1093.2952334674046  # m
SPRUNG_TO_FRONT_AXLE_M = 1.1561957064  # a: the sprung mass's CoG behind the front axle
SPRUNG_TO_REAR_AXLE_M = 1.4227170936  # b
SPRUNG_COG_HEIGHT_M = 0.61373004  # h_s, above the ground
SPRUNG_ROLL_PITCH_KGM2 = (207.26524557936952, 1565.8178787125541)  # I_Phi_s (IXS), I_y_s (IYS)
# I_z (IZZ, without the sprung mass's S of IXS and IYS) read as the whole car's yaw inertia:
# as the sprung mass's it would break the triangle inequality with I_Phi_s and I_y_s (207.3 +
# 1565.8 < 1791.6: no rigid body has such moments).
WHOLE_YAW_KGM2 = 1791.5995300122856
UNSPRUNG_PER_AXLE_KG = 63.7921826056784  # m_uf = m_ur
FRONT_TRACK_M = 1.38684  # T_f
REAR_TRACK_M = 1.36398  # T_r
FRONT_WHEEL_RATE_NPM = 24453.137879749014  # K_sf, at the wheel
REAR_WHEEL_RATE_NPM = 19635.504745231297  # K_sr
FRONT_DAMPING_AT_WHEEL_NSPM = 1786.2441002440723  # K_sdf
REAR_DAMPING_AT_WHEEL_NSPM = 1649.0833034887382  # K_sdr
FRONT_ANTI_ROLL_NM_PER_RAD = 6914.881688272133  # -K_tsf (negative in its convention)
REAR_ANTI_ROLL_NM_PER_RAD = 2643.6009520155308  # -K_tsr
TYRE_RADIAL_NPM = 158294.1398119115  # K_zt

# [E90] left corner, Chrono's suspension frame (origin at the wheel centre, x forward, y left).
E90_HALF_TRACK_M = 0.750062
E90_POINTS = {
    "lower_arm_front_pivot_m": (0.27051, 0.34544, -0.05969),  # LCA_F
    "lower_arm_rear_pivot_m": (-0.04318, 0.37338, -0.12573),  # LCA_B
    "ball_joint_m": (0.02794, 0.66294, -0.10414),  # LCA_U
    "strut_top_mount_m": (-0.08382, 0.54102, 0.46863),  # SHOCK_C (= SPRING_C)
    "strut_lower_mount_m": (-0.00508, 0.61976, -0.00127),  # SHOCK_U (= SPRING_U)
    # The spring acts between the shock's points in [E90]: its seats at the strut's ends.
    "spring_upper_seat_m": (-0.08382, 0.54102, 0.46863),  # SPRING_C
    "spring_lower_seat_m": (-0.00508, 0.61976, -0.00127),  # SPRING_U
    "tie_rod_inner_m": (-0.2, 0.2, -0.05),  # TIEROD_C
    "tie_rod_outer_m": (-0.2, 0.574803759, -0.00127),  # TIEROD_U
    "wheel_centre_m": (0.0, E90_HALF_TRACK_M, 0.0),  # SPINDLE
}
# [EST] The rack end (tie rod's inner point) in this car file's frame: Chrono's TIEROD_C
# (-0.2, 0.2, -0.05) is a round estimate (SAE's points are inch conversions: 0.27051 m =
# 10.65 in) with which the corner steers ±2 deg over ±75 mm of wheel travel (±1.9 deg
# unscaled), far beyond a production front; placed here, in its plane x = -0.2 m, for the least
# bump steer over ±75 mm (least squares on a 1 mm grid: toe within ±0.07 deg).
TIE_ROD_INNER_M = [-0.2, 0.203, 0.280]
E90_LOWER_ARM_KG = 2.72  # m_LCAMass
E90_TIE_ROD_KG = 1.13  # m_tierodMass

# [EST] the shipped tyre (Pacejka 2006, Table A3.1, 205/60R15: urdf/tyres/): no Magic Formula
# data of the 320i's own tyres could be reached; a passenger tyre of its size class.
TYRE_RADIUS_M, TYRE_WIDTH_M = 0.313, 0.205
# [EST] drawn at ride height: the wheel centre at the tyre's radius less its deflection under
# the front wheel's static load (~2.9 kN on K_zt: 18 mm).
WHEEL_CENTRE_HEIGHT_M = 0.295

SOURCES = {
    "mass.total_mass_kg": "[CR2] m",
    "mass.cog_behind_front_axle_m": "the whole car's: [CR2]'s sprung mass (a, h_s) and the "
                                    "parts where the model puts them",
    "mass.cog_height_m": "the whole car's, as above ([CR2]'s own h_cg: 0.5749 m)",
    "mass.inertia_kgm2": "the whole car's about its CoG: roll and pitch [CR2]'s sprung mass's "
                         "(I_Phi_s, I_y_s) and the parts'; yaw [CR2]'s I_z (the whole car's: "
                         "as the sprung mass's it breaks the triangle inequality)",
    "mass.front_wheel_kg": "[EST] the shipped car's wheel and tyre",
    "mass.front_knuckle_kg": "[CR2] m_uf / 2 less the corner's other parts",
    "mass.front_lower_arm_kg": "[E90] m_LCAMass",
    "mass.piston_rod_kg": "[EST] a 22 mm rod",
    "mass.strut_slider_kg": "the cylindrical joint's light link (no part)",
    "mass.tie_rod_kg": "[E90] m_tierodMass",
    "mass.rack_kg": "[EST] as the shipped car's",
    "mass.rear_wheel_kg": "[EST] the shipped car's wheel and tyre",
    "mass.rear_carrier_kg": "[CR2] m_ur / 2 less the wheel",
    "mass.wheel_spin_inertia_kgm2": "[EST] the shipped car's (the same tyre)",
    "wheelbase_m": "[CR2] a + b",
    "driven_axle": "the 320i is rear-driven",
    "front.*_m points": "[E90] scaled laterally by T_f / 1.500124 [CR2], on the ground at ride "
                        "height",
    "front.tie_rod_inner_m": "[EST] placed for the least bump steer (TIE_ROD_INNER_M: [E90]'s "
                             "is Chrono's round estimate, ±2 deg over ±75 mm)",
    "front.guide_below_top_mount_m": "[EST] as the shipped car's (a 0.47-0.48 m strut)",
    "front.guide_length_l_m": "[EST] as the shipped car's",
    "front.rod_radius_r_m": "[EST] a 22 mm rod",
    "front.wheel_rate_Npm": "[CR2] K_sf",
    "front.strut_damping_Nspm": "[CR2] K_sdf at the wheel / MR², MR the strut's motion ratio",
    "front.anti_roll_bar_Nm_per_rad": "[CR2] -K_tsf",
    "front.top_mount_*": "[EST] rigid; the shipped car's compliant-mount data",
    "front.rack_stroke_m": "[EST] as the shipped car's",
    "front.rack_gain_m_per_rad": "[EST] as the shipped car's (no published c-factor of the "
                                 "car's rack found)",
    "rear.track_m": "[CR2] T_r",
    "rear.wheel_rate_Npm": "[CR2] K_sr",
    "rear.wheel_damping_Nspm": "[CR2] K_sdr",
    "rear.anti_roll_bar_Nm_per_rad": "[CR2] -K_tsr",
    "rear.*": "[EST] the semi-trailing arms as the shipped car's trailing-arm layout",
    "tyre.radial_stiffness_Npm": "[CR2] K_zt",
    "tyre.radial_damping_Nspm": "[EST] ~5 % of critical for the unsprung mass",
    "tyre.*": "[EST] the shipped tyre, 205/60R15",
}


def _front_points():
    scale = (FRONT_TRACK_M / 2) / E90_HALF_TRACK_M
    points = {name: [x, y * scale, z + WHEEL_CENTRE_HEIGHT_M]
              for name, (x, y, z) in E90_POINTS.items()}
    points["tie_rod_inner_m"] = list(TIE_ROD_INNER_M)
    return points


def car() -> HardPointCar:
    """The car file's content (``HardPointCar``)."""
    corner_parts = (15.0, E90_LOWER_ARM_KG, 1.0, 0.05, E90_TIE_ROD_KG)
    mass = WholeCarMass(
        total_mass_kg=MASS_KG, cog_behind_front_axle_m=SPRUNG_TO_FRONT_AXLE_M,
        cog_height_m=SPRUNG_COG_HEIGHT_M,
        inertia_kgm2=[*SPRUNG_ROLL_PITCH_KGM2, WHOLE_YAW_KGM2],
        front_wheel_kg=15.0, front_knuckle_kg=UNSPRUNG_PER_AXLE_KG / 2 - sum(corner_parts),
        front_lower_arm_kg=E90_LOWER_ARM_KG, piston_rod_kg=1.0, strut_slider_kg=0.05,
        tie_rod_kg=E90_TIE_ROD_KG, rack_kg=2.0, rear_wheel_kg=15.0,
        rear_carrier_kg=UNSPRUNG_PER_AXLE_KG / 2 - 15.0, wheel_spin_inertia_kgm2=0.6)
    front = FrontHardPoints(
        **_front_points(), guide_below_top_mount_m=0.20, guide_length_l_m=0.14,
        rod_radius_r_m=0.011, wheel_rate_Npm=FRONT_WHEEL_RATE_NPM,
        strut_damping_Nspm=FRONT_DAMPING_AT_WHEEL_NSPM,
        anti_roll_bar_Nm_per_rad=FRONT_ANTI_ROLL_NM_PER_RAD, top_mount_stiffness_Npm=0.0,
        top_mount_damping_Nspm=2000.0, top_mount_body_kg=0.5, top_mount_link_kg=0.05,
        rack_stroke_m=0.07, rack_gain_m_per_rad=0.008)
    lift = TYRE_RADIUS_M - WHEEL_CENTRE_HEIGHT_M  # V's heights less the file's
    rear = RearSuspensionParameters(
        track_m=REAR_TRACK_M, pivot_ahead_of_axle_m=0.45, pivot_y_m=0.55,
        pivot_height_m=0.30 - lift, spring_ahead_of_axle_m=0.05, spring_y_m=0.55,
        spring_lower_height_m=0.25 - lift, spring_upper_height_m=0.60 - lift,
        wheel_rate_Npm=REAR_WHEEL_RATE_NPM, wheel_damping_Nspm=REAR_DAMPING_AT_WHEEL_NSPM,
        anti_roll_bar_Nm_per_rad=REAR_ANTI_ROLL_NM_PER_RAD)
    tyre = TyreVerticalParameters(unloaded_radius_m=TYRE_RADIUS_M, width_m=TYRE_WIDTH_M,
                                  radial_stiffness_Npm=TYRE_RADIAL_NPM,
                                  radial_damping_Nspm=250.0)
    hard = HardPointCar(mass=mass, wheelbase_m=SPRUNG_TO_FRONT_AXLE_M + SPRUNG_TO_REAR_AXLE_M,
                        driven_axle="rear", front=front, rear=rear, tyre=tyre)
    # The body as [CR2] gives it (in V), the parts where the model puts them: the whole car's
    # centre of gravity and inertia follow.
    params = to_parameters(hard)
    shift = frame_shift_m(hard)
    params.mass.cog_to_front_axle_m = SPRUNG_TO_FRONT_AXLE_M
    params.mass.cog_to_rear_axle_m = SPRUNG_TO_REAR_AXLE_M
    params.mass.sprung_cog_height_m = SPRUNG_COG_HEIGHT_M + float(shift[2])
    params.mass.sprung_inertia_kgm2 = [*SPRUNG_ROLL_PITCH_KGM2, WHOLE_YAW_KGM2]
    whole = centre_of_mass(params)
    mass.cog_behind_front_axle_m = float(-whole[0])
    mass.cog_height_m = float(whole[2] - shift[2])
    roll, pitch, _ = whole_car_inertia_kgm2(params)
    mass.inertia_kgm2 = [float(roll), float(pitch), WHOLE_YAW_KGM2]
    # The damper along the strut: [CR2]'s damping at the wheel over the motion ratio squared
    # (the corner's kinematics; the car as the file now gives it).
    params = to_parameters(hard)
    ratio = spring_settings(params, model_source(params))[("front", "left")].motion_ratio
    front.strut_damping_Nspm = FRONT_DAMPING_AT_WHEEL_NSPM / ratio ** 2
    return hard


def _source(key):
    group, _, name = key.partition(".")
    if key in SOURCES:
        return SOURCES[key]
    if key == "front.tie_rod_inner_m":
        return SOURCES[key]
    if group == "front" and name in E90_POINTS:
        return SOURCES["front.*_m points"]
    if group == "front" and name.startswith("top_mount_"):
        return SOURCES["front.top_mount_*"]
    return SOURCES.get(f"{group}.*", "")


def car_file_text(hard=None) -> str:
    """The car file, each value with its source."""
    hard = hard or car()
    lines = [
        "# BMW 320i (E30): a car file (drake_car.model.hard_points), generated by",
        "# drake_car/model/cars/bmw_320i.py from its sources (the module says each one);",
        "# do not edit by hand: python -m drake_car.model.cars.bmw_320i rewrites it.",
        "# [CR2] CommonRoad vehicle models, parameter set 2 (BMW 320i, from NHTSA DOT HS 807 956);",
        "# [E90] SAE 2007-01-0818 via Project Chrono's BMW_E90_MacPhersonStrut; [EST] estimates.",
        "# Frame: x forward, y left, z up, z = 0 on the ground at ride height, x = 0 at the front",
        "# wheel centres; the left corner's points."]
    for section in ("mass", "wheelbase_m", "driven_axle", "front", "rear", "tyre"):
        value = getattr(hard, section)
        if not dataclasses.is_dataclass(value):
            lines.append(f"{section}: {_text(value)}  # {_source(section)}")
            continue
        lines.append(f"{section}:")
        for field in dataclasses.fields(value):
            key = f"{section}.{field.name}"
            lines.append(f"  {field.name}: {_text(getattr(value, field.name))}  # {_source(key)}")
    return "\n".join(lines) + "\n"


def _text(value):
    if isinstance(value, str):
        return value
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(repr(float(v)) for v in value) + "]"
    return repr(float(value))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=CAR_FILE,
                        help="where to write the car file (default: %(default)s)")
    args = parser.parse_args()
    args.out.write_text(car_file_text())
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
