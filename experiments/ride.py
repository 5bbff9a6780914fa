"""Ride comfort and road holding on ISO 8608 roads against the struts' dry friction (issue 23):
the car drives straight at constant speed over a two-track random road; per run the ISO 2631-1
Wk-weighted RMS vertical acceleration at the driver's seat point, the pitch and roll
accelerations, the dynamic wheel-load coefficients front and rear and the rods' sticking, each
with its numerical error (the run against itself at half the step). Runs go through the sweep
runner into DIR/runs (resumable: a restart reuses every finished run); the analysis uses every
finished run of the chosen cells.

    python experiments/ride.py --out DIR [--classes B,C] [--speeds 60] [--strut damper]
                               [--workers 2] [--no-run]

Writes DIR/outcomes.csv, DIR/ride_vs_mu_<strut>.png, DIR/psd_<class>_<speed>.png,
DIR/report.md."""

import argparse
import dataclasses
import sys
import time
from pathlib import Path

from drake_car.law.checks import ParameterError
from drake_car.study.ride.analysis import collect
from drake_car.study.ride.grid import STRUTS, RideStudy, analysed_from_s, ride_scenes
from drake_car.study.ride.report import write_outputs
from drake_car.sweep.runner import run_sweep
from drake_car.results.files import read_csv
from drake_car.scene.load import scene_hash
from drake_car.sweep.store import read_status


@dataclasses.dataclass
class FinishedRun:
    scene: object
    history: dict
    wall_s: float


def _list(text, kind, name):
    try:
        return [kind(v) for v in text.split(",") if v]
    except ValueError:
        raise ParameterError(name, text, "must be a comma-separated list") from None


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", required=True, type=Path)
    parser.add_argument("--classes", default="A,B,C")
    parser.add_argument("--speeds", default="60,100")
    parser.add_argument("--strut", default="damper", help="damper, paper or both")
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--no-run", action="store_true",
                        help="analyse the finished runs only")
    args = parser.parse_args(argv)
    try:
        classes = _list(args.classes, str, "--classes")
        speeds = _list(args.speeds, float, "--speeds")
        struts = list(STRUTS) if args.strut == "both" else [args.strut]
        if any(s not in STRUTS for s in struts):
            raise ParameterError("--strut", args.strut, f"must be one of {', '.join(STRUTS)}, both")
        studies = [RideStudy(classes=classes, speeds_kph=speeds, strut=s) for s in struts]
        scenes = {}
        for study in studies:
            scenes.update(ride_scenes(study))
    except (ParameterError, ValueError) as e:
        print(f"ride: {e}", file=sys.stderr)
        return 2
    args.out.mkdir(parents=True, exist_ok=True)
    began = time.perf_counter()
    if not args.no_run:
        result = run_sweep(scenes, args.out, workers=args.workers)
        print(f"sweep: {result['ok']} ok, {result['failed']} failed, {result['reused']} reused, "
              f"{result['wall_s']:.0f} s")
    runs = finished_runs(args.out, scenes)
    study = studies[0]
    rows = collect(runs, lambda scene: analysed_from_s(scene, study))
    if not rows:
        print(f"ride: {args.out}: no finished run with its half-step twin", file=sys.stderr)
        return 1
    write_outputs(args.out, rows, runs, study, time.perf_counter() - began)
    print(f"wrote {args.out / 'report.md'} ({len(rows)} runs with their twins)")
    return 0


def finished_runs(out, scenes):
    """name -> (scene, history, wall_s) of the scenes with an ok run in ``out``: the history
    read from its CSV (bit for bit the run's), the scene the grid's own (the same content
    hash), which spares parsing each run's pickled scene."""
    runs = {}
    for name, scene in scenes.items():
        folder = out / "runs" / scene_hash(scene)
        record = read_status(folder)
        if record is not None and record["status"] == "ok":
            runs[name] = FinishedRun(scene, read_csv(folder / "history.csv"), record["wall_s"])
    return runs


if __name__ == "__main__":
    sys.exit(main())
