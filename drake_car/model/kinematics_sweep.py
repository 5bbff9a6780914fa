"""Suspension kinematics sweeps (chassis fixed): the curves Adams/Car users look at first."""

import dataclasses

import numpy as np

from drake_car.model.car import model_source
from drake_car.model.geometry import SIDES
from drake_car.model.kinematics import SuspensionKinematics
from drake_car.model.parameters import CarParameters

KINEMATICS_COLUMNS = ("side", "wheel_travel_m", "camber_deg", "toe_deg", "caster_deg",
                      "kingpin_deg", "strut_length_m", "overlap_m", "closure_error_m")
STEERING_COLUMNS = ("rack_m", "steer_left_deg", "steer_right_deg", "closure_error_m")


@dataclasses.dataclass
class KinematicsSweep:
    kinematics: dict  # column -> list
    steering: dict


def run_kinematics_sweep(params: CarParameters | None = None, *, travel_m=0.08, points=33,
                         model_path=None) -> KinematicsSweep:
    """Each front wheel through ±travel_m (bump positive), then the rack through its stroke."""
    params = params or CarParameters()  # checked where it entered (a scene's load)
    if not travel_m > 0 or points < 3:
        raise ValueError(f"travel_m = {travel_m} must be > 0 and points = {points} >= 3")
    kin = SuspensionKinematics(model_source(params, model_path), params.front.guide_length_l_m)
    table = {c: [] for c in KINEMATICS_COLUMNS}
    travels = np.linspace(-travel_m, travel_m, points)
    for side in SIDES:
        # Continuation from the design position outwards, bump then rebound.
        states = {}
        for segment in (travels[travels >= 0], travels[travels < 0][::-1]):
            kin.solve("front", side, 0.0)
            for travel in segment:
                kin.solve("front", side, float(travel))
                states[float(travel)] = kin.front_state(side, float(travel))
        kin.solve("front", side, 0.0)
        for travel in travels:
            st = states[float(travel)]
            for c in KINEMATICS_COLUMNS:
                table[c].append(getattr(st, c))
    steering = {c: [] for c in STEERING_COLUMNS}
    stroke = params.front.rack_stroke_m
    racks = np.linspace(-stroke, stroke, points)
    for direction in (1, -1):
        kin.set_rack(0.0)
        for side in SIDES:
            kin.solve("front", side, 0.0)
        segment = racks[racks >= 0] if direction > 0 else racks[racks < 0][::-1]
        for rack in segment:
            kin.set_rack(float(rack))
            for side in SIDES:
                kin.solve("front", side, 0.0)
            left, right = kin.front_state("left", 0.0), kin.front_state("right", 0.0)
            steering["rack_m"].append(float(rack))
            steering["steer_left_deg"].append(left.steer_deg)
            steering["steer_right_deg"].append(right.steer_deg)
            steering["closure_error_m"].append(max(left.closure_error_m, right.closure_error_m))
    order = np.argsort(steering["rack_m"])
    steering = {c: [steering[c][i] for i in order] for c in STEERING_COLUMNS}
    return KinematicsSweep(table, steering)
