"""The design study: where, over the strut's design and the severity of use, does strut
friction change the front wheel loads and the steering? (scenes/studies/design.yaml: the base
scene, the factors with their ranges and reasons, the maps, the lines, the sample sizes.)

Runs, all on the sweep runner (a local Dask cluster, or --scheduler ADDRESS), kept in
DIR/sweep/ (a rerun reuses every finished run):
  - 2-D maps (hands off after the manoeuvre: the lasting load split and the pull);
  - lines: one factor at a time (spring inclination, top mount, speed-up) at two μs, hands off;
  - Sobol's sample over the factors (SALib; hands on: the split and the rack-force change);
  - a Monte Carlo of jam states (random road unevenness before the manoeuvre, hands off);
  - each mitigation over the same states; a sample of all of these at half the step (noise);
  - accuracy on demand where the struts jam (the spec's ``accuracy``: by default the maps',
    lines', Sobol's and mitigations' runs at μs >= 0.3, and --compare's): each resolves its
    struts' slips locally, windows at halved steps, in the same sweep (--refine local), or is
    repeated at 1/2 and 1/4 of its step and halved further until its lasting split and pull
    converge (--refine global, the default: on --quick it costs less than the local route, and
    its errors are converged, where the local route's summed window errors are 0.07-2 % of the
    corner load against a 0.1 % tolerance; docs/studies.md); --no_verify: neither.
Writes DIR/report.md (what it means for a designer, with numbers) and DIR/study/: table.csv
(one row per run), the maps, lines.png, sobol.png, monte_carlo.png and summary.json.

Around your car: --scene FILE[:ENTRY] lays the values that scene states (your car, tyres,
timeline, ...) over the study's base scene, --scene_text YAML over that; the maps' star is then
at your car's values. --compare YAML is your design change (laid over the base scene): it runs
against the car as it is on the flat road at each line μs (refined for its own error) and over
the jam states, and the report answers what it does to the lasting split (N and %), the pull
and the steering-wheel torque. --quick is a smoke test of every part, on a shortened study: it
says so on every page (report, figure titles, summary.json, stderr) and its numbers are not
findings.

  drake-car-design --out results/design          (its runs: 39 min on this 2-core
      machine beside other work; refining the jam cases (the default, --refine global)
      adds about 3 times that, --refine local about 2.3 times [EST from a sample,
      docs/studies.md])
  drake-car-design --out /tmp/design --quick     (a smoke run, ~2 min)
  drake-car-design --out results/design_sedan \
      --scene_text "{tyres: !MagicFormula {tir_file: tests/data/tyres/Sedan_Pac02Tire.tir}}"
  drake-car-design --out results/my_car --scene my_car.yaml:car \
      --compare "car: {front: {spring_offset_m: 0.03}}"
"""

import os
import sys
import time

from drake_car.commands import cli
from drake_car.data import resource
from drake_car.law.checks import check_input_option
from drake_car.scene.load import parse_scene_option
from drake_car.results.files import write_csv, write_json
from drake_car.results.folder import (OutputError, check_output_target, output_folder,
                                      study_lock)
from drake_car.study.design import jam_cases
from drake_car.study.design import resolved_runs as design_local
from drake_car.study.design import analysis as design_analysis
from drake_car.study.design import base_car
from drake_car.study.design import compare as design_compare
from drake_car.study.design import report as design_report
from drake_car.study.design import runs as runs_of
from drake_car.study.design import smoke
from drake_car.study.design import tables as design_tables
from drake_car.study.design.spec import load_study
from drake_car.sweep.runner import run_scenes, run_sweep


