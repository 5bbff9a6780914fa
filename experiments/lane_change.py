"""The paper's study (Harlecki & Kubas, section 4): two lane changes at 60 km/h (a: left turn
first, b: right turn first) × three strut friction sets, (μs, μd) = (0, 0) with 1250 N s/m,
(0.2, 0.15) and (0.4, 0.3) dry. Writes into DIR (default results/):

  <case>_<set>.csv        the six runs a_1 ... b_3 (columns: drake_car.study.RUN_COLUMNS)
  <case>_<set>.scene.json how each run was made (car, friction, timeline, step)
  fig13.png ... fig16.png the paper's figures; wheel_loads.png before/after the manoeuvre
  summary.json, report.md each of the paper's claims: reproduced or not, the deciding number,
                          the figure; rod positions at places a and b; wall times
  diagram.svg, a_3.html   the Diagram (Graphviz) and a Meshcat replay of run a_3

Where a verdict disagrees with the paper, the runs are repeated at half the time step and the
report shows both verdicts.

Example:  python experiments/lane_change.py --out results
"""

import dataclasses
import multiprocessing
import time

import _common

from drake_car.assembly import TyreSetup, build_car_diagram
from drake_car.drive import rolling_radius
from drake_car.manoeuvre import Timeline, drive_trajectory, rack_trajectory
from drake_car.outputs import Progress, output_folder, provenance, write_csv, write_json
from drake_car.pictures import start_meshcat, write_diagram_svg
from drake_car.scene import SceneError, dump_scene
from drake_car.study import (
    PAPER_STUDY_SCENES,
    CASES, DISPLACEMENT_THRESHOLD_M, FRICTION_SETS, SYMMETRY_TOLERANCE, RunConfig,
    STUDY_CHANNELS, evaluate_claims, place_values, run_one, static_equilibrium)
from drake_car.study_plots import all_figures


def _work(args):
    config, start = args
    columns, info, _ = run_one(config, start)
    return config.name, columns, info


def run_all(configs, start, jobs, progress):
    results = {}
    tasks = [(c, start) for c in configs]
    if jobs > 1:
        with multiprocessing.get_context("spawn").Pool(jobs) as pool:
            for name, columns, info in pool.imap_unordered(_work, tasks):
                results[name] = (columns, info)
                progress.update(len(results), f"{name}: {info['simulated_s']:.1f} s simulated "
                                f"in {info['wall_s']:.1f} s")
    else:
        for task in tasks:
            name, columns, info = _work(task)
            results[name] = (columns, info)
            progress.update(len(results), f"{name}: {info['wall_s']:.1f} s wall")
    return results


