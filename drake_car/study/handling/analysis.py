"""The handling study's analysis: the two scenes it needs (ISO 4138 ramp steer, ISO 7401 step
steer), their runs' metrics, the single-track model built from the car's own parameters, the
understeer budget (``understeer``) and the cross-check against CommonRoad's multi-body model of
the same car (``crosscheck``), the tyre it runs on and what changed against the shipped tyre
(``tyre_section``). ``handling_study(scenes, fit_range)`` runs and analyses both."""

import logging
import time

import numpy as np

from drake_car.study.car.describe import drive_short
from drake_car.model.geometry import (
    design_axle_loads_N, steering_sign, whole_car_cog_to_front_m)
from drake_car.model.kinematics_sweep import run_kinematics_sweep
from drake_car.scene.load import SceneError
from drake_car.scene.manoeuvres import RampSteer, StepSteer
from drake_car.scene.scene import LinearTyre, MagicFormula
from drake_car.sim.simulate import simulate
from drake_car.study.handling import crosscheck
from drake_car.study.handling import measures as handling
from drake_car.study.handling import tyre_section
from drake_car.study.handling.tyre_section import tyre_of
from drake_car.study.handling.understeer import understeer_budget

log = logging.getLogger(__name__)

ENTRIES = {"steady_state": RampSteer, "step_steer": StepSteer}


def check_scenes(scenes, path):
    """Refuses (SceneError) scenes that are not the handling study's: the two entries of
    ``ENTRIES`` with their manoeuvres, tyres with lateral forces, the channels it reads."""
    for name, kind in ENTRIES.items():
        if name not in scenes:
            raise SceneError(f"{path}: needs the scenes {', '.join(ENTRIES)}; it has "
                             f"{', '.join(scenes)}")
        scene = scenes[name]
        if not isinstance(scene.manoeuvre, kind):
            raise SceneError(f"{path} [{name}]: manoeuvre must be !{kind.__name__}, not "
                             f"!{type(scene.manoeuvre).__name__}")
        if not isinstance(scene.tyres, (MagicFormula, LinearTyre)):
            raise SceneError(f"{path} [{name}]: tyres must be !MagicFormula or !LinearTyre "
                             "(the tests need lateral forces)")
        first = scenes[next(iter(ENTRIES))].tyres.tir_file
        if scene.tyres.tir_file != first:
            raise SceneError(f"{path} [{name}]: tyres.tir_file {scene.tyres.tir_file} differs "
                             f"from the other test's {first}: both tests run on one tyre")
        missing = {"chassis", "steering", "tyres"} - set(
            scene.logging.channels or ("chassis", "steering", "tyres"))
        if missing:
            raise SceneError(f"{path} [{name}]: logging.channels must include "
                             f"{', '.join(sorted(missing))}")


def handling_study(scenes, fit_range, *, crosscheck_why=None, progress=True,
                   shipped_why=None):
    """Runs both scenes and analyses them; the cross-check too unless ``crosscheck_why`` says
    why it is left out; on a tyre other than the shipped one, both scenes again on the shipped
    tyre and what changed, unless ``shipped_why`` says why not. Returns (runs, result, wall
    times); the shipped tyre's runs are ``runs["shipped_tyre"]`` ({name: run}). Raises
    ``handling.HandlingError`` when a run does not give what the analysis needs."""
    walls, runs = {}, {}
    for name in ENTRIES:
        runs[name] = simulate(scenes[name], progress=progress)
        walls[f"{name} run"] = runs[name].wall_s
    started = time.perf_counter()
    result = analyse(runs, fit_range)
    walls["metrics and budget"] = time.perf_counter() - started
    result["tyre"] = tyre_section.facts(scenes["steady_state"])
    if not result["tyre"]["shipped"] and shipped_why is not None:
        result["tyre_change"] = {"skipped": shipped_why}
    elif not result["tyre"]["shipped"]:
        started = time.perf_counter()
        shipped, note = tyre_section.shipped_scenes({name: scenes[name] for name in ENTRIES})
        runs["shipped_tyre"] = {name: simulate(shipped[name], progress=progress)
                                for name in ENTRIES}
        base = analyse(runs["shipped_tyre"], fit_range)
        result["tyre_change"] = {"rows": tyre_section.changes(result, base), "note": note}
        walls["the shipped tyre's runs and metrics"] = time.perf_counter() - started
    vehicle = crosscheck.parameter_set_of(scenes["steady_state"].car) if (
        crosscheck_why is None) else None
    if crosscheck_why is None and vehicle is None:
        crosscheck_why = ("CommonRoad has no parameter set of this car (its sets "
                          + ", ".join(f"{i}: {n}" for i, n in crosscheck.PARAMETER_SETS.items())
                          + ", by total mass and front track)")
    if crosscheck_why is None:
        started = time.perf_counter()
        try:
            result["crosscheck"] = cross_check(runs, result, fit_range, vehicle)
        except crosscheck.BrokeDown as e:  # before our runs' first steer: nothing to compare
            result["crosscheck"] = {"skipped": f"CommonRoad's model ({vehicle[1]}) could not "
                                               f"go on {e}"}
        walls["cross-check"] = time.perf_counter() - started
    else:
        result["crosscheck"] = {"skipped": crosscheck_why}
    return runs, result, walls


