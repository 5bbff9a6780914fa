"""The car driving the paper's manoeuvre: settle, speed up to 60 km/h, straight, lane change,
calm down (paper section 4), on Magic Formula tyres."""

import dataclasses
import math
import time

import numpy as np
from pydrake.systems.analysis import Simulator

from drake_car.assembly import DEFAULT_TIME_STEP_S, LOG_CHANNELS, TyreSetup, build_car_diagram
from drake_car.manoeuvre import (
    LaneChangeProfile, Timeline, drive_trajectory, rack_trajectory)  # noqa: F401
from drake_car.law.road import flat
from drake_car.model.parameters import CarParameters
from drake_car.monitor import attach_monitor, run_checked

CASES = ("a", "b", "straight")


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
    html: str | None = None  # the Meshcat replay, when the scene asked for one
    monitor: object = None  # drake_car.monitor.MonitorStats (frozen SAP steps)


def run_drive(case="a", params: CarParameters | None = None, *, friction=None,
              tyres: TyreSetup | None = None, timeline: Timeline | None = None,
              profile: LaneChangeProfile | None = None, time_step_s=DEFAULT_TIME_STEP_S,
              record_period_s=0.01, end_time_s=None, meshcat=None, progress=None,
              extra_channels=None, rack=None, road_height=None, drive_reaction="driveshaft",
              channels=LOG_CHANNELS, realtime_rate=0.0, sap_pacer=True,
              initial_positions=None):
    """Simulates the manoeuvre; returns the history sampled every ``record_period_s``.

    The history holds "t", "phase" and the columns of the logged ``channels`` (groups of
    ``drake_car.assembly.LOG_CHANNELS``; each has a VectorLogSink in the diagram, a group not
    asked for has none): chassis (x_m, y_m, yaw_rad, yaw_rate_radps, speed_mps), steering (rack_m,
    steer_fl_deg, steer_fr_deg), struts (d_left_m, d_right_m, rot_left_rad, rot_right_rad),
    tyres (Fx_fl_N ... vx_rr_mps, see ``TyreSystem.diagnostic_names``) and friction
    (friction_left_translation_v ..., see ``StrutFriction.diagnostic_names``).
    ``extra_channels(built, root_context) -> dict`` adds columns computed in Python at each
    record time (the run then stops at every record time to call it).
    ``profile`` defaults to the calibrated lane change (scenes/lane_change_profile.json);
    ``rack`` (a PiecewisePolynomial) replaces the lane change's rack command altogether;
    ``road_height`` is a profile of ``drake_car.law.road`` (default flat); ``realtime_rate``
    > 0 paces the run (for watching it live in ``meshcat``); ``sap_pacer`` False leaves out the
    pacer of ``drake_car.systems.sap_pacer`` (to measure what it prevents);
    ``initial_positions``: the car's generalized positions at t = 0, at rest (e.g. a settled
    state, ``SettleResult.positions``; default: the model's design position, from which the
    car drops onto its tyres)."""
    if case not in CASES:
        raise ValueError(f"case {case!r} must be one of {CASES}")
    if not record_period_s > 0:
        raise ValueError(f"record_period_s = {record_period_s} must be > 0")
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
        drive_trajectory=drive_trajectory(timeline, rolling_radius(params)),
        log_channels=tuple(channels), log_period_s=record_period_s, sap_pacer=sap_pacer)
    simulator = Simulator(built.diagram)
    simulator.set_target_realtime_rate(realtime_rate)
    root = simulator.get_mutable_context()
    if initial_positions is not None:
        plant_context = built.plant.GetMyContextFromRoot(root)
        expected = built.plant.num_positions(built.car.instance)
        if len(initial_positions) != expected:
            raise ValueError(f"initial_positions has {len(initial_positions)} entries; the car "
                             f"has {expected} generalized positions")
        built.plant.SetPositions(plant_context, built.car.instance, initial_positions)
    end = timeline.duration_s if end_time_s is None else end_time_s
    steps = int(round(end / record_period_s))
    stats = attach_monitor(simulator, built)
    simulator.Initialize()
    start = time.perf_counter()
    extra = {}
    if extra_channels is not None:
        for k in range(steps + 1):
            run_checked(simulator, k * record_period_s)
            for key, value in extra_channels(built, root).items():
                extra.setdefault(key, []).append(value)
            if progress is not None and k % max(1, steps // 20) == 0:
                progress(root.get_time(), end)
    else:
        chunks = 20 if progress is not None else 1
        for k in range(1, chunks + 1):
            run_checked(simulator, steps * record_period_s * k / chunks)
            if progress is not None:
                progress(root.get_time(), end)
    wall = time.perf_counter() - start
    history = logged_history(built, root)
    if "t" not in history:
        history["t"] = np.arange(steps + 1) * record_period_s
    for key, values in extra.items():
        history[key] = np.asarray(values)
    history["phase"] = [timeline.phase(t) for t in history["t"]]
    return DriveRun(history=history, wall_s=wall, built=built, simulator=simulator,
                    monitor=stats)


def logged_history(built, root_context):
    """Columns of every logger of ``built`` (a CarDiagram), with their sample times "t"."""
    history = {}
    for group, logger in built.loggers.items():
        log = logger.FindLog(root_context)
        times = log.sample_times()
        if "t" in history and not np.array_equal(history["t"], times):
            raise RuntimeError(f"logger of {group} sampled at other times than the others")
        history["t"] = np.array(times)
        data = log.data()
        for row, name in enumerate(built.log_columns[group]):
            history[name] = np.array(data[row])
    return history


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