def main():
    p = _common.parser(__doc__, default_out=_common.REPO_ROOT / "results")
    p.add_argument("--time_step_s", type=_common.positive("time_step_s"), default=1e-3)
    p.add_argument("--jobs", type=int, default=2, help="parallel processes (default 2)")
    p.add_argument("--scale_time", type=_common.positive("scale_time"), default=1.0,
                   help="shorten every phase by this factor (for quick checks)")
    p.add_argument("--no_verify", action="store_true",
                   help="skip the half-step repetition of disagreeing verdicts")
    p.add_argument("--no_html", action="store_true", help="skip the Meshcat replay")
    p.add_argument("--scene", default=str(PAPER_STUDY_SCENES),
                   help="the study's scenes (entries a_1 ... b_3); default: %(default)s")
    p.add_argument("--scene_text", default="",
                   help="YAML laid over every run's scene, e.g. \"car: {ball_joint_offset_b_m: 0.06}\"")
    args = p.parse_args()
    if args.jobs < 1:
        p.error("--jobs must be >= 1")
    default = Timeline()
    s = args.scale_time
    timeline = Timeline(settle_s=default.settle_s * s, speed_up_s=default.speed_up_s * s,
                        straight_s=default.straight_s * s,
                        lane_change_s=default.lane_change_s * s, calm_s=default.calm_s * s)
    began = time.perf_counter()
    configs = [RunConfig(case, n, time_step_s=args.time_step_s, timeline=timeline,
                         scene_text=args.scene_text, scene_file=args.scene)
               for case in CASES for n in FRICTION_SETS]
    try:
        scenes = {c.name: c.scene() for c in configs}
        geometry = {repr(dataclasses.replace(c.car()[0], front=dataclasses.replace(
            c.car()[0].front, strut_damping_Nspm=0.0))) for c in configs}
    except SceneError as e:
        p.error(str(e))
    if len(geometry) != 1:
        p.error("the study's runs must share the car (all but friction and strut damping): "
                "they start from one static equilibrium")
    # Every run starts at rest from the lubricated car's static equilibrium; Δd is measured
    # from its overlaps (the paper's "increments from static equilibrium").
    start = static_equilibrium(configs[0].car()[0], time_step_s=args.time_step_s)
    d_static = start.overlap_m
    progress = Progress("lane-change study", len(configs))
    results = run_all(configs, start, args.jobs, progress)
    runs = {name: cols for name, (cols, _) in results.items()}
    claims, shifts = evaluate_claims(runs, timeline, start.corner_loads_N)
    half = None
    if not args.no_verify and not all(c["reproduced"] for c in claims):
        half_configs = [dataclasses.replace(c, time_step_s=c.time_step_s / 2) for c in configs]
        half_progress = Progress("half-step check", len(half_configs))
        half_results = run_all(half_configs, start, args.jobs, half_progress)
        half_claims, _ = evaluate_claims({n: cols for n, (cols, _) in half_results.items()},
                                         timeline, start.corner_loads_N)
        half = {"time_step_s": args.time_step_s / 2,
                "verdicts": [c["reproduced"] for c in half_claims],
                "numbers": [c["number"] for c in half_claims]}

    with output_folder(args.out) as out:
        for config in configs:
            columns, info = results[config.name]
            write_csv(out / f"{config.name}.csv", columns)
            (out / f"{config.name}.scene.yaml").write_text(dump_scene(scenes[config.name]))
            params, friction = config.car()
            write_json(out / f"{config.name}.scene.json", {
                "run": config.name, "case": config.case, "friction_set": config.friction_set,
                "mu_s_mu_d": FRICTION_SETS[config.friction_set],
                "friction": None if friction is None else dataclasses.asdict(friction),
                "car": dataclasses.asdict(params), "timeline": dataclasses.asdict(timeline),
                "time_step_s": config.time_step_s,
                "tyres": {"tir": str(config.tyres.tir_path), "combined": config.tyres.combined,
                          "slip": dataclasses.asdict(config.tyres.slip)},
                "d_static_m": d_static, "result": info})
        figures = all_figures(runs, timeline, out)
        a3 = RunConfig("a", 3, time_step_s=args.time_step_s, timeline=timeline)
        params, friction = a3.car()
        built = build_car_diagram(params, time_step_s=args.time_step_s, friction=friction,
                                  tyres=TyreSetup(),
                                  rack_trajectory=rack_trajectory(timeline, _profile(), "a"),
                                  drive_trajectory=drive_trajectory(
                                      timeline, rolling_radius(params)),
                                  log_channels=STUDY_CHANNELS)  # as run_one builds it
        write_diagram_svg(built.diagram, out / "diagram.svg")
        if not args.no_html:
            _replay(a3, start, out / "a_3.html")
        wall = time.perf_counter() - began
        summary = _summary(runs, results, claims, shifts, timeline, half, wall, start,
                           figures)
        write_json(out / "summary.json", summary)
        (out / "report.md").write_text(_report(summary))
    failed = [c["claim"] for c in claims if not c["reproduced"]]
    print(f"{len(claims) - len(failed)} of {len(claims)} claims reproduced; "
          f"wrote {args.out} (report: {args.out / 'report.md'})")


def _profile():
    from drake_car.calibration import calibrated_profile
    return calibrated_profile()


def _replay(config, start, path):
    meshcat = start_meshcat()
    meshcat.StartRecording(frames_per_second=25.0)
    run_one(config, start, meshcat=meshcat)
    meshcat.StopRecording()
    meshcat.PublishRecording()
    path.write_text(meshcat.StaticHtml())


