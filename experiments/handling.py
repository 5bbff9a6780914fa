"""Handling tests of the car, its understeer budget and a cross-check against an independent
model of the same car, from the two scenes of scenes/handling.yaml (steady_state: ISO 4138
continuous ramp steer at 60 km/h; step_steer: ISO 7401 step steer at 60 km/h). Writes into DIR:

  steady_state/   the run (history.csv, scene.yaml, run.json), steady_state.csv (the standard's
                  quantities at the CoG), steady_state.json (gradients, yaw gain, the
                  single-track model), steady_state.png
  step_steer/     the run, step_steer.csv, step_steer.json (response times, overshoot, gains),
                  step_steer.png
  budget.csv, budget.json, budget_series.csv, budget.png
                  the understeer gradient split into named terms (drake_car/study/understeer.py)
  crosscheck/     CommonRoad's multi-body model (parameter set 1, Ford Escort) on our runs'
                  road-wheel steer at our speed: ramp.csv, step.csv, crosscheck.json,
                  crosscheck_ramp.png, crosscheck_step.png
  steering.csv    the rack-to-road-wheel relation (chassis fixed) the understeer gradient uses
  summary.json, report.md, diagram.svg

--scene_text is laid over both scenes (e.g. "drive: !PrescribedRotation {}"); --ay_range is the
linear range the gradients are fitted over. The cross-check needs the test extra
commonroad-vehicle-models; without it (or with --no_crosscheck) it is left out and the report
says so.

Example:  python experiments/handling.py --out results/handling
          python experiments/handling.py --out results/handling_locked \\
              --scene_text "drive: !PrescribedRotation {}"
"""

import argparse
import math
import sys
import time

import matplotlib
import numpy as np

from drake_car import cli
from drake_car.data import resource
from drake_car.law.magic_formula import MagicFormulaTyre
from drake_car.model.geometry import design_axle_loads_N, whole_car_cog_to_front_m
from drake_car.model.kinematics_sweep import run_kinematics_sweep
from drake_car.model.loading import tir_path
from drake_car.scene.load import SceneError, load_scene_file
from drake_car.scene.manoeuvres import RampSteer, StepSteer
from drake_car.scene.scene import LinearTyre, MagicFormula
from drake_car.sim.outputs import (
    output_folder,
    provenance,
    write_csv,
    write_diagram_svg,
    write_json,
    write_run,
)
from drake_car.sim.simulate import simulate
from drake_car.study import crosscheck, handling
from drake_car.study.handling import DEG_PER_G as DEG
from drake_car.study.paper import StudyError
from drake_car.study.understeer import understeer_budget

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HANDLING = resource("scenes/handling.yaml")
ENTRIES = {"steady_state": RampSteer, "step_steer": StepSteer}


def ay_range(text):
    try:
        lo, hi = (float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"--ay_range: {text!r} must be two numbers LO,HI (m/s²)") from None
    if not 0 <= lo < hi <= 10:
        raise argparse.ArgumentTypeError(
            f"--ay_range: {lo}, {hi} must satisfy 0 <= LO < HI <= 10 m/s²")
    return lo, hi


def check_scenes(scenes, path):
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
        missing = {"chassis", "steering", "tyres"} - set(
            scene.logging.channels or ("chassis", "steering", "tyres"))
        if missing:
            raise SceneError(f"{path} [{name}]: logging.channels must include "
                             f"{', '.join(sorted(missing))}")


def main(argv=None):
    p = cli.parser(__doc__)
    p.add_argument("--scene", default=str(HANDLING),
                   help="the handling scenes file (default: %(default)s)")
    p.add_argument("--scene_text", default="", help="YAML laid over both scenes")
    p.add_argument("--ay_range", type=ay_range, default=handling.DEFAULT_AY_RANGE,
                   help="LO,HI: the linear range of a_y (m/s²) the gradients are fitted over "
                        "(default: 0.5,3.0)")
    p.add_argument("--no_crosscheck", action="store_true",
                   help="leave out the cross-check against CommonRoad's model")
    args = p.parse_args(argv)
    cli.check_out(args)
    scenes = load_scene_file(args.scene, args.scene_text or None)
    check_scenes(scenes, args.scene)
    available, why = crosscheck.available()
    if args.no_crosscheck:
        available, why = False, "left out (--no_crosscheck)"
    elif not available:
        print(f"warning: cross-check left out: {why}", file=sys.stderr)
    began = time.perf_counter()
    with output_folder(args.out) as out:
        walls = {}
        runs = {}
        for name in ENTRIES:
            runs[name] = simulate(scenes[name], progress=True)
            walls[f"{name} run"] = runs[name].wall_s
        started = time.perf_counter()
        try:
            result = analyse(runs, args.ay_range)
            walls["metrics and budget"] = time.perf_counter() - started
            if available:
                started = time.perf_counter()
                result["crosscheck"] = cross_check(runs, result, args.ay_range)
                walls["cross-check"] = time.perf_counter() - started
            else:
                result["crosscheck"] = {"skipped": why}
        except handling.HandlingError as e:
            raise StudyError(f"{args.scene}: {e}") from None
        write_outputs(out, runs, result)
        result["wall_s"] = {"total": time.perf_counter() - began} | walls
        result["provenance"] = provenance()
        write_json(out / "summary.json", summary(result))
        (out / "report.md").write_text(report(result))
    ss = result["steady_state"]["metrics"]
    print(f"understeer {ss['understeer_gradient_deg_per_g']:.2f} deg/g, roll "
          f"{ss['roll_gradient_deg_per_g']:.2f} deg/g, yaw gain "
          f"{result['steady_state']['yaw_gain_ratio']:.3f} of the single-track model; wrote "
          f"{args.out} (report: {args.out / 'report.md'})")


