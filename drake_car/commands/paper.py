"""The paper's study (Harlecki & Kubas, section 4): two lane changes at 60 km/h (a: left turn
first, b: right turn first) × the strut friction sets, from the scenes of --scene (default: the
paper's six, scenes/paper_study.yaml: three sets). Any number of sets runs, each in both cases:
the claims about high friction judge the highest dry set and compare it with the others, and
say which (study.paper.sets). Writes into DIR:

  <run>/history.csv, scene.yaml, run.json   each run as it ran (the scene with every value)
  <run>.csv               the study's columns of each run (Δd from static equilibrium, μ1, ...)
  fig13.png ... fig16.png the paper's figures (places a and b shaded, both struts in Fig. 16)
  claim1_return.png, load_split.png, symmetry.png, rod_rotation.png   a figure per claim
  summary.json, report.md the paper's claims: reproduced or not, the deciding numbers beside
                          their thresholds with their numerical error, the figures
  diagram_overview.svg    the Diagram of the replayed run at a glance; diagram.svg every port
  <run>/replay.html       the Meshcat replay of the highest-friction run of case a

  The manoeuvre adapts to the car: a launch left out is the paper's 3 s or as long as the car's
  drive allows, the lane change's rack is calibrated for the car (once, cached by its inputs'
  content; the shipped Escort's calibration where they match); the report says how (section
  "The manoeuvre as it ran") and flags, as stderr does, a run that is off its speed at place a,
  its 3.7 m or its parallel end (study.paper.manoeuvre).

  outcomes.csv            one row per run (or mirror pair) and outcome: run, outcome, value,
                          error, unit, step_s, converged, tolerance, observed_order,
                          steps_tried_s, values_by_step, run_wall_s, solver_error, limited_by;
                          the report, summary.json and load_split.png read it

Accuracy on demand (skip it with --no_verify), --refine local (the default): every run with
dry friction resolves each slip of its struts in a window re-run at halved steps until where
the rods rest converges, with the error each window inherits from the last one and from the gap
before it (``sim.resolve``, ``study.paper.local_route``); the runs without dry friction are
repeated at dt/2 and dt/4 (the global route). --refine global: every run is repeated at dt/2
and dt/4, and the runs whose deciding outcomes have not converged within their tolerances
(``study.paper.outcomes.TOLERANCES``, each with its reason) are halved again until they
converge, or --finest_step_s or --budget_s is reached (``sweep.refine``), its errors a run's
own differences between steps plus the solver's (a last round at SAP's tolerance loosened
twice, ``systems.sap_ballast``; --no_solver_axis leaves it out). A claim is decided where its
margin exceeds its whole error (a value that did not converge: the spread of its last three
steps or levels), else the report says "undecided". Each round of runs goes as one sweep
(``sweep.runner.run_scenes``: in parallel on one cluster for the whole job, a progress bar over
the runs on a terminal): the first round is the runs, their dt/2 and dt/4 repetitions and the
same runs with the paper's drive. Options and scenes: --scene_text is laid over every run's
scene (e.g.
"plant: {time_step: 5e-4}" or "car: {front: {ball_joint_offset_b_m: 0.06}}"); the replay is
added to one run's scene (so its saved scene says so).

Example:  drake-car-paper --out results/paper
"""

import dataclasses
import time
from pathlib import Path
from resource import RUSAGE_CHILDREN, RUSAGE_SELF, getrusage

from drake_car.commands import cli
from drake_car.data import resource
from drake_car.scene.study_file import load_study_file
from drake_car.scene.scene import MeshcatReplay, NoVisualization, PrescribedRotation
from drake_car.results.files import (
    write_csv, write_diagram_overview_svg, write_diagram_svg, write_json, write_run)
from drake_car.results.folder import output_folder
from drake_car.results.provenance import provenance
from drake_car.sim.simulate import simulate as simulate_here
from drake_car.study.paper.figures import all_figures
from drake_car.study.paper.manoeuvre import manoeuvre_summary, prepare
from drake_car.study.paper.claims import (
    check_study_scenes, evaluate_claims, friction_of, study_columns, study_runs)