def crosscheck_left_out(no_crosscheck):
    """Why the cross-check is left out (None: it runs): asked for, or its package missing."""
    if no_crosscheck:
        return "left out (--no_crosscheck)"
    available, why = crosscheck.available()
    if not available:
        log.warning("cross-check left out: %s", why)
        return why
    return None


def analyse(runs, fit_range):
    """Metrics of both runs, the single-track model, the budget."""
    ramp, step = runs["steady_state"], runs["step_steer"]
    car = ramp.scene.car
    tyre = tyre_of(ramp.scene)
    linear = isinstance(ramp.scene.tyres, LinearTyre)
    combined = getattr(ramp.scene.tyres, "combined_slip", True)
    steering = run_kinematics_sweep(car, points=29).steering
    a, L = whole_car_cog_to_front_m(car), car.wheelbase_m
    h = ramp.history
    rack_steer = handling.kinematic_steer_rad(h["rack_m"], steering)
    wheel_steer = handling.road_wheel_steer_rad(h)
    mass = car.mass.total_mass_kg
    metrics = handling.steady_state(h, steer_rad=rack_steer, wheel_steer_rad=wheel_steer,
                                    wheelbase_m=L, cog_offset_m=a, mass_kg=mass,
                                    ay_range=fit_range)
    loads = design_axle_loads_N(car)
    stiff = {axle: handling.axle_cornering_stiffness(tyre, loads[axle], linear=linear)
             for axle in loads}
    single = handling.single_track(mass_kg=car.mass.total_mass_kg, wheelbase_m=L,
                                   cog_to_front_m=a, front_stiffness=stiff["front"],
                                   rear_stiffness=stiff["rear"], speed_mps=metrics["speed_mps"])
    single["axle_loads_N"] = loads
    budget = understeer_budget(h, car, tyre, kinematic_steer_rad=rack_steer, combined=combined,
                               linear=linear, ay_range=fit_range)
    command = ramp.scene.manoeuvre.rack()
    # The rack's own travel (a rack behind the axle travels against the command: sim.build).
    rack_command = steering_sign(car) * np.array([command.value(t)[0, 0] for t in h["t"]])
    servo = handling.steady_state(
        h, steer_rad=handling.kinematic_steer_rad(rack_command, steering),
        wheelbase_m=L, cog_offset_m=a, mass_kg=mass,
        ay_range=fit_range)["understeer_gradient_deg_per_g"]
    hs = step.history
    step_rack = handling.kinematic_steer_rad(hs["rack_m"], steering)
    step_metrics = handling.step_steer(hs, steer_rad=step_rack, cog_offset_m=a, mass_kg=mass)
    step_wheel = handling.step_steer(hs, steer_rad=handling.road_wheel_steer_rad(hs),
                                     cog_offset_m=a, mass_kg=mass)
    gain = car.front.rack_gain_m_per_rad
    return {
        "fit_range_mps2": list(fit_range), "steering": steering,
        "rack_gain_m_per_rad": gain, "steering_ratio": steering_ratio(steering, gain),
        "steering_sign": steering_sign(car),
        "mass_kg": car.mass.total_mass_kg, "cog_offset_m": a, "wheelbase_m": L,
        "t_steer_s": {name: handling.first_time(r.history["phase"], r.history["t"], "III")
                      for name, r in runs.items()},
        "drive": drive_short(ramp.scene),
        "steady_state": {
            "metrics": metrics, "single_track": single,
            "yaw_gain_ratio": metrics["yaw_rate_gain_per_s"] / single["yaw_rate_gain_per_s"],
            "yaw_gain_ratio_wheel": (metrics["yaw_rate_gain_wheel_per_s"]
                                     / single["yaw_rate_gain_per_s"]),
            "steering_servo_deg_per_g": servo - metrics["understeer_gradient_deg_per_g"],
            "series": handling.steady_state_series(h, steer_rad=rack_steer, wheelbase_m=L,
                                                   cog_offset_m=a, mass_kg=mass)
            | {"wheel_steer_deg": np.degrees(wheel_steer)}},
        "step_steer": {
            "metrics": step_metrics, "wheel_steer_gains": {
                "yaw_rate_per_s": step_wheel["yaw_rate"]["gain"],
                "lateral_acceleration_mps2_per_rad": step_wheel["lateral_acceleration"]["gain"]},
            "series": step_series(hs, step_rack, a, mass)},
        "budget": budget,
    }


