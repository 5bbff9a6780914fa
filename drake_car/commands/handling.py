"""Handling tests of the car, its understeer budget and a cross-check against an independent
model of the same car, from the two scenes of scenes/handling.yaml (steady_state: ISO 4138
continuous ramp steer at 60 km/h; step_steer: ISO 7401 step steer at 60 km/h). Writes into DIR:

  steady_state/   the run (history.csv, scene.yaml, run.json), steady_state.csv (the standard's
                  quantities at the CoG), steady_state.json (gradients, yaw gain, the
                  single-track model), steady_state.png
  step_steer/     the run, step_steer.csv, step_steer.json (response times, overshoot, gains),
                  step_steer.png
  budget.csv, budget.json, budget_series.csv, budget.png
                  the understeer gradient split into named terms (drake_car/study/handling/understeer.py)
  crosscheck/     CommonRoad's multi-body model of the car (its parameter set 1, Ford Escort;
                  2, BMW 320i; 3, VW Vanagon, known by mass and front track; none for another
                  car) on our runs' road-wheel steer at our speed, as far as it runs (where
                  the car spins in it, the report says so): ramp.csv, step.csv, crosscheck.json,
                  crosscheck_ramp.png, crosscheck_step.png
  steering.csv    the rack-to-road-wheel relation (chassis fixed) the understeer gradient uses
  tyre/           the tyre the car runs on, as drake-car-tyre writes it (curves.csv,
                  summary.txt, its figures); the report's tyre section
  shipped_tyre/   on a tyre other than the shipped one: both tests again on the shipped tyre
                  (their runs); the report's table says what changed (understeer, yaw gain, ...)
  summary.json, report.md, diagram.svg

--scene_text is laid over both scenes (e.g. "drive: !PrescribedRotation {}", or another tyre:
"{tyres: !MagicFormula {tir_file: FILE}}"); --ay_range is the
linear range the gradients are fitted over. The cross-check needs the test extra
commonroad-vehicle-models; without it (or with --no_crosscheck) it is left out and the report
says so.

Example:  drake-car-handling --out results/handling
          drake-car-handling --out results/handling_locked \\
              --scene_text "drive: !PrescribedRotation {}"
          drake-car-handling --out results/handling_sedan --scene_text \\
              "{tyres: !MagicFormula {tir_file: tests/data/tyres/Sedan_Pac02Tire.tir}}"
"""

import argparse
import time

from drake_car.commands import cli
from drake_car.data import resource
from drake_car.results.files import write_json, write_text
from drake_car.results.folder import output_folder
from drake_car.results.provenance import provenance
from drake_car.scene.study_file import load_study_file
from drake_car.study.handling.analysis import check_scenes, crosscheck_left_out, handling_study
from drake_car.study.handling.measures import DEFAULT_AY_RANGE, HandlingError
from drake_car.study.handling.outputs import summary, write_outputs
from drake_car.study.handling.report import report

HANDLING = resource("scenes/handling.yaml")


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


def main(argv=None):
    p = cli.parser(__doc__, name="handling", scene=True, scene_default=str(HANDLING),
                   scene_help=(
                       "the handling scenes file (not your car: give that with --scene_text "
                       "\"car_file: FILE\")"), scene_text="YAML laid over both scenes")
    p.add_argument("--ay_range", type=ay_range, default=DEFAULT_AY_RANGE,
                   help="LO,HI: the linear range of a_y (m/s²) the gradients are fitted over "
                        "(default: 0.5,3.0)")
    p.add_argument("--no_crosscheck", action="store_true",
                   help="leave out the cross-check against CommonRoad's model")
    p.add_argument("--no_shipped_comparison", action="store_true",
                   help="on a tyre other than the shipped one, do not run the tests again on "
                        "the shipped tyre (the report then says nothing of what changed)")
    args = p.parse_args(argv)
    cli.check_out(args)
    scenes = load_study_file(args.scene, args.scene_text or None,
                             command=cli.command_name("handling"), holds=(
                                 "the handling scenes file: its entries steady_state and "
                                 "step_steer (as scenes/handling.yaml)"))
    check_scenes(scenes, args.scene)
    why = crosscheck_left_out(args.no_crosscheck)
    began = time.perf_counter()
    with output_folder(args.out) as out:
        try:
            runs, result, walls = handling_study(
                scenes, args.ay_range, crosscheck_why=why, progress=not args.quiet,
                shipped_why=("left out (--no_shipped_comparison)"
                             if args.no_shipped_comparison else None))
        except HandlingError as e:
            raise HandlingError(f"{args.scene}: {e}") from None
        write_outputs(out, runs, result, scenes["steady_state"])
        result["wall_s"] = {"total": time.perf_counter() - began} | walls
        result["provenance"] = provenance()
        write_json(out / "summary.json", summary(result))
        write_text(out / "report.md", report(result))
    ss = result["steady_state"]["metrics"]
    change = {r["quantity"]: r for r in result.get("tyre_change", {}).get("rows", [])}
    against = ""
    if change:
        k = change["understeer gradient, δ from the rack"]
        r = change["steady-state yaw-rate gain dr/dδ (rack)"]
        against = (f" (shipped tyre: {k['shipped']:.2f} deg/g, yaw gain {r['shipped']:.3f} "
                   f"against {r['this']:.3f} 1/s)")
    print(f"tyre {result['tyre']['file']} ({result['tyre']['form']}): understeer "
          f"{ss['understeer_gradient_deg_per_g']:.2f} deg/g{against}, roll "
          f"{ss['roll_gradient_deg_per_g']:.2f} deg/g, yaw gain "
          f"{result['steady_state']['yaw_gain_ratio']:.3f} of the single-track model; wrote "
          f"{args.out} (report: {args.out / 'report.md'})")


def console():
    """The console script ``drake-car-handling``."""
    cli.run_main(main)


if __name__ == "__main__":
    console()