def _summary(runs, results, claims, shifts, timeline, half, wall, start, figures):
    rod_positions = {}
    for name, h in runs.items():
        rod_positions[name] = {}
        for side in ("left", "right"):
            at_a, at_b = place_values(h, timeline, f"dd_{side}_m")
            rod_positions[name][f"dd_{side}_at_a_m"] = at_a
            rod_positions[name][f"dd_{side}_at_b_m"] = at_b
    return {
        "claims": claims,
        "rod_positions": rod_positions,
        "rod_shift_b_minus_a_m": shifts,
        "runs": {name: info for name, (_, info) in results.items()},
        "half_step_check": half,
        "static_equilibrium": {
            "overlap_m": start.overlap_m, "corner_loads_N": start.corner_loads_N,
            "how": f"the lubricated car settled for {start.duration_s:g} s at "
                   f"{start.time_step_s:g} s; every run starts from it at rest",
            "max_abs_velocity_last_half_s": start.max_abs_velocity},
        "timeline_s": dataclasses.asdict(timeline),
        "figures": figures,
        "wall_s": wall,
        "provenance": provenance(),
    }


def _report(summary):
    lines = ["# The paper's study: lane change with strut friction", "",
             f"Made by `{summary['provenance']['command']}`, commit "
             f"{summary['provenance']['git_commit'][:10]}, drake {summary['provenance']['drake']},"
             f" {summary['provenance']['created_utc']}; {summary['wall_s']:.0f} s wall in all.",
             "", "## The paper's claims", "",
             "| # | claim | reproduced | deciding number | figure |", "|---|---|---|---|---|"]
    half = summary["half_step_check"]
    for i, c in enumerate(summary["claims"], start=1):
        verdict = "yes" if c["reproduced"] else "**no**"
        if half is not None:
            verdict += f" (half step: {'yes' if half['verdicts'][i - 1] else 'no'})"
        lines.append(f"| {i} | {c['claim']} | {verdict} | {c['number']} | {c['figure']} |")
    lines += ["", f"\"Practically zero\" made explicit: {1e3 * DISPLACEMENT_THRESHOLD_M:g} mm "
              f"of rod displacement; \"almost identical\" curves: within "
              f"{100 * SYMMETRY_TOLERANCE:g} % of the largest |Δd|. Places a and b are averages "
              "over the 0.3 s before the lane change and the last 0.5 s.", ""]
    disagreements = [(i, c) for i, c in enumerate(summary["claims"], start=1)
                     if not c["reproduced"]]
    if disagreements:
        lines += ["## Where the model disagrees with the paper, and why", ""]
        for i, c in disagreements:
            lines.append(f"- **{i}. {c['claim']}**: {c.get('why', '').rstrip('.')}.")
        lines.append("")
    if half is not None:
        lines += [f"Every run was repeated at half the time step ({half['time_step_s']:g} s) "
                  "because at least one verdict disagrees with the paper; the verdicts above "
                  "show both.", ""]
    lines += ["## Rod positions at places a (before the lane change) and b (end)", "",
              "| run | Δd left a [mm] | Δd left b [mm] | Δd right a [mm] | Δd right b [mm] |",
              "|---|---|---|---|---|"]
    for name, pos in sorted(summary["rod_positions"].items()):
        lines.append(f"| {name} | {1e3 * pos['dd_left_at_a_m']:.3f} | "
                     f"{1e3 * pos['dd_left_at_b_m']:.3f} | {1e3 * pos['dd_right_at_a_m']:.3f} | "
                     f"{1e3 * pos['dd_right_at_b_m']:.3f} |")
    lines += ["", "## Runs", "", "| run | wall [s] | real-time factor | lane-change shift [m] "
              "| frozen SAP steps |", "|---|---|---|---|---|"]
    for name, info in sorted(summary["runs"].items()):
        shift = info["lane_change"]["shift_m"] if info["lane_change"] else float("nan")
        lines.append(f"| {name} | {info['wall_s']:.1f} | {info['real_time_factor']:.2f} | "
                     f"{shift:.3f} | {info.get('frozen_sap_steps', 'n/a')} |")
    lines += ["", "Frozen SAP steps: steps in which Drake's solver returned its initial guess "
              "(`drake_car/systems/sap_pacer.py`); the pacer keeps them at 0."]
    lines += ["", "Figures: " + ", ".join(f"`{f}`" for f in summary["figures"]) +
              "; the Diagram: `diagram.svg`; the replay of run a_3: `a_3.html`.", ""]
    return "\n".join(lines)


if __name__ == "__main__":
    main()