def steering_ratio(steering, rack_gain_m_per_rad):
    """The overall steering ratio at the centre: the steering wheel's angle per road-wheel
    angle, 1 / (c dδ/dq) with c the car's rack gain (m of rack per steering-wheel radian) and
    dδ/dq the linkage's mean road-wheel angle per rack travel at q = 0 (the kinematics table,
    chassis fixed)."""
    rack = np.asarray(steering["rack_m"], float)
    mean = np.radians(0.5 * (np.asarray(steering["steer_left_deg"])
                             + np.asarray(steering["steer_right_deg"])))
    slope = abs(float(np.interp(0.0, rack, np.gradient(mean, rack))))  # a rack behind: < 0
    return 1.0 / (rack_gain_m_per_rad * slope) if slope else float("nan")


def step_series(h, rack_steer, cog_offset, mass):
    g = handling.cog_motion(h, cog_offset, mass)
    return {"t": h["t"], "steer_deg": np.degrees(rack_steer),
            "wheel_steer_deg": np.degrees(handling.road_wheel_steer_rad(h)),
            "yaw_rate_degps": np.degrees(g["yaw_rate"]), "ay_mps2": g["ay"],
            "roll_deg": np.degrees(h["roll_rad"]), "sideslip_cog_deg": np.degrees(g["sideslip"]),
            "speed_mps": g["speed"]}


def cross_check(runs, result, fit_range, vehicle=(1, "Ford Escort")):
    """CommonRoad's MB (its parameter set ``vehicle``: (id, name)) on our runs' road-wheel steer
    and speed; its metrics; the single-track chain from its data to ours; the understeer
    reconciliation."""
    p = crosscheck.parameters(vehicle[0])
    L_mb = p.a + p.b
    out = {"vehicle": {"id": vehicle[0], "name": vehicle[1]},
           "parameters": {k: getattr(p, k) for k in (
               "m", "m_s", "m_uf", "m_ur", "a", "b", "I_z", "h_s", "T_f", "T_r", "K_sf",
               "K_sr", "K_tsf", "K_tsr", "K_zt", "h_raf", "h_rar")}
           | {"tire_p_ky1": p.tire.p_ky1}}
    windows = {}
    for name, before in (("steady_state", 1.0), ("step_steer", 0.5)):
        h = runs[name].history
        t3 = handling.first_time(h["phase"], h["t"], "III")
        keep = h["t"] >= t3 - before
        mb = crosscheck.simulate_mb(h["t"][keep], handling.road_wheel_steer_rad(h)[keep],
                                    h["speed_mps"][keep], p=p)
        mb["phase"] = list(np.asarray(h["phase"])[keep])
        windows[name] = (keep, mb)
    keep, mb_ramp = windows["steady_state"]
    try:
        mb_ss = handling.steady_state(mb_ramp, steer_rad=mb_ramp["steer_rad"], wheelbase_m=L_mb,
                                      cog_offset_m=0.0, ay_range=fit_range)
    except handling.HandlingError:
        if mb_ramp["broke_down_s"] is None:
            raise
        raise crosscheck.BrokeDown(mb_ramp["broke_down_s"], "in the ramp steer, before its "
                                   f"a_y reached the fit range {fit_range} m/s²") from None
    no_camber = crosscheck.simulate_mb(mb_ramp["t"], mb_ramp["steer_rad"], mb_ramp["speed_mps"],
                                       p=p, camber_sign=False)
    no_camber["phase"] = mb_ramp["phase"]
    mb_ss_no_camber = handling.steady_state(no_camber, steer_rad=no_camber["steer_rad"],
                                            wheelbase_m=L_mb, cog_offset_m=0.0,
                                            ay_range=fit_range)
    keep_s, mb_step = windows["step_steer"]
    mb_st = handling.step_steer(mb_step, steer_rad=mb_step["steer_rad"], cog_offset_m=0.0)
    ramp_run, step_run = runs["steady_state"], runs["step_steer"]
    car = ramp_run.scene.car
    ours = result["steady_state"]["metrics"]
    budget = result["budget"]
    inertia = crosscheck.car_inertia(car)
    loads = budget["static_wheel_loads_N"]
    tyre = tyre_of(ramp_run.scene)
    relax = (ramp_run.scene.tyres.slip.relaxation_length_lat_m
             if ramp_run.scene.tyres.slip.relaxation else 0.0)
    hs = step_run.history
    t_step = hs["t"][keep_s]
    chain = crosscheck.single_track_chain(
        p, speed_mps=ours["speed_mps"], our_mass_kg=car.mass.total_mass_kg,
        our_cog_to_front_m=whole_car_cog_to_front_m(car), our_wheelbase_m=car.wheelbase_m,
        our_front_stiffness=handling.axle_cornering_stiffness(tyre, loads["fl"] + loads["fr"]),
        our_rear_stiffness=handling.axle_cornering_stiffness(tyre, loads["rl"] + loads["rr"]),
        our_yaw_inertia_kgm2=inertia["yaw_inertia_kgm2"], our_relaxation_m=relax,
        t=t_step, steer_rad=handling.road_wheel_steer_rad(hs)[keep_s])
    reconciliation = crosscheck.understeer_reconciliation(
        ours_wheel_k=ours["understeer_gradient_wheel_deg_per_g"], budget_rows=budget["rows"],
        mb_k=mb_ss["understeer_gradient_deg_per_g"],
        mb_k_no_camber=mb_ss_no_camber["understeer_gradient_deg_per_g"], chain=chain)
    roll = crosscheck.roll_model(p)
    our_roll_stiffness = roll_stiffness(car)
    sprung = car.mass.total_mass_kg - car.parts_mass_kg()
    ended = {name: _broke_down_at(runs[name].history, keep, mb, runs[name].scene.car)
             for name, (keep, mb) in windows.items() if mb["broke_down_s"] is not None}
    out.update(
        broke_down=ended,
        ramp=mb_ss, ramp_no_camber_sign=mb_ss_no_camber, step=mb_st, chain=chain,
        reconciliation=reconciliation, roll_model=roll, our_inertia=inertia,
        our_roll_stiffness=our_roll_stiffness, our_sprung_mass_kg=sprung,
        our_equivalent_roll_arm_m=crosscheck.equivalent_roll_arm(
            ours["roll_gradient_deg_per_g"], our_roll_stiffness["with_tyres_Nm_per_rad"], sprung),
        static_axle_loads_N=crosscheck.static_axle_loads(p),
        series_ramp=_paired(runs["steady_state"].history, keep, mb_ramp, car),
        series_step=_paired(hs, keep_s, mb_step, car))

    return out


