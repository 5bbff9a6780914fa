"""The paper's study (Harlecki & Kubas, section 4): two lane changes at 60 km/h (a: left turn
first, b: right turn first) × three strut friction sets, from the six scenes of
scenes/paper_study.yaml. Writes into DIR:

  <run>/history.csv, scene.yaml, run.json   each run as it ran (the scene with every value)
  <run>.csv               the study's columns of each run (Δd from static equilibrium, μ1, ...)
  fig13.png ... fig16.png the paper's figures (places a and b shaded, both struts in Fig. 16)
  claim1_return.png, load_split.png, symmetry.png, rod_rotation.png   a figure per claim
  summary.json, report.md the paper's claims: reproduced or not, the deciding numbers beside
                          their thresholds with their numerical error, the figures
  diagram_overview.svg    the Diagram of the replayed run at a glance; diagram.svg every port
  <run>/replay.html       the Meshcat replay of the highest-friction run of case a

Every run is repeated at half its time step (skip it with --no_verify): the report gives each
deciding number at both steps, |x(dt) - x(dt/2)| as its numerical error, and both verdicts.
All runs go as one sweep (``sweep.runner.run_scenes``: in parallel, a progress bar over the
runs on a terminal). Options and scenes: --scene_text is laid over every run's scene (e.g.
"plant: {time_step: 5e-4}" or "car: {front: {ball_joint_offset_b_m: 0.06}}"); the replay is
added to one run's scene (so its saved scene says so).

Example:  python experiments/lane_change.py --out results
"""

import dataclasses
import time

from drake_car import cli
from drake_car.data import resource
from drake_car.scene.load import load_scene_file
from drake_car.scene.scene import MeshcatReplay, NoVisualization, PrescribedRotation
from drake_car.results.diagram import write_diagram_overview_svg, write_diagram_svg
from drake_car.results.files import write_csv, write_json, write_run
from drake_car.results.folder import output_folder
from drake_car.results.provenance import provenance
from drake_car.study.paper.figures import all_figures
from drake_car.study.paper.measures import claim_measures
from drake_car.study.paper.claims import (
    check_study_scenes, evaluate_claims, friction_of, study_runs,
    study_timeline)
from drake_car.study.paper.report import report, summary
from drake_car.sweep.runner import run_scenes

PAPER_STUDY = resource("scenes/paper_study.yaml")
HALF = " at dt/2"  # the half-step repetition of a run, among the sweep's names
PAPER_DRIVE = " paper's drive"  # the run with the paper's drive, among the sweep's names


def main(argv=None):
    p = cli.parser(__doc__)
    p.add_argument("--scene", default=str(PAPER_STUDY),
                   help="the study's scenes file (default: %(default)s)")
    p.add_argument("--scene_text", default="", help="YAML laid over every run's scene")
    p.add_argument("--no_verify", action="store_true",
                   help="skip the half-step repetition of every run (the numbers' "
                        "numerical error estimates)")
    p.add_argument("--no_html", action="store_true", help="no Meshcat replay")
    p.add_argument("--no_paper_drive", action="store_true",
                   help="skip the comparison with the paper's own drive (both front wheels' "
                        "rotation prescribed: a locked front axle)")
    p.add_argument("--scheduler", default=None,
                   help="a Dask scheduler's address (default: a local cluster)")
    p.add_argument("--workers", type=cli.count, default=None,
                   help="local workers (default: one per core)")
    args = p.parse_args(argv)
    cli.check_out(args)
    scenes = load_scene_file(args.scene, args.scene_text or None)
    check_study_scenes(scenes)  # before any work
    replayed = None
    if not args.no_html:
        case_a = [n for n, s in scenes.items() if getattr(s.manoeuvre, "case", None) == "a"]
        replayed = max(case_a, key=lambda n: friction_of(scenes[n])[0]) if case_a else None
        if replayed is not None:
            scenes[replayed] = dataclasses.replace(scenes[replayed],
                                                   visualization=MeshcatReplay())
    began = time.perf_counter()
    with output_folder(args.out) as out:
        halved = {} if args.no_verify else {
            name: dataclasses.replace(s, plant=_halved(s.plant), visualization=NoVisualization())
            for name, s in scenes.items()}
        locked = {} if args.no_paper_drive else {
            name + PAPER_DRIVE: dataclasses.replace(s, drive=PrescribedRotation(),
                                                    visualization=NoVisualization())
            for name, s in scenes.items()}
        # One sweep (one progress bar) over the runs, their half-step repetitions and the
        # comparison with the paper's drive.
        done = run_scenes(scenes | {n + HALF: s for n, s in halved.items()} | locked,
                          scheduler=args.scheduler, workers=args.workers)
        runs = {name: done[name] for name in scenes}
        study = study_runs(runs)
        timeline = study_timeline(runs)
        claims, shifts = evaluate_claims(study, timeline)
        half, half_study = None, None
        if halved:
            half_study = study_runs({name: done[name + HALF] for name in halved})
            half_claims, _ = evaluate_claims(half_study, timeline)
            half = {"time_step_s": {n: s.plant.time_step for n, s in halved.items()},
                    "verdicts": [c["reproduced"] for c in half_claims],
                    "numbers": [c["number"] for c in half_claims],
                    "measures": claim_measures(half_study, timeline)}
        paper_drive = None
        if locked:
            locked_study = study_runs({name: done[name + PAPER_DRIVE] for name in scenes})
            locked_claims, _ = evaluate_claims(locked_study, timeline)
            paper_drive = {"verdicts": [c["reproduced"] for c in locked_claims],
                           "numbers": [c["number"] for c in locked_claims]}
        for name, run in runs.items():
            (out / name).mkdir()
            write_run(run, out / name, diagram=False)
            write_csv(out / f"{name}.csv", study[name].columns)
        figures = all_figures(study, timeline, out, half=half_study)
        shown = replayed or next(iter(runs))
        write_diagram_svg(runs[shown].diagram_dot, out / "diagram.svg")
        write_diagram_overview_svg(runs[shown].diagram_dot, out / "diagram_overview.svg")
        s = summary(study, claims, shifts, timeline, runs=runs, half=half, figures=figures,
                    wall_s=time.perf_counter() - began, provenance=provenance(),
                    replay=replayed)
        s["paper_drive"] = paper_drive
        write_json(out / "summary.json", s)
        (out / "report.md").write_text(report(s))
    failed = [c["claim"] for c in claims if not c["reproduced"]]
    print(f"{len(claims) - len(failed)} of {len(claims)} claims reproduced; wrote {args.out} "
          f"(report: {args.out / 'report.md'})")


def _halved(plant):
    from pydrake.multibody.plant import MultibodyPlantConfig
    config = MultibodyPlantConfig(**{f.name: getattr(plant, f.name)
                                     for f in MultibodyPlantConfig.__fields__})
    config.time_step = plant.time_step / 2
    return config


if __name__ == "__main__":
    cli.run_main(main)