def main(argv=None):
    p = cli.parser(__doc__, name="design", cluster=True, out_help=(
        "the study's folder: its sweep's runs are added as they finish and "
        "reused by the same command again; the study's results are rewritten"),
        scene=True, scene_help="your car: a scene FILE[:ENTRY] whose stated values are laid "
        "over the study's base scene (default: the study's own base)",
        scene_text="YAML laid over the study's base scene, so over every run (e.g. another "
                   "tyre: \"{tyres: !MagicFormula {tir_file: FILE}}\")")
    p.add_argument("--study", default=f"{resource('scenes/studies/design.yaml')}:study",
                   help="the study's spec, FILE:ENTRY (default: %(default)s)")
    p.add_argument("--quick", action="store_true",
                   help="a smoke test of every part on a shortened study (its timeline, "
                        "samples and pull distance cut; said on every page): its numbers are "
                        "not findings")
    p.add_argument("--compare", default=None, metavar="YAML",
                   help="your design change, laid over the base scene (e.g. \"car: {front: "
                        "{spring_offset_m: 0.03}}\"): what it does, with its error")
    p.add_argument("--rerun_failed", action="store_true",
                   help="run the failed runs again (a rerun reuses them otherwise)")
    p.add_argument("--refine", choices=("local", "global"), default="global",
                   help="accuracy on demand for the jam cases (the spec's accuracy section): "
                        "they resolve their struts' slips locally (local: "
                        "the split's error covers the windows, docs/studies.md), or are halved "
                        "whole (global: the reference, several times the CPU) "
                        "(default: %(default)s)")
    p.add_argument("--no_verify", action="store_true",
                   help="no accuracy on demand: the jam cases at the study's step only, every "
                   "error the half-step noise sample's (the spec's accuracy section says which "
                   "runs are refined and to what)")
    args = p.parse_args(argv)
    check_study_folder(args.out)
    with study_lock(args.out, "design study"):  # one study writes to a folder at a time
        _study(args)


def _study(args):
    """The study, its runs, analysis and outputs, into ``args.out`` (its lock held)."""
    path, child = parse_scene_option(args.study)
    check_input_option("--study", path, "study file", is_text="YAML text")
    study = load_study(path, child, args.scene_text or None,
                       scene=parse_scene_option(args.scene) if args.scene else None)
    study, adapted = base_car.adapted_base(study, stated=_stated(args))
    if adapted:
        print("The manoeuvre on your car: " + "; ".join(adapted) + ".", file=sys.stderr,
              flush=True)
    if args.compare is not None:
        study = design_compare.with_compare(study, args.compare)
    changes = None
    if args.quick:
        study, changes = smoke.quick(study)
        print(f"{smoke.NOTE}\nWhat --quick changes: " + "; ".join(changes) + ".",
              file=sys.stderr, flush=True)
    began = time.perf_counter()
    parts = {"map": {name: (runs_of.hands_off(study, scene), values)
                     for name, (scene, values) in runs_of.map_scenes(study).items()},
             "line": runs_of.line_scenes(study), "sobol": runs_of.sobol_scenes(study),
             "mc": runs_of.monte_carlo_scenes(study), "mitigation": runs_of.mitigation_scenes(study)}
    if args.compare is not None:
        parts[design_compare.PART] = design_compare.compare_scenes(study, args.compare)
    jam = {} if args.no_verify else jam_cases.jam_scenes(study, parts)
    local = args.refine == "local" and bool(jam)
    if local:  # the jam cases resolve their events in the study's own sweep
        parts = design_local.resolving_parts(study, parts, set(jam))
        print(design_local.announcement(study, len(jam), design_compare.PART in parts),
              flush=True)
    named = {name: entry for part in parts.values() for name, entry in part.items()}
    # The half-step noise sample speaks for the runs at the study's step: drawn from them.
    sampled = {k: {n: e for n, e in v.items() if n not in jam} for k, v in parts.items()
               if k != design_compare.PART}
    parts["noise"] = runs_of.noise_scenes(study, named, runs_of.noise_sample(study, sampled))
    named |= parts["noise"]
    sweep_dir = args.out / "sweep"
    with cli.cluster_client(args, len(named)) as client:
        sweep = run_sweep({name: scene for name, (scene, _) in named.items()}, sweep_dir,
                          client=client, rerun_failed=args.rerun_failed,
                          progress=not args.quiet)
        refined = None
        if jam and not local:
            print(f"accuracy on demand: {len(jam)} runs, at μs >= {study.accuracy.jam_mu_s:g} "
                  f"({', '.join(study.accuracy.parts)})"
                  + (" and --compare's at any μs" if design_compare.PART in parts else "")
                  + " at 1/2 and 1/4 of their step, then "
                  f"halved where not converged, down to {1e3 * study.accuracy.finest_step_s:g} "
                  "ms", flush=True)
            refined = jam_cases.refine_jam_cases(
                study, parts, lambda batch: run_scenes(batch, out_dir=sweep_dir, client=client,
                                                       skip_failed=True,
                                                       rerun_failed=args.rerun_failed,
                                                       progress=not args.quiet))
    rows = design_analysis.table(study, parts, sweep_dir)
    noise = design_tables.noise_levels(rows, exclude=set(jam))
    if local:
        design_local.apply(rows, study, noise, set(jam))
    else:
        jam_cases.apply(rows, refined, noise)
    report = args.out / "report.md"
    partial = args.out / f".report.md.partial-{os.getpid()}"
    kept = args.out / f".report.md.old-{os.getpid()}"
    swapped = False
    try:
        with output_folder(args.out / "study") as out:
            summary = _analysed(args, study, rows, out, sweep, began, noise, local, jam, refined,
                                changes, adapted)
            partial.write_text(design_report.report(summary, figures="study/"))
            # Never a report beside a study/ it did not come from: the old one is put aside
            # while study/ is swapped (back if the swap is refused; a kill after the swap
            # leaves none, and a rerun reuses every run).
            if report.exists():
                os.replace(report, kept)
        swapped = True
        os.replace(partial, report)
    except BaseException:
        if not swapped and kept.exists():
            os.replace(kept, report)  # the old study/ stays: so does its report
        raise
    finally:
        partial.unlink(missing_ok=True)
        kept.unlink(missing_ok=True)
    print(f"{len(rows)} runs ({sweep['reused']} reused, {sweep['failed']} failed); wrote "
          f"{report}")