def roll_stiffness(car):
    """Our car's roll stiffness from its parameters, as MB's roll model counts it: the wheel
    rates per axle (K_w T²/2) plus the anti-roll bars, each in series with its tyres."""
    f, r, k_t = car.front, car.rear, car.tyre.radial_stiffness_Npm
    front = f.wheel_rate_Npm * f.track_m ** 2 / 2 + getattr(f, "anti_roll_bar_Nm_per_rad", 0.0)
    rear = r.wheel_rate_Npm * r.track_m ** 2 / 2 + getattr(r, "anti_roll_bar_Nm_per_rad", 0.0)
    tyre_f, tyre_r = k_t * f.track_m ** 2 / 2, k_t * r.track_m ** 2 / 2
    return {"suspension_front_Nm_per_rad": front, "suspension_rear_Nm_per_rad": rear,
            "with_tyres_Nm_per_rad": 1 / (1 / front + 1 / tyre_f) + 1 / (1 / rear + 1 / tyre_r)}


def _broke_down_at(h, keep, mb, car):
    """Where CommonRoad's model stopped in a run (``crosscheck.BrokeDown``): the time and our
    car's road-wheel steer and lateral acceleration there (its channels are NaN after it)."""
    t = h["t"][keep]
    i = min(int(np.searchsorted(t, mb["broke_down_s"])), len(t) - 1)
    g = handling.cog_motion(h, whole_car_cog_to_front_m(car), car.mass.total_mass_kg)
    return {"t_s": float(mb["broke_down_s"]), "why": mb.get("broke_down_why"),
            "steer_deg": float(np.degrees(handling.road_wheel_steer_rad(h)[keep][i])),
            "ay_mps2": float(g["ay"][keep][i])}


def _paired(h, keep, mb, car):
    """Ours and MB's channels side by side (ISO signs; ours at the CoG)."""
    g = handling.cog_motion(h, whole_car_cog_to_front_m(car), car.mass.total_mass_kg)
    return {"t": h["t"][keep], "steer_deg": np.degrees(handling.road_wheel_steer_rad(h)[keep]),
            "mb_steer_deg": np.degrees(mb["steer_rad"]),
            "yaw_rate_degps": np.degrees(g["yaw_rate"][keep]),
            "mb_yaw_rate_degps": np.degrees(mb["yaw_rate_radps"]),
            "ay_mps2": g["ay"][keep], "mb_ay_mps2": mb["ay_mps2"],
            "roll_deg": np.degrees(h["roll_rad"][keep]), "mb_roll_deg": np.degrees(mb["roll_rad"]),
            "sideslip_deg": np.degrees(g["sideslip"][keep]),
            "mb_sideslip_deg": np.degrees(mb["sideslip_rad"]),
            "speed_mps": g["speed"][keep], "mb_speed_mps": mb["speed_mps"]}
