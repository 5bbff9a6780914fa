"""The design study: where, over the strut's design and the severity of use, does strut
friction change the front wheel loads and the steering? (scenes/studies/design.yaml: the base
scene, the factors with their ranges and reasons, the maps, the sample sizes.)

Runs, all on the sweep runner (a local Dask cluster, or --scheduler ADDRESS), kept in
DIR/sweep/ (a rerun reuses every finished run):
  - 2-D maps (hands off after the manoeuvre: the lasting load split and the pull);
  - Sobol's sample over the factors (SALib; hands on: the split and the rack-force change);
  - a Monte Carlo of jam states (random road unevenness before the manoeuvre, hands off);
  - each mitigation over the same states; a sample repeated at half the step (the noise).
Writes DIR/study/: table.csv (one row per run), maps, sobol.png, monte_carlo.png,
summary.json and report.md.

  python experiments/design_study.py --out results/design          (about 30 min here)
  python experiments/design_study.py --out /tmp/design --quick     (a smoke run, ~2 min)
"""

import time

from drake_car import cli
from drake_car.data import resource
from drake_car.scene.load import parse_scene_option, scene_hash
from drake_car.sim.outputs import (
    check_output_target, output_folder, provenance, write_csv, write_json)
from drake_car.study import design_figures as figures
from drake_car.study import design_report
from drake_car.study import design_runs as runs_of
from drake_car.study.design import OUTCOMES, factor, load_study, outcomes, paper_value
from drake_car.study.sweep import run_sweep
from drake_car.study.sweep_folder import load_run, read_status


def main(argv=None):
    p = cli.parser(__doc__)
    p.add_argument("--study", default=f"{resource('scenes/studies/design.yaml')}:study",
                   help="the study's spec, FILE:ENTRY (default: %(default)s)")
    p.add_argument("--quick", action="store_true", help="a smoke run of every part")
    p.add_argument("--scheduler", default=None, help="a Dask scheduler's address")
    p.add_argument("--workers", type=int, default=None, help="local workers (default: cores)")
    args = p.parse_args(argv)
    path, child = parse_scene_option(args.study)
    study = load_study(path, child)
    if args.quick:
        study = runs_of.quick(study)
    check_output_target(args.out / "study")
    began = time.perf_counter()
    parts = {"map": runs_of.map_scenes(study), "sobol": runs_of.sobol_scenes(study),
             "mc": runs_of.monte_carlo_scenes(study), "mitigation": runs_of.mitigation_scenes(study)}
    maps_hands_off = {name: (runs_of.hands_off(study, scene), values)
                      for name, (scene, values) in parts["map"].items()}
    parts["map"] = maps_hands_off
    sample = dict(list(parts["map"].items())[:study.noise_samples // 2]
                  + list(parts["sobol"].items())[:study.noise_samples - study.noise_samples // 2])
    parts["noise"] = runs_of.noise_scenes(study, sample)
    named = {name: entry for part in parts.values() for name, entry in part.items()}
    sweep = run_sweep({name: scene for name, (scene, _) in named.items()}, args.out / "sweep",
                      scheduler=args.scheduler, workers=args.workers)
    table = []
    for role, part in parts.items():
        for name, (scene, values) in part.items():
            key = scene_hash(scene)
            row = {"name": name, "role": role, "hash": key,
                   "status": read_status(args.out / "sweep" / "runs" / key)["status"]}
            row |= {f.key: _value_of(scene, f) for f in study.factors}
            row |= {"sample": values.get("sample", ""), "mitigation": values.get("mitigation", ""),
                    "of": values.get("of", "")}
            result = (outcomes(load_run(args.out / "sweep", key)[1].history, scene, study)
                      if row["status"] == "ok" else {k: float("nan") for k in OUTCOMES})
            table.append(row | result)
    with output_folder(args.out / "study") as out:
        summary = analyse(study, table, out, sweep, time.perf_counter() - began)
        write_csv(out / "table.csv", {k: [row[k] for row in table] for k in table[0]})
        write_json(out / "summary.json", summary)
        (out / "report.md").write_text(design_report.report(summary))
    print(f"{len(table)} runs ({sweep['reused']} reused, {sweep['failed']} failed); wrote "
          f"{args.out / 'study' / 'report.md'}")


def _value_of(scene, f):
    value = scene
    for part in f.key.split("."):
        value = getattr(value, part)
    return float(value)


def analyse(study, table, out, sweep, wall):
    noise = design_report.noise_levels(table)
    threshold = 100 * study.split_threshold
    maps = []
    for i, spec in enumerate(study.maps):
        rows = [r for r in table if r["name"].startswith(f"map{i}_")]
        fx, fy = factor(study, spec.x), factor(study, spec.y)
        for outcome, scale, limit, unit in (("split_change_rel", 100.0, threshold,
                                             "lasting front load split change [% of corner load]"),
                                            ("pull_deg", 1.0, study.pull_threshold_deg,
                                             f"heading change over {study.pull_distance_m:g} m "
                                             "hands off [deg]")):
            xs, ys, values = design_report.map_grid(study, spec, rows, outcome, scale)
            name = f"map{i}_{outcome}.png"
            figures.heat_map(xs, ys, values, x_label=fx.label, y_label=fy.label,
                             paper=(paper_value(study, fx), paper_value(study, fy)),
                             threshold=limit, title=f"{fy.label} × {fx.label}",
                             path=out / name, value_label=unit,
                             noise=noise.get(outcome, 0.0) * scale)
            maps.append({"figure": name, "caption": f"{unit} over {fx.label} × {fy.label}; "
                         "the star is the paper's car, the line the threshold; x marks cells "
                         "within the numerical noise of it"})
    sobol_rows = [r for r in table if r["role"] == "sobol"]
    sobol = design_report.sobol_tables(study, sobol_rows)
    if sobol is not None:
        figures.sobol_bars(sobol, out / "sobol.png")
    baseline = [r for r in table if r["role"] == "mc"]
    mitigation_rows = [r for r in table if r["role"] == "mitigation"]
    mitigations = design_report.mitigation_table(study, baseline, mitigation_rows)
    cases = {"baseline": [100 * r["split_change_rel"] for r in baseline]}
    for m in study.mitigations:
        cases[m.name] = [100 * r["split_change_rel"] for r in mitigation_rows
                         if r["mitigation"] == m.name]
    figures.distributions(cases, x_label="|lasting front load split change| [% of corner "
                          "load]", threshold=threshold, path=out / "monte_carlo.png",
                          title="Jam states (Monte Carlo) and mitigations")
    failed = sum(r["status"] != "ok" for r in table)
    return {"split_threshold": study.split_threshold,
            "pull_threshold_deg": study.pull_threshold_deg,
            "pull_distance_m": study.pull_distance_m,
            "factors": design_report.factor_rows(study), "maps": maps, "sobol": sobol,
            "monte_carlo": vars(study.monte_carlo), "mitigation_samples": study.mitigation_samples,
            "mitigations": mitigations,
            "noise": {"pairs": sum(r["role"] == "noise" for r in table), "levels": noise},
            "answers": design_report.answers(study, table, sobol, mitigations, noise),
            "method": design_report.method(study),
            "runs": {"total": len(table), "reused": sweep["reused"], "failed": failed},
            "wall_s": wall, "provenance": provenance()}


if __name__ == "__main__":
    cli.run_main(main)

