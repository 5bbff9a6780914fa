"""Ride comfort and road holding on ISO 8608 roads against the struts' dry friction: the car
drives straight at constant speed over a two-track random road; per run the ISO 2631-1
Wk-weighted RMS vertical acceleration at the driver's seat point, the pitch and roll
accelerations, the dynamic wheel-load coefficients front and rear and the rods' sticking, each
with its numerical error (the run against itself at half the step). Runs go through the sweep
runner into DIR/runs (resumable: the same command again reuses every finished run); the
analysis uses every finished run of the chosen cells. Writes into DIR:

  outcomes.csv            a row per run and outcome, with its numerical error
  ride_vs_mu_<strut>.png  comfort and wheel-load fluctuation against μs per class and speed
  psd_<class>_<speed>_<strut>.png   the seat point's acceleration spectrum, with and without
                          friction
  report.md               what a given μs costs in comfort and road holding
  runs/, index.csv, sweep.json   the sweep's runs (drake-car-sweep's layout)

  drake-car-ride --out DIR [--classes B,C] [--speeds 60] [--strut damper]
  drake-car-ride --out DIR --scene my_car.yaml:car     (your car: the values its scene states
                                                        laid over scenes/ride.yaml's ride)
"""

import dataclasses
import time

from drake_car.commands import cli
from drake_car.law.checks import ParameterError
from drake_car.results.files import files_into, read_csv
from drake_car.scene.load import parse_scene_option
from drake_car.study.ride.analysis import collect
from drake_car.study.ride.grid import STRUTS, RideStudy, analysed_from_s, ride_scenes
from drake_car.study.ride.report import write_outputs
from drake_car.sweep.holdings import none_of_these
from drake_car.sweep.runner import run_sweep
from drake_car.results.folder import OutputError, study_lock
from drake_car.sweep.store import (
    check_sweep_folder, damage, key_parts, read_status, run_key)


OPTIONS = {"classes": "--classes", "speeds_kph": "--speeds"}  # RideStudy's fields


@dataclasses.dataclass
class FinishedRun:
    scene: object
    history: dict
    wall_s: float


def _list(text, kind, name, what="values"):
    try:
        values = [kind(v) for v in text.split(",") if v]
    except ValueError:
        raise ParameterError(name, text, f"must be a comma-separated list of {what}") from None
    if not values:
        raise ParameterError(name, text, "must name at least one value")
    return values


def main(argv=None):
    p = cli.parser(__doc__, name="ride", cluster=True, out_help=(
        "the study's sweep folder: its runs are added to it as they finish and "
        "reused by the same command again (never replaced)"), scene=True, scene_help=(
        "your car: a scene FILE[:ENTRY] whose stated values (car, tyres, ...) are laid over "
        "the ride's base scene (scenes/ride.yaml: ride)"), scene_text=(
        "YAML laid over the ride's base scene, so over every run (e.g. another car: "
        "\"car_file: cars/bmw_320i.yaml\")"))
    p.add_argument("--classes", default="A,B,C", help="ISO 8608 road classes (default: A,B,C)")
    p.add_argument("--speeds", default="60,100", help="speeds in km/h (default: 60,100)")
    p.add_argument("--strut", default="damper",
                   help="damper (the car's damper plus dry friction), paper (dry friction "
                        "alone, as the paper's strut) or both (default: damper)")
    p.add_argument("--no_run", action="store_true", help="analyse the finished runs only")
    args = p.parse_args(argv)
    classes = _list(args.classes, str, "--classes")
    speeds = _list(args.speeds, float, "--speeds", "numbers in km/h (e.g. 40,60,80)")
    struts = list(STRUTS) if args.strut == "both" else [args.strut]
    if any(s not in STRUTS for s in struts):
        raise ParameterError("--strut", args.strut, f"must be one of {', '.join(STRUTS)}, both")
    studies = [RideStudy(classes=classes, speeds_kph=speeds, strut=s) for s in struts]
    try:  # the options, before any work (the road's length is derived from the speeds)
        studies[0].check()
    except ParameterError as e:
        raise ParameterError(OPTIONS.get(e.key, e.key), e.value, e.requirement) from None
    check_sweep_folder(args.out)  # before the scenes (the launch and rack are calibrated)
    with study_lock(args.out, "ride study"):  # one study writes to a folder at a time
        _study(args, studies)


def _study(args, studies):
    """The ride runs, their analysis and outputs, into ``args.out`` (its lock held)."""
    scenes = {}
    scene = parse_scene_option(args.scene) if args.scene else None
    for study in studies:
        scenes.update(ride_scenes(study, scene_text=args.scene_text or None, scene=scene))
    began = time.perf_counter()
    if not args.no_run:
        with cli.cluster_client(args, len(scenes)) as client:
            result = run_sweep(scenes, args.out, client=client, progress=not args.quiet)
        print(f"sweep: {result['ok']} ok, {result['failed']} failed, {result['reused']} "
              f"reused, {result['wall_s']:.0f} s")
    runs = finished_runs(args.out, scenes)
    rows = collect(runs, lambda scene: analysed_from_s(scene, studies[0]))
    if not rows:
        raise ParameterError("--out", str(args.out), none_of_these(
            args.out, scenes, runs, "this car's ride runs" if args.scene else
            "this scene's ride runs" if args.scene_text else "the shipped car's ride runs"))
    with files_into(args.out) as out:  # each file whole
        write_outputs(out, rows, runs, studies[0], time.perf_counter() - began)
    print(f"wrote {args.out / 'report.md'} ({len(rows)} runs with their twins)")


def finished_runs(out, scenes):
    """name -> (scene, history, wall_s) of the scenes with an ok run in ``out`` (its folder
    named by the run's key: the scene, the files it reads, the code): the history read from
    its CSV (bit for bit the run's, its checksum checked), the scene the grid's own."""
    runs = {}
    for name, scene in scenes.items():
        folder = out / "runs" / run_key(key_parts(scene))
        record = read_status(folder)
        if record is not None and record.get("status") == "ok":
            why = damage(folder, record)
            if why:
                raise OutputError(f"{folder}: {why}; run the command again without --no_run "
                                  "(damaged runs are rerun)")
            runs[name] = FinishedRun(scene, read_csv(folder / "history.csv"), record["wall_s"])
    return runs


def console():
    """The console script ``drake-car-ride``."""
    cli.run_main(main)


if __name__ == "__main__":
    console()
