"""The car driving the paper's manoeuvre: settle, speed up to 60 km/h, straight, lane change,
calm down (paper section 4), on Magic Formula tyres."""

import dataclasses
import math
import time

import numpy as np
from pydrake.systems.analysis import Simulator

from drake_car.assembly import DEFAULT_TIME_STEP_S, TyreSetup, build_car_diagram
from drake_car.manoeuvre import (
    LaneChangeProfile, Timeline, drive_trajectory, rack_trajectory)  # noqa: F401
from drake_car.law.road import flat
from drake_car.model.geometry import SIDES
from drake_car.model.parameters import CarParameters
from drake_car.monitor import attach_monitor, run_checked
from drake_car.systems.tyre import WHEELS

CASES = ("a", "b", "straight")
HISTORY_COLUMNS = (
    "t", "phase", "x_m", "y_m", "yaw_rad", "speed_mps", "rack_m", "steer_fl_deg",
    "steer_fr_deg") + tuple(f"Fz_{w}_N" for w in WHEELS) + tuple(
    f"Fy_{w}_N" for w in WHEELS) + tuple(f"Fx_{w}_N" for w in WHEELS) + (
    "d_left_m", "d_right_m", "rot_left_rad", "rot_right_rad")


def rolling_radius(params: CarParameters):
    """Effective rolling radius of a front tyre at its design load: R0 - δ/3."""
    load = params.design_axle_loads_N()["front"] / 2
    return params.tyre.unloaded_radius_m - load / params.tyre.radial_stiffness_Npm / 3


@dataclasses.dataclass
class DriveRun:
    history: dict
    wall_s: float
    built: object
    simulator: object


def run_drive(case="a", params: CarParameters | None = None, *, friction=None,
              tyres: TyreSetup | None = None, timeline: Timeline | None = None,
              profile: LaneChangeProfile | None = None, time_step_s=DEFAULT_TIME_STEP_S,
              record_period_s=0.01, end_time_s=None, meshcat=None, progress=None,
              extra_channels=None, rack=None, road_height=None, drive_reaction="driveshaft"):
    """Simulates the manoeuvre; returns the history (columns ``HISTORY_COLUMNS`` plus those of
    ``extra_channels(built, root_context) -> dict``) sampled every ``record_period_s``.
    ``profile`` defaults to the calibrated lane change (scenes/lane_change_profile.json);
    ``rack`` (a PiecewisePolynomial) replaces the lane change's rack command altogether;
    ``road_height`` is a profile of ``drake_car.law.road`` (default flat)."""
    if case not in CASES:
        raise ValueError(f"case {case!r} must be one of {CASES}")
    params = params or CarParameters()
    tyres = tyres or TyreSetup()
    timeline = timeline or Timeline()
    if profile is None:
        from drake_car.calibration import calibrated_profile
        profile = calibrated_profile()
    built = build_car_diagram(
        params, time_step_s=time_step_s, friction=friction, tyres=tyres, meshcat=meshcat,
        road_height=road_height or flat, drive_reaction=drive_reaction,
        rack_trajectory=rack if rack is not None else rack_trajectory(timeline, profile, case),
        drive_trajectory=drive_trajectory(timeline, rolling_radius(params)))
    simulator = Simulator(built.diagram)
    root = simulator.get_mutable_context()
    plant, car = built.plant, built.car
    pc = plant.GetMyContextFromRoot(root)
    tyre_context = built.tyre.GetMyContextFromRoot(root)
    chassis = car.body("chassis")
    rack = car.joint("rack_slide")
    prismatic = {s: car.joint(f"strut_prismatic_{s}") for s in SIDES}
    revolute = {s: car.joint(f"strut_revolute_{s}") for s in SIDES}
    wheels = {"fl": car.body("wheel_front_left"), "fr": car.body("wheel_front_right")}
    names = built.tyre.diagnostic_names()
    fx_i = [names.index(f"Fx_N_{w}") for w in WHEELS]
    fy_i = [names.index(f"Fy_N_{w}") for w in WHEELS]
    fz_i = [names.index(f"Fz_N_{w}") for w in WHEELS]
    l_guide = params.front.guide_length_l_m
    end = timeline.duration_s if end_time_s is None else end_time_s
    steps = int(round(end / record_period_s))
    history = {c: [] for c in HISTORY_COLUMNS}
    attach_monitor(simulator, built)
    simulator.Initialize()
    start = time.perf_counter()
    for k in range(steps + 1):
        run_checked(simulator, k * record_period_s)
        t = root.get_time()
        pose = chassis.EvalPoseInWorld(pc)
        rotation = pose.rotation().matrix()
        velocity = chassis.EvalSpatialVelocityInWorld(pc).translational()
        diag = built.tyre.GetOutputPort("tyre_diagnostics").Eval(tyre_context)
        history["t"].append(t)
        history["phase"].append(timeline.phase(t))
        history["x_m"].append(pose.translation()[0])
        history["y_m"].append(pose.translation()[1])
        history["yaw_rad"].append(math.atan2(rotation[1, 0], rotation[0, 0]))
        history["speed_mps"].append(math.hypot(velocity[0], velocity[1]))
        history["rack_m"].append(rack.get_translation(pc))
        for w, body in wheels.items():
            axis = rotation.T @ body.EvalPoseInWorld(pc).rotation().matrix()[:, 1]
            history[f"steer_{w}_deg"].append(math.degrees(math.atan2(-axis[0], axis[1])))
        for i, w in enumerate(WHEELS):
            history[f"Fz_{w}_N"].append(diag[fz_i[i]])
            history[f"Fy_{w}_N"].append(diag[fy_i[i]])
            history[f"Fx_{w}_N"].append(diag[fx_i[i]])
        for s in SIDES:
            history[f"d_{s}_m"].append(l_guide - prismatic[s].get_translation(pc))
            history[f"rot_{s}_rad"].append(revolute[s].get_angle(pc))
        if extra_channels is not None:
            for key, value in extra_channels(built, root).items():
                history.setdefault(key, []).append(value)
        if progress is not None and k % max(1, steps // 20) == 0:
            progress(t, end)
    wall = time.perf_counter() - start
    history = {k: (np.asarray(v) if k != "phase" else list(v)) for k, v in history.items()}
    return DriveRun(history=history, wall_s=wall, built=built, simulator=simulator)


def lane_change_metrics(history, timeline: Timeline):
    """Lateral shift of the car over phase III and heading change at its end (None when the
    history stops before phase III ends)."""
    t = history["t"]
    _, t3, t4, _ = timeline.boundaries()
    if t[-1] < t4:
        return None
    i3, i4 = np.searchsorted(t, t3), min(np.searchsorted(t, t4), len(t) - 1)
    heading = history["yaw_rad"]
    y = history["y_m"]
    return {"shift_m": float(y[i4] - y[i3]),
            "heading_change_deg": float(math.degrees(heading[i4] - heading[i3])),
            "final_heading_deg": float(math.degrees(heading[-1] - heading[i3])),
            "final_shift_m": float(y[-1] - y[i3])}