def _analysed(args, study, rows, out, sweep, began, noise, local, jam, refined, changes,
              adapted):
    """The study's summary; its table and summary.json written into ``out``."""
    errors = (design_local.summary(rows, study, set(jam)) if local
              else jam_cases.summary(refined, rows, study))
    summary = design_analysis.analyse(study, rows, out, sweep, time.perf_counter() - began,
                                      noise, errors, smoke=changes, adapted=adapted)
    summary["scene_text"] = args.scene_text or None
    summary["scene"], summary["study_file"] = args.scene, args.study
    summary["compare"] = design_compare.compare_summary(study, rows, args.compare, noise)
    write_csv(out / "table.csv", {k: [row[k] for row in rows] for k in rows[0]})
    write_json(out / "summary.json", summary)
    return summary


def _stated(args):
    """The manoeuvre keys the user's scene states (its file's text and --scene_text): a launch
    or rack given there is run as given."""
    text = args.scene_text or ""
    if args.scene:
        text += parse_scene_option(args.scene)[0].read_text(errors="replace")
    return {key for key in ("speed_up_s", "amplitude_m", "second_lobe") if key in text}


def check_study_folder(out):
    """``out`` is new, empty, or a design study's folder (its runs are resumed): refused before
    any work otherwise."""
    if out.exists() and not out.is_dir():
        raise OutputError(f"--out {out}: is a file, not a folder")
    if out.is_dir() and any(out.iterdir()) and not (out / "sweep").is_dir():
        raise OutputError(f"--out {out}: exists, is not empty and holds no design study (no "
                          "sweep/ folder); choose a new or empty folder, or a study's to resume")
    check_output_target(out / "study")


def console():
    """The console script ``drake-car-design``."""
    cli.run_main(main)


if __name__ == "__main__":
    console()