from drake_car.study.paper.outcomes import (
    at_one_step, read_outcomes, study_outcomes, write_outcomes)
from drake_car.study.paper.local_route import accurate_runs
from drake_car.study.paper.report import report, summary, verdict_line
from drake_car.sweep.refine import check_twin, halved, loosened
from drake_car.sweep.runner import run_scenes

PAPER_STUDY = resource("scenes/paper_study.yaml")
PAPER = cli.command_name("paper")
PAPER_DRIVE = " paper's drive"  # the run with the paper's drive, among the sweep's names


def main(argv=None):
    p = cli.parser(__doc__, name="paper", scene=True, scene_default=str(PAPER_STUDY),
                   scene_help=(
                       "the study's scenes file, each entry a run (not your car: give that with "
                       "--scene_text \"car_file: FILE\")"), cluster=True,
                   scene_text="YAML laid over every run's scene")
    p.add_argument("--no_verify", action="store_true",
                   help="no accuracy on demand: every run at its scene's step only, no "
                        "numerical error estimated")
    p.add_argument("--refine", choices=("local", "global"), default="local",
                   help="accuracy on demand by resolving every slip of the dry runs' struts "
                        "in a window at halved steps, with what each window inherits and the "
                        "gap before it (local), or by halving every run's whole step (global, "
                        "the reference, several times the CPU) (default: %(default)s)")
    p.add_argument("--finest_step_s", type=cli.positive("--finest_step_s"), default=3.125e-5,
                   help="the finest step accuracy on demand may try (default: %(default)g)")
    p.add_argument("--budget_s", type=cli.positive("--budget_s"), default=1800.0,
                   help="no further halving once the refinement has taken this much wall "
                        "time (default: %(default)g)")
    p.add_argument("--runs_dir", type=Path, default=None,
                   help="keep every run (each step tried) in this sweep folder too, by its "
                        "key (scene, files read, code): a rerun reuses them (default: in "
                        "memory only)")
    p.add_argument("--no_html", action="store_true", help="no Meshcat replay")
    p.add_argument("--no_solver_axis", action="store_true",
                   help="no solver twins: the error budget without SAP's tolerance (saves a "
                        "run of each run at its finest step, or of each window's finest "
                        "level on the local route)")
    p.add_argument("--no_paper_drive", action="store_true",
                   help="skip the comparison with the paper's own drive (both driven "
                        "wheels' rotation prescribed: a locked driven axle, the front on the "
                        "paper's Escort, the rear on a rear-drive car's car.driven_axle)")
    args = p.parse_args(argv)
    cli.check_out(args, kept=("runs_dir",))
    scenes = load_study_file(args.scene, args.scene_text or None, command=PAPER, holds=(
        "the study's scenes file: each entry a run, a !LaneChange of case a or b with its "
        "friction set (as scenes/paper_study.yaml)"))
    roles = check_study_scenes(scenes)  # before any work
    if not (args.no_verify or args.no_solver_axis):
        for scene in scenes.values():
            check_twin(scene)
    scenes, calibration = prepare(scenes, run=simulate_here)
    replayed = None
    if not args.no_html:
        case_a = [n for n, s in scenes.items() if getattr(s.manoeuvre, "case", None) == "a"]
        replayed = max(case_a, key=lambda n: friction_of(scenes[n])[0]) if case_a else None
        if replayed is not None:
            scenes[replayed] = dataclasses.replace(scenes[replayed],
                                                   visualization=MeshcatReplay())
    began = time.perf_counter()
    timeline = next(iter(scenes.values())).manoeuvre.timeline
    with output_folder(args.out) as out:
        locked = {} if args.no_paper_drive else {
            name + PAPER_DRIVE: dataclasses.replace(s, drive=PrescribedRotation(),
                                                    visualization=NoVisualization())
            for name, s in scenes.items()}
        count = len(scenes) * (1 if args.no_verify else 3) + len(locked)
        with cli.cluster_client(args, count) as client:
            def simulate(batch):
                return run_scenes(batch, client=client, out_dir=args.runs_dir,
                                  progress=not args.quiet)
            if args.no_verify:
                done = simulate(scenes | locked)
                runs = {name: done[name] for name in scenes}
                locked_runs = {name: done[name + PAPER_DRIVE] for name in scenes if locked}
                table = at_one_step(study_outcomes(
                    {n: study_columns(r.history) for n, r in runs.items()}, roles, timeline))
                for (name, _), row in table.items():
                    row["steps_s"] = [scenes[name.split("|")[0]].plant.time_step]
                    row["step_s"] = row["steps_s"][0]
                run_wall, refinement = {n: r.wall_s for n, r in runs.items()}, None
                run_cpu = {n: r.cpu_s for n, r in runs.items()}
            else:
                done = accurate_runs(scenes, roles, timeline, simulate, route=args.refine,
                                     extra=locked, halve=_unseen_halved,
                                     finest_step_s=args.finest_step_s, budget_s=args.budget_s,
                                     solver_twin=None if args.no_solver_axis
                                     else _unseen_loosened)
                runs, table, refinement = done.runs, done.outcomes, done.refinement
                locked_runs = {name: done.extra[name + PAPER_DRIVE] for name in scenes
                               if locked}
                run_wall, run_cpu = done.run_wall_s, done.run_cpu_s
        write_outcomes(out / "outcomes.csv", table, run_wall, run_cpu)
        outcomes = read_outcomes(out / "outcomes.csv")  # what the report and figures read
        study = study_runs(runs)
        claims, shifts = evaluate_claims(study, timeline)
        paper_drive = None
        if locked:
            locked_study = study_runs(locked_runs)
            locked_claims, _ = evaluate_claims(locked_study, timeline)
            paper_drive = {"verdicts": [c["reproduced"] for c in locked_claims],
                           "numbers": [c["number"] for c in locked_claims]}
        for name, run in runs.items():
            (out / name).mkdir()
            write_run(run, out / name, diagram=False)
            write_csv(out / f"{name}.csv", study[name].columns)
        figures = all_figures(study, timeline, out, outcomes=outcomes)
        shown = replayed or next(iter(runs))
        write_diagram_svg(runs[shown].diagram_dot, out / "diagram.svg")
        write_diagram_overview_svg(runs[shown].diagram_dot, out / "diagram_overview.svg")
        s = summary(study, claims, shifts, timeline, runs=runs, outcomes=outcomes,
                    refinement=refinement, figures=figures,
                    wall_s=time.perf_counter() - began, provenance=provenance(),
                    replay=replayed)
        s["cpu_s"] = _cpu_s()
        if refinement is not None:
            refinement["job_cpu_s"] = s["cpu_s"]
        s["paper_drive"] = paper_drive
        s["manoeuvre"] = manoeuvre_summary(runs, calibration)
        write_json(out / "summary.json", s)
        (out / "report.md").write_text(report(s))
        claims = s["claims"]
    steps_s = sorted({scene.plant.time_step for scene in scenes.values()})
    print(verdict_line(claims, verified=not args.no_verify, steps_s=steps_s)
          + f"; wrote {args.out} (report: {args.out / 'report.md'})")


def _unseen_halved(scene, halvings):
    """A refinement's run: the scene at a finer step, without a replay."""
    return halved(dataclasses.replace(scene, visualization=NoVisualization()), halvings)


def _unseen_loosened(scene):
    """A solver twin: the scene with SAP's tolerance loosened twice, without a replay."""
    return loosened(dataclasses.replace(scene, visualization=NoVisualization()))


def _cpu_s():
    """CPU time of this process and its finished children (the local cluster's workers,
    reaped when it closes), user + system (s)."""
    return sum(getattr(getrusage(who), f) for who in (RUSAGE_SELF, RUSAGE_CHILDREN)
               for f in ("ru_utime", "ru_stime"))


def console():
    """The console script ``drake-car-paper``."""
    cli.run_main(main)


if __name__ == "__main__":
    console()