def tyre_of(scene):
    return MagicFormulaTyre.from_file(tir_path(scene.tyres.tir_file))


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
    rack_command = np.array([command.value(t)[0, 0] for t in h["t"]])
    servo = handling.steady_state(
        h, steer_rad=handling.kinematic_steer_rad(rack_command, steering),
        wheelbase_m=L, cog_offset_m=a, mass_kg=mass,
        ay_range=fit_range)["understeer_gradient_deg_per_g"]
    hs = step.history
    step_rack = handling.kinematic_steer_rad(hs["rack_m"], steering)
    step_metrics = handling.step_steer(hs, steer_rad=step_rack, cog_offset_m=a, mass_kg=mass)
    step_wheel = handling.step_steer(hs, steer_rad=handling.road_wheel_steer_rad(hs),
                                     cog_offset_m=a, mass_kg=mass)
    return {
        "fit_range_mps2": list(fit_range), "steering": steering,
        "mass_kg": car.mass.total_mass_kg, "cog_offset_m": a, "wheelbase_m": L,
        "t_steer_s": {name: handling.first_time(r.history["phase"], r.history["t"], "III")
                      for name, r in runs.items()},
        "drive": type(ramp.scene.drive).__name__,
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


def step_series(h, rack_steer, cog_offset, mass):
    g = handling.cog_motion(h, cog_offset, mass)
    return {"t": h["t"], "steer_deg": np.degrees(rack_steer),
            "wheel_steer_deg": np.degrees(handling.road_wheel_steer_rad(h)),
            "yaw_rate_degps": np.degrees(g["yaw_rate"]), "ay_mps2": g["ay"],
            "roll_deg": np.degrees(h["roll_rad"]), "sideslip_cog_deg": np.degrees(g["sideslip"]),
            "speed_mps": g["speed"]}


def cross_check(runs, result, fit_range):
    """CommonRoad's MB on our runs' road-wheel steer and speed; its metrics; the single-track
    chain from its data to ours; the understeer reconciliation."""
    p = crosscheck.parameters()
    L_mb = p.a + p.b
    out = {"parameters": {k: getattr(p, k) for k in (
        "m", "m_s", "a", "b", "I_z", "h_s", "T_f", "T_r", "K_sf", "K_sr", "K_tsf", "K_tsr",
        "K_zt", "h_raf", "h_rar")} | {"tire_p_ky1": p.tire.p_ky1}}
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
    mb_ss = handling.steady_state(mb_ramp, steer_rad=mb_ramp["steer_rad"], wheelbase_m=L_mb,
                                  cog_offset_m=0.0, ay_range=fit_range)
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
    out.update(
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


def write_outputs(out, runs, result):
    for name, run in runs.items():
        (out / name).mkdir()
        write_run(run, out / name, diagram=False)
    write_diagram_svg(runs["steady_state"].diagram_dot, out / "diagram.svg")
    ss, st, budget = result["steady_state"], result["step_steer"], result["budget"]
    write_csv(out / "steady_state" / "steady_state.csv", ss["series"])
    write_json(out / "steady_state" / "steady_state.json",
               {k: v for k, v in ss.items() if k != "series"})
    write_csv(out / "step_steer" / "step_steer.csv", st["series"])
    write_json(out / "step_steer" / "step_steer.json",
               {k: v for k, v in st.items() if k != "series"})
    write_csv(out / "steering.csv", result["steering"])
    write_csv(out / "budget.csv", {k: [row[k] for row in budget["rows"]]
                                   for k in ("key", "term", "gradient_deg_per_g", "share_pct",
                                             "how")})
    write_csv(out / "budget_series.csv", budget["series"])
    write_json(out / "budget.json", {k: v for k, v in budget.items() if k != "series"})
    result["figures"] = handling_figures(result, out)
    cc = result["crosscheck"]
    if "skipped" not in cc:
        (out / "crosscheck").mkdir()
        write_csv(out / "crosscheck" / "ramp.csv", cc["series_ramp"])
        write_csv(out / "crosscheck" / "step.csv", cc["series_step"])
        write_json(out / "crosscheck" / "crosscheck.json",
                   {k: v for k, v in cc.items() if not k.startswith("series")})
        result["figures"] |= crosscheck_figures(result, out)


def summary(result):
    """What summary.json holds: every number, no series."""
    def strip(d):
        return {k: (strip(v) if isinstance(v, dict) else v) for k, v in d.items()
                if k not in ("series", "series_ramp", "series_step", "steering")}
    return strip(result)



# -- figures ---------------------------------------------------------------------------------

DPI = 110
OUTSIDE = dict(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, fontsize=8)


def _save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=DPI, bbox_inches="tight")
    plt.close(fig)


def _shade(ax, fit_range):
    ax.axvspan(*fit_range, color="0.9", zorder=0, label="fit range")


def handling_figures(result, out):
    ss, st, budget = result["steady_state"], result["step_steer"], result["budget"]
    m, single, s = ss["metrics"], ss["single_track"], ss["series"]
    fit = result["fit_range_mps2"]
    turning = s["t"] >= result["t_steer_s"]["steady_state"]
    ay = s["ay_mps2"][turning]
    v = m["speed_mps"]
    L = result["wheelbase_m"]
    line = np.linspace(0.0, float(ay.max()), 50)
    fig, axes = plt.subplots(2, 3, figsize=(15, 8))
    ax = axes[0, 0]
    _shade(ax, fit)
    ax.plot(ay, s["understeer_deg"][turning], label="δ (rack) − L r/V")
    ax.plot(ay, (s["wheel_steer_deg"] - s["steer_deg"] + s["understeer_deg"])[turning],
            label="δ (wheels) − L r/V")
    k = m["understeer_gradient_deg_per_g"]
    ax.plot(line, m["understeer_intercept_deg"] + k * line / 9.81, "k--", lw=1,
            label=f"fit: {k:.2f} deg/g")
    ax.plot(line, single["understeer_gradient_deg_per_g"] * line / 9.81, ":", color="tab:red",
            label=f"single track: {single['understeer_gradient_deg_per_g']:.2f} deg/g")
    ax.set(xlabel="a_y at the CoG (m/s²)", ylabel="deg", title="understeer (ISO 4138)")
    ax.legend(fontsize=8)
    ax = axes[0, 1]
    ax.plot(ay, s["steer_deg"][turning], label="δ from the rack")
    ax.plot(ay, s["wheel_steer_deg"][turning], label="δ of the wheels")
    ax.plot(line, np.degrees(L * line / v ** 2), "k:", label="neutral: L a_y/V²")
    ax.set(xlabel="a_y (m/s²)", ylabel="road-wheel angle (deg)", title="steer angle")
    ax.legend(fontsize=8)
    for ax, key, label, grad in (
            (axes[0, 2], "roll_deg", "roll (deg)", "roll_gradient_deg_per_g"),
            (axes[1, 0], "sideslip_cog_deg", "sideslip at the CoG (deg)",
             "sideslip_gradient_deg_per_g"),
            (axes[1, 1], "rack_force_N", "rack force (N)", "rack_force_gradient_N_per_g")):
        _shade(ax, fit)
        ax.plot(ay, s[key][turning])
        value = f"{m[grad]:.0f} N/g" if key == "rack_force_N" else f"{m[grad]:.2f} deg/g"
        ax.set(xlabel="a_y (m/s²)", ylabel=label,
               title=f"{label.split(' (')[0]}: {value} in the fit range")
    axes[1, 0].plot(line, single["sideslip_gradient_deg_per_g"] * line / 9.81, ":",
                    color="tab:red", label="single track")
    axes[1, 0].legend(fontsize=8)
    ax = axes[1, 2]
    ax.plot(s["steer_deg"][turning], s["yaw_rate_degps"][turning], label="measured")
    d = np.linspace(0.0, float(s["steer_deg"][turning].max()), 20)
    ax.plot(d, single["yaw_rate_gain_per_s"] * d, ":", color="tab:red",
            label=f"single track: {single['yaw_rate_gain_per_s']:.2f} /s")
    ax.set(xlabel="δ from the rack (deg)", ylabel="yaw rate (deg/s)",
           title=f"yaw-rate gain {m['yaw_rate_gain_per_s']:.2f} /s in the fit range "
                 f"({ss['yaw_gain_ratio']:.3f} of the single track)")
    ax.legend(fontsize=8)
    fig.suptitle(f"Steady-state circular driving, ramp steer at {3.6 * v:.1f} km/h "
                 f"({result['drive']})")
    _save(fig, out / "steady_state" / "steady_state.png")

    sr, sm = st["series"], st["metrics"]
    t50 = sm["yaw_rate"]["steer_50pct_s"]
    t = sr["t"] - t50
    show = (t > -0.5) & (t < 2.5)
    fig, axes = plt.subplots(2, 2, figsize=(12, 7))
    axes[0, 0].plot(t[show], sr["steer_deg"][show], label="from the rack")
    axes[0, 0].plot(t[show], sr["wheel_steer_deg"][show], label="of the wheels")
    axes[0, 0].set(ylabel="road-wheel angle (deg)", title="steer")
    axes[0, 0].legend(fontsize=8)
    for ax, key, name, scale, unit in (
            (axes[0, 1], "yaw_rate_degps", "yaw_rate", math.degrees(1), "deg/s"),
            (axes[1, 0], "ay_mps2", "lateral_acceleration", 1.0, "m/s²")):
        r = sm[name]
        ax.plot(t[show], sr[key][show])
        ax.axhline(r["steady"] * scale, color="k", lw=0.8, ls="--", label="steady")
        ax.axhline(0.9 * r["steady"] * scale, color="0.5", lw=0.8, ls=":", label="90 %")
        ax.axvline(r["response_time_s"], color="tab:green", lw=0.8,
                   label=f"response time {r['response_time_s']:.3f} s")
        if r["peak_response_time_s"] is not None:
            ax.axvline(r["peak_response_time_s"], color="tab:red", lw=0.8,
                       label=f"peak {r['peak_response_time_s']:.3f} s, "
                             f"+{r['overshoot_pct']:.1f} %")
        ax.set(ylabel=unit, title=name.replace("_", " ") + " (at the CoG)")
        ax.legend(fontsize=8)
    ax = axes[1, 1]
    ax.plot(t[show], sr["roll_deg"][show], label="roll")
    ax.plot(t[show], sr["sideslip_cog_deg"][show], label="sideslip at the CoG")
    ax.set(ylabel="deg", title="roll and sideslip")
    ax.legend(fontsize=8)
    for ax in axes.flat:
        ax.set_xlabel("time from 50 % steer (s)")
        ax.grid(alpha=0.3)
    fig.suptitle(f"Step steer at {3.6 * sm['speed_mps']:.1f} km/h (ISO 7401, {result['drive']})")
    _save(fig, out / "step_steer" / "step_steer.png")

    rows = budget["rows"]
    fig, ax = plt.subplots(figsize=(10, 6))
    names = [r["term"] for r in rows]
    values = [r["gradient_deg_per_g"] for r in rows]
    colours = ["0.6" if "remainder" in r["key"] or r["key"] == "slip_spread" else "tab:blue"
               for r in rows]
    y = np.arange(len(rows))[::-1]
    ax.barh(y, values, color=colours)
    ax.set_yticks(y, names, fontsize=8)
    ax.axvline(0, color="k", lw=0.8)
    ax.set(xlabel="contribution to the understeer gradient (deg/g)",
           title=f"Understeer budget: measured {budget['measured_deg_per_g']:.3f} deg/g, named "
                 f"terms {budget['named_sum_deg_per_g']:.3f}, remainders (grey) "
                 f"{budget['remainder_deg_per_g']:+.3f}")
    _save(fig, out / "budget.png")
    return {"steady_state/steady_state.png": "ramp steer: understeer, steer angle, roll, "
                                             "sideslip, rack force against a_y; yaw rate "
                                             "against steer; the single-track model dotted",
            "step_steer/step_steer.png": "step steer: steer, yaw rate and a_y with their "
                                         "response and peak times, roll and sideslip",
            "budget.png": "the understeer budget's terms"}


def crosscheck_figures(result, out):
    cc = result["crosscheck"]
    s = cc["series_ramp"]
    fit = result["fit_range_mps2"]
    v = result["steady_state"]["metrics"]["speed_mps"]
    L, L_mb = result["wheelbase_m"], cc["parameters"]["a"] + cc["parameters"]["b"]
    turning = s["t"] >= result["t_steer_s"]["steady_state"]
    fig, axes = plt.subplots(2, 2, figsize=(12, 8))
    for ax, key, label in ((axes[0, 0], "under", "δ (wheels) − L r/V (deg)"),
                           (axes[0, 1], "roll_deg", "roll (deg)"),
                           (axes[1, 0], "sideslip_deg", "sideslip at the CoG (deg)")):
        _shade(ax, fit)
        if key == "under":
            ours = s["steer_deg"] - np.degrees(L * np.radians(s["yaw_rate_degps"]) / s["speed_mps"])
            mb = s["mb_steer_deg"] - np.degrees(
                L_mb * np.radians(s["mb_yaw_rate_degps"]) / s["mb_speed_mps"])
        else:
            ours, mb = s[key], s["mb_" + key]
        ax.plot(s["ay_mps2"][turning], ours[turning], label="drake_car")
        ax.plot(s["mb_ay_mps2"][turning], mb[turning], label="CommonRoad MB")
        ax.set(xlabel="a_y (m/s²)", ylabel=label)
        ax.legend(fontsize=8)
    ax = axes[1, 1]
    ax.plot(s["steer_deg"][turning], s["yaw_rate_degps"][turning], label="drake_car")
    ax.plot(s["mb_steer_deg"][turning], s["mb_yaw_rate_degps"][turning], label="CommonRoad MB")
    ax.set(xlabel="road-wheel angle (deg)", ylabel="yaw rate (deg/s)")
    ax.legend(fontsize=8)
    fig.suptitle(f"Ramp steer at {3.6 * v:.1f} km/h: drake_car against CommonRoad's multi-body "
                 "model (parameter set 1), same road-wheel steer")
    _save(fig, out / "crosscheck" / "crosscheck_ramp.png")

    s = cc["series_step"]
    t50 = result["step_steer"]["metrics"]["yaw_rate"]["steer_50pct_s"]
    t = s["t"] - t50
    fig, axes = plt.subplots(2, 2, figsize=(12, 7))
    for ax, key, label in ((axes[0, 0], "yaw_rate_degps", "yaw rate (deg/s)"),
                           (axes[0, 1], "ay_mps2", "a_y at the CoG (m/s²)"),
                           (axes[1, 0], "roll_deg", "roll (deg)"),
                           (axes[1, 1], "sideslip_deg", "sideslip at the CoG (deg)")):
        ax.plot(t, s[key], label="drake_car")
        ax.plot(t, s["mb_" + key], label="CommonRoad MB")
        ax.set(xlabel="time from 50 % steer (s)", ylabel=label)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("Step steer: drake_car against CommonRoad's multi-body model, same road-wheel "
                 "steer")
    _save(fig, out / "crosscheck" / "crosscheck_step.png")
    return {"crosscheck/crosscheck_ramp.png": "ramp steer, ours against CommonRoad's MB: "
                                              "understeer, roll, sideslip against a_y; yaw "
                                              "rate against steer",
            "crosscheck/crosscheck_step.png": "step steer, ours against CommonRoad's MB: yaw "
                                              "rate, a_y, roll, sideslip"}



# -- the report ------------------------------------------------------------------------------

def _f(value, digits=3, signed=False):
    if value is None:
        return "–"
    return f"{value:+.{digits}g}" if signed else f"{value:.{digits}g}"


def _fixed(value, digits=3):
    return "–" if value is None else f"{value:+.{digits}f}"


def _diff(ours, theirs):
    if ours is None or theirs is None or theirs == 0:
        return None
    return 100.0 * (ours - theirs) / abs(theirs)


def report(result):
    prov, walls = result["provenance"], result["wall_s"]
    ss, st, budget = result["steady_state"], result["step_steer"], result["budget"]
    m, single = ss["metrics"], ss["single_track"]
    lo, hi = result["fit_range_mps2"]
    v = m["speed_mps"]
    wall_parts = ", ".join(f"{k} {v:.1f} s" for k, v in walls.items() if k != "total")
    lines = [
        "# drake_car: handling (ISO 4138, ISO 7401), understeer budget, cross-check", "",
        f"Made by `{prov['command']}`; {prov['created_utc']}, drake {prov['drake']}, commit "
        f"{(prov['git_commit'] or 'unknown')[:10]}. Drive: **{result['drive']}**. Wall time "
        f"**{walls['total']:.0f} s** ({wall_parts}). The scenes as they ran: "
        "`steady_state/scene.yaml`, `step_steer/scene.yaml`.", "",
        "Signs are ISO 8855 (x forward, y left, z up): in a left turn δ, r, a_y and roll (right "
        "side down) are positive; sideslip is positive with the velocity left of the heading. "
        "The chassis channels are logged at the body origin (the ground point midway between "
        "the front wheels); the standards' CoG quantities are moved to the CoG "
        f"({result['cog_offset_m']:.3f} m behind it) by rigid-body kinematics in the heading "
        "frame (v_y,G = v_y,O − a r); a_y at the CoG is the whole car's by Newton, the tyres' "
        "lateral forces (heading frame) over the mass. **δ from the rack** is the road-wheel "
        "angle the rack alone gives (mean of left and right, chassis fixed: `steering.csv`), "
        "i.e. ISO's steering-wheel angle over the overall steering ratio; **δ of the wheels** "
        "is the measured mean of the two front wheels' steer to the body (roll steer "
        f"included). Gradients are least-squares slopes over a_y = {lo:g} … {hi:g} m/s² "
        f"(t = {m['t_range_s'][0]:.2f} … {m['t_range_s'][1]:.2f} s, {m['samples']} samples), "
        f"at the speed the car held there: {v:.3f} m/s = {3.6 * v:.2f} km/h "
        f"({m['speed_range_mps'][0]:.3f} … {m['speed_range_mps'][1]:.3f} m/s).", "",
        "## Steady-state circular driving (ISO 4138, continuous ramp steer)", "",
        "| quantity | value |", "|---|---|",
        f"| understeer gradient K = d(δ − L r/V)/da_y, δ from the rack | "
        f"**{m['understeer_gradient_deg_per_g']:.3f} deg/g** |",
        f"| understeer gradient, δ of the wheels | "
        f"{m['understeer_gradient_wheel_deg_per_g']:.3f} deg/g |",
        f"| steer-angle gradient dδ/da_y (rack) | {m['steer_gradient_deg_per_g']:.3f} deg/g |",
        f"| roll gradient | **{m['roll_gradient_deg_per_g']:.2f} deg/g** |",
        f"| sideslip gradient at the CoG | {m['sideslip_gradient_deg_per_g']:.2f} deg/g |",
        f"| rack-force gradient | {m['rack_force_gradient_N_per_g']:.0f} N/g |",
        f"| yaw-rate gain dr/dδ (rack) | {m['yaw_rate_gain_per_s']:.3f} 1/s = "
        f"**{ss['yaw_gain_ratio']:.3f} × single track** ({single['yaw_rate_gain_per_s']:.3f} 1/s)"
        " |",
        f"| yaw-rate gain dr/dδ (wheels) | {m['yaw_rate_gain_wheel_per_s']:.3f} 1/s = "
        f"{ss['yaw_gain_ratio_wheel']:.3f} × single track |",
        f"| highest a_y of the run | {m['max_ay_mps2']:.2f} m/s² |",
        f"| a_y rise in the fit range | {m['ay_rate_mps2_per_s']:.2f} m/s² per s |", "",
        "Local understeer gradient (rack δ), how it grows towards the limit: " + ", ".join(
            f"{b['ay_range_mps2'][0]:g}–{b['ay_range_mps2'][1]:g} m/s²: "
            f"{b['understeer_gradient_deg_per_g']:.2f}" for b in m["local_understeer"])
        + " deg/g.", "",
        "**The single-track model from the car's own parameters**: mass "
        f"{result['mass_kg']:.1f} kg, CoG {result['cog_offset_m']:.3f} m behind the front axle, "
        f"wheelbase {result['wheelbase_m']:.3f} m; axle cornering stiffness from the .tir at "
        "half the static axle load per tyre (m g b/L, m g a/L: "
        f"{single['axle_loads_N']['front']:.0f} / {single['axle_loads_N']['rear']:.0f} N), "
        "zero camber: C_f = "
        f"{single['front_stiffness_N_per_rad'] / 1e3:.1f} kN/rad, C_r = "
        f"{single['rear_stiffness_N_per_rad'] / 1e3:.1f} kN/rad; K = m/L (b/C_f − a/C_r) = "
        f"{single['understeer_gradient_deg_per_g']:.3f} deg/g, r/δ = V/(L + K V²) = "
        f"{single['yaw_rate_gain_per_s']:.3f} 1/s at {v:.2f} m/s, sideslip gradient "
        f"{single['sideslip_gradient_deg_per_g']:.2f} deg/g, characteristic speed "
        f"{_f(single['characteristic_speed_kph'], 4)} km/h.", "",
        f"The steering servo (the rack held at its command by a stiff PD) gives "
        f"{ss['steering_servo_deg_per_g']:+.3f} deg/g more if K is taken on the rack's command "
        "instead of its position; K above uses the position (a real column's compliance "
        "would add here).", "",
    ]
    lines += _step_section(st)
    lines += _budget_section(budget, m)
    lines += _crosscheck_section(result)
    lines += ["## Figures", ""] + [f"- `{name}`: {caption}"
                                   for name, caption in result["figures"].items()] + [""]
    return "\n".join(lines)


def _step_section(st):
    sm = st["metrics"]
    y, a = sm["yaw_rate"], sm["lateral_acceleration"]
    return [
        "## Step steer (ISO 7401)", "",
        f"Road-wheel step {sm['steer_deg']:.2f} deg (from the rack), speed held "
        f"{sm['speed_mps']:.3f} m/s. Times from 50 % of the steer input; steady values over "
        "the last second.", "",
        "| | yaw rate | a_y at the CoG |", "|---|---|---|",
        f"| steady value | {math.degrees(y['steady']):.3f} deg/s | {a['steady']:.3f} m/s² |",
        f"| gain per road-wheel angle (rack) | {y['gain']:.3f} 1/s | {a['gain']:.1f} m/s² per "
        "rad |",
        f"| gain per road-wheel angle (wheels) | {st['wheel_steer_gains']['yaw_rate_per_s']:.3f}"
        f" 1/s | {st['wheel_steer_gains']['lateral_acceleration_mps2_per_rad']:.1f} m/s² per "
        "rad |",
        f"| response time (50 % steer → 90 % of steady) | **{_f(y['response_time_s'])} s** | "
        f"**{_f(a['response_time_s'])} s** |",
        f"| peak response time | {_f(y['peak_response_time_s'])} s | "
        f"{_f(a['peak_response_time_s'])} s |",
        f"| overshoot | {y['overshoot_pct']:.1f} % | {a['overshoot_pct']:.1f} % |", "",
        f"Steady roll {math.degrees(sm['roll']['steady']):.2f} deg (overshoot "
        f"{sm['roll']['overshoot_pct']:.1f} %), sideslip at the CoG "
        f"{math.degrees(sm['sideslip']['steady']):.2f} deg.", ""]


def _budget_section(budget, m):
    lines = [
        "## Understeer budget", "",
        "The identity: with α* = −α (the logged slip angle is ISO's, positive when the wheel "
        "moves to its left, the force then negative) the axles' mean slip angles towards the "
        "turn, a rigid car in a steady turn at small angles (tan α ≈ α, cos δ ≈ 1, V r ≈ a_y) "
        "has δ_wheels − L r/V = α*_f − α*_r + ε, and δ_rack = δ_wheels + roll steer. The force "
        "each axle needs comes from the steady lateral and yaw balances about the CoG "
        "(Y_f = m a_y b/L − Σ Fx sin δ − (ΣMz + M_x)/L, Y_r = m a_y a/L + (ΣMz + M_x)/L, "
        "M_x = −Σ y_i Fx_i cos δ_i, plus the front Fy's own cos δ and track × sin δ "
        "projections); the slip an axle needs for a force is the common slip of its two "
        "tyres (the scene's Magic Formula, right tyres mirrored) at given loads, cambers and "
        "longitudinal slips. Each term below changes one thing along that chain (in the "
        "table's order; an interaction lands in the later term) and is the gradient of the "
        "change of α*_f − α*_r against a_y, so the terms sum exactly to the measured "
        "gradient; what the named terms do not explain is in the three remainders. "
        "Source: `drake_car/study/understeer.py`.", "",
        "| term | deg/g | share | how |", "|---|---|---|---|"]
    for row in budget["rows"]:
        lines.append(f"| {row['term']} | {row['gradient_deg_per_g']:+.3f} | "
                     f"{row['share_pct']:+.1f} % | {row['how']} |")
    ok = abs(budget["remainder_pct"]) <= 10
    lines += [
        f"| **named terms** | **{budget['named_sum_deg_per_g']:.3f}** | "
        f"{100 - budget['remainder_pct']:.1f} % | |",
        f"| **measured (δ from the rack)** | **{budget['measured_deg_per_g']:.3f}** | 100 % | "
        f"fit over the same {budget['samples']} samples; {m['understeer_gradient_deg_per_g']:.3f}"
        " over all of them |", "",
        f"The named terms give {budget['named_sum_deg_per_g']:.3f} of the measured "
        f"{budget['measured_deg_per_g']:.3f} deg/g: the remainders are "
        f"{budget['remainder_pct']:+.1f} % ({'within' if ok else 'NOT within'} 10 %). "
        "Static state (the straight's last second): wheel loads "
        + ", ".join(f"{w} {v:.0f} N" for w, v in budget["static_wheel_loads_N"].items())
        + "; axle cornering stiffness there "
        f"{budget['axle_stiffness_N_per_rad']['front'] / 1e3:.1f} / "
        f"{budget['axle_stiffness_N_per_rad']['rear'] / 1e3:.1f} kN/rad (front/rear). "
        "Without roll steer (δ of the wheels) the gradient is "
        f"{budget['measured_wheel_deg_per_g']:.3f} deg/g.", ""]
    return lines


def _crosscheck_section(result):
    cc = result["crosscheck"]
    if "skipped" in cc:
        return ["## Cross-check against CommonRoad's multi-body model", "",
                f"Not run: {cc['skipped']}.", ""]
    ours, mb, chain = result["steady_state"]["metrics"], cc["ramp"], cc["chain"]
    p, roll = cc["parameters"], cc["roll_model"]
    step, mb_step = result["step_steer"]["metrics"], cc["step"]
    v = ours["speed_mps"]
    rec = {r["key"]: r for r in cc["reconciliation"]}
    k_o, k_m = ours["understeer_gradient_wheel_deg_per_g"], mb["understeer_gradient_deg_per_g"]
    L, L_mb = result["wheelbase_m"], p["a"] + p["b"]
    gain = (lambda k, length: v / (length + k / DEG * v * v))
    predicted = gain(k_o, L) / gain(k_m, L_mb)
    measured = ours["yaw_rate_gain_wheel_per_s"] / mb["yaw_rate_gain_per_s"]
    c_mb, _, c_tyre, c_ours, _, c_relax = chain
    r_ours = cc["our_roll_stiffness"]
    arm = cc["our_equivalent_roll_arm_m"]
    ay_ratio = step["lateral_acceleration"]["steady"] / mb_step["lateral_acceleration"]["steady"]

    def chain_text(key):
        steps = ", ".join(f"{c['model']} {_f(c[key])}" for c in chain[1:])
        return f"single track (same steer) from its data {_f(c_mb[key])} s; then {steps} s"

    def rest(measured, model, channel):
        a, b = measured[channel]["response_time_s"], model[f"{channel}_response_time_s"]
        return "–" if a is None or b is None else f"{a - b:+.3f} s"

    k_text = ("reconciled part by part in the next table: MB's lever/load inconsistency "
              f"{rec['levers']['mb']:+.2f} (its), our tyres' Kyα at our static loads "
              f"{rec['tyres']['ours']:+.2f}, our load sensitivity "
              f"{rec['load_transfer']['ours']:+.2f} and aligning moments "
              f"{rec['aligning']['ours']:+.2f} (MB has neither), camber ours "
              f"{rec['camber']['ours']:+.2f} vs its {_f(rec['camber']['mb'], 2, True)}, our "
              f"drive and Fy projections {rec['drive']['ours']:+.2f}, rest ours "
              f"{rec['rest']['ours']:+.2f} vs its {rec['rest']['mb']:+.2f} deg/g")
    rows = [
        ("understeer gradient, δ of the wheels (deg/g)", k_o, k_m, k_text),
        ("yaw-rate gain dr/dδ (1/s)", ours["yaw_rate_gain_wheel_per_s"],
         mb["yaw_rate_gain_per_s"],
         f"follows K: V/(L + K V²) with the two K's gives ours/its {predicted:.3f} (measured "
         f"{measured:.3f})"),
        ("roll gradient (deg/g)", ours["roll_gradient_deg_per_g"], mb["roll_gradient_deg_per_g"],
         f"its roll model: roll axis at the ground (arm h_s = {roll['roll_arm_m']:.3f} m), "
         f"K_φ = {roll['with_tyres_Nm_per_rad'] / 1e3:.1f} kN m/rad (corner springs "
         f"{roll['suspension_front_Nm_per_rad'] / 1e3:.1f} / "
         f"{roll['suspension_rear_Nm_per_rad'] / 1e3:.1f} incl. its K_tsf, tyres in series): "
         f"{roll['roll_gradient_deg_per_g']:.2f} deg/g by hand. Our parameters counted the "
         f"same way (wheel rates, anti-roll bars, tyres) give K_φ = "
         f"{r_ours['with_tyres_Nm_per_rad'] / 1e3:.1f} kN m/rad; with it our gradient needs an "
         f"arm of {arm:.3f} m, i.e. our suspension kinematics (roll centres, and jacking "
         f"by the tyres' forces) act as a roll axis ≈{roll['roll_arm_m'] - arm:.2f} m above "
         "the ground on average (its: at the ground)"),
        ("sideslip gradient at the CoG (deg/g)", ours["sideslip_gradient_deg_per_g"],
         mb["sideslip_gradient_deg_per_g"],
         "rear tyre stiffness: single track b/V² − m a/(L C_r) gives "
         f"{c_mb['sideslip_gradient_deg_per_g']:+.2f} with its C_r = "
         f"{c_mb['rear_stiffness_N_per_rad'] / 1e3:.0f} kN/rad, "
         f"{c_tyre['sideslip_gradient_deg_per_g']:+.2f} with our .tir's "
         f"{c_tyre['rear_stiffness_N_per_rad'] / 1e3:.0f} kN/rad, "
         f"{c_ours['sideslip_gradient_deg_per_g']:+.2f} with our mass and CoG; beyond the "
         "single track (load transfer, camber, aligning moments, roll) ours "
         f"{ours['sideslip_gradient_deg_per_g'] - c_ours['sideslip_gradient_deg_per_g']:+.2f}"
         f", its {mb['sideslip_gradient_deg_per_g'] - c_mb['sideslip_gradient_deg_per_g']:+.2f}"),
        ("step: yaw-rate gain, δ of the wheels (1/s)",
         result["step_steer"]["wheel_steer_gains"]["yaw_rate_per_s"], mb_step["yaw_rate"]["gain"],
         "as the ramp's yaw-rate gain (K)"),
        ("step: yaw-rate response time (s)", step["yaw_rate"]["response_time_s"],
         mb_step["yaw_rate"]["response_time_s"], chain_text("yaw_rate_response_time_s")
         + "; the rest (beyond the single track: roll, load transfer, camber, roll steer) ours "
         + rest(step, c_relax, "yaw_rate") + ", its " + rest(mb_step, c_mb, "yaw_rate")),
        ("step: yaw-rate overshoot (%)", step["yaw_rate"]["overshoot_pct"],
         mb_step["yaw_rate"]["overshoot_pct"],
         "single-track overshoot from its data to ours: "
         + ", ".join(f"{c['yaw_rate_overshoot_pct']:.1f}" for c in chain)
         + " %; the rest is the roll and load-transfer dynamics"),
        ("step: a_y response time (s)", step["lateral_acceleration"]["response_time_s"],
         mb_step["lateral_acceleration"]["response_time_s"],
         chain_text("lateral_acceleration_response_time_s")
         + "; the rest (roll, load transfer and camber building up over the roll mode) ours "
         + rest(step, c_relax, "lateral_acceleration") + ", its "
         + rest(mb_step, c_mb, "lateral_acceleration")),
        ("step: steady a_y (m/s²)", step["lateral_acceleration"]["steady"],
         mb_step["lateral_acceleration"]["steady"],
         "the same steer, its higher yaw-rate gain (K, above)"),
        ("step: steady roll (deg)", math.degrees(step["roll"]["steady"]),
         math.degrees(mb_step["roll"]["steady"]),
         f"its higher a_y (ours/its {ay_ratio:.3f}) times the roll gradients' ratio "
         f"{ours['roll_gradient_deg_per_g'] / mb['roll_gradient_deg_per_g']:.3f} (above): "
         f"{ay_ratio * ours['roll_gradient_deg_per_g'] / mb['roll_gradient_deg_per_g']:.3f}"),
        ("step: steady sideslip at the CoG (deg)", math.degrees(step["sideslip"]["steady"]),
         math.degrees(mb_step["sideslip"]["steady"]), "as the sideslip gradient (above)"),
    ]
    lines = [
        "## Cross-check against CommonRoad's multi-body model (Ford Escort, parameter set 1)",
        "",
        "CommonRoad's MB model (`vehiclemodels`, unchanged; wrapper "
        "`drake_car/study/crosscheck.py`) driven by our runs' measured road-wheel angle (mean "
        "of steer_fl/fr, its sign flipped to its SAE frame) at the speed our car held, "
        "settled straight for 4 s first. Its steer, yaw rate, a_y and sideslip are converted "
        "back to ISO signs (roll keeps its sign). a_y is each whole car's CoG's (its tyre "
        "forces over its mass), sideslip is at its sprung mass's CoG (0.884 m behind the "
        "front axle) and at the point on the ground below our CoG (0.884 m). Both "
        "understeer gradients here use the wheels' angle (ours without roll steer). "
        "Differences over 10 % are attributed in the last column.", "",
        "| quantity | drake_car | CommonRoad MB | difference | attribution |",
        "|---|---|---|---|---|"]
    for name, a, b, why in rows:
        d = _diff(a, b)
        note = why if d is None or abs(d) > 10 else "within 10 %"
        lines.append(f"| {name} | {_f(a, 4)} | {_f(b, 4)} | "
                     f"{'–' if d is None else f'{d:+.0f} %'} | {note} |")
    lines += [
        "", "**The understeer gradients as sums of the same parts** (deg/g; each column sums "
        "to its model's gradient with the wheels' angle):", "",
        "| part | drake_car | CommonRoad MB |", "|---|---|---|"]
    for r in cc["reconciliation"]:
        lines.append(f"| {r['part']} | {_fixed(r['ours'])} | {_fixed(r['mb'])} |")
    lines += [
        f"| **sum** | **{k_o:.3f}** | **{k_m:.3f}** |", "",
        f"MB's camber part is its gradient with its tyres' camber-sign terms off for the run "
        f"({cc['ramp_no_camber_sign']['understeer_gradient_deg_per_g']:.3f} deg/g) subtracted "
        f"from its own. Its tyre: Kyα = {abs(p['tire_p_ky1']):.2f} Fz per tyre at any load (no "
        "load sensitivity, so lateral load transfer does not change its axles' stiffness), no "
        "aligning moment, no relaxation; its static loads "
        f"{cc['static_axle_loads_N']['front']:.0f} / {cc['static_axle_loads_N']['rear']:.0f} N "
        "include the unsprung masses while its yaw lever arms are the sprung mass's a, b "
        "(its whole-car CoG is 0.917 m behind the front axle).", "",
        "**Single-track models from its data to ours**, one difference at a time (the step's "
        "times from the same steer series):", "",
        "| model | C_f / C_r (kN/rad) | m (kg) | a (m) | I_z (kg m²) | σ (m) | K (deg/g) | "
        "r/δ (1/s) | sideslip grad. | yaw resp. (s) | a_y resp. (s) |",
        "|---|---|---|---|---|---|---|---|---|---|---|"]
    for c in chain:
        lines.append(
            f"| {c['model']} | {c['front_stiffness_N_per_rad'] / 1e3:.1f} / "
            f"{c['rear_stiffness_N_per_rad'] / 1e3:.1f} | {c['mass_kg']:.1f} | "
            f"{c['cog_to_front_m']:.3f} | {c['yaw_inertia_kgm2']:.0f} | {c['relaxation_m']:.2f} "
            f"| {c['understeer_gradient_deg_per_g']:.3f} | {c['yaw_rate_gain_per_s']:.3f} | "
            f"{c['sideslip_gradient_deg_per_g']:+.2f} | {_f(c['yaw_rate_response_time_s'])} | "
            f"{_f(c['lateral_acceleration_response_time_s'])} |")
    inertia = cc["our_inertia"]
    lines += [
        "", f"Our whole car (the plant at its design position): {inertia['mass_kg']:.1f} kg, "
        f"CoG {-inertia['cog_m'][0]:.4f} m behind the front axle and {inertia['cog_m'][2]:.3f} m "
        f"high, yaw inertia {inertia['yaw_inertia_kgm2']:.0f} kg m² (MB: {p['I_z']:.0f}, the "
        "sprung mass's, used for the whole car). Sprung mass ours "
        f"{cc['our_sprung_mass_kg']:.1f} kg, its {p['m_s']:.1f} kg.", ""]
    return lines


if __name__ == "__main__":
    cli.run_main(main)
