"""The car checked on its own: the lubricated car settling from its design position (corner
loads against the real car's axle loads, ride heights, strut overlaps), the suspension's
kinematics (chassis fixed), the Diagram of the car with strut friction, and a Meshcat replay of
the car settling with jammed struts. Writes into DIR:

  hard_points.csv  the car's hard-point table: its inputs (a car file's points, or today's
               parameters) beside what the model derives (b, kingpin, caster, scrub radius,
               the strut's and spring's inclinations, the sprung mass's CoG, ride frequencies);
               a row the scene's car: values changed against the car file's (or the shipped
               car's) is marked "input (scene)" or "moved (scene)", its value beside
  settle/      the lubricated car settling (drake-car-run's files, settle.json)
  kinematics/  kinematics.csv, steering.csv and their plots
  jammed/      the car settling with μs = 0.4 (scene car.yaml:settle_jammed), its replay.html
               and diagram.svg (the Diagram with strut friction, as it ran)
  report.md    the figures, how they were made, and where to look

(The paper's phase I with the three friction sets is part of the paper's study,
drake-car-paper.)

Example:  drake-car-car-checks --out results/car
"""

import dataclasses
import time

from drake_car.commands import cli
from drake_car.data import resource
from drake_car.model.kinematics_sweep import run_kinematics_sweep
from drake_car.scene.load import load_scene
from drake_car.scene.scene import MeshcatReplay
from drake_car.results.files import write_csv, write_json, write_run
from drake_car.results.folder import output_folder
from drake_car.sim.simulate import simulate
from drake_car.study.car.figures import plot_kinematics, plot_steering
from drake_car.model.hard_point_table import table_columns
from drake_car.study.car.report import hard_point_rows, write_report

CAR_SCENES = resource("scenes/car.yaml")


def main(argv=None):
    p = cli.parser(__doc__, name="car_checks",
                   scene_text="YAML laid over both settling scenes (e.g. the car's parameters)")
    args = p.parse_args(argv)
    cli.check_out(args)
    text = args.scene_text or None
    lubricated = load_scene(CAR_SCENES, child="settle", scene_text=text)
    jammed = load_scene(CAR_SCENES, child="settle_jammed", scene_text=text)
    jammed = dataclasses.replace(jammed, visualization=MeshcatReplay(camera="follow"))
    began = time.perf_counter()
    with output_folder(args.out) as out:
        settled = simulate(lubricated, progress=not args.quiet)
        (out / "settle").mkdir()
        write_run(settled, out / "settle")
        write_json(out / "settle" / "settle.json",
                   {k: v for k, v in settled.final.items() if k != "positions"})
        sweep = run_kinematics_sweep(lubricated.car)
        (out / "kinematics").mkdir()
        write_csv(out / "kinematics" / "kinematics.csv", sweep.kinematics)
        write_csv(out / "kinematics" / "steering.csv", sweep.steering)
        plot_kinematics(sweep.kinematics, out / "kinematics" / "kinematics.png")
        plot_steering(sweep.steering, out / "kinematics" / "steering.png")
        stuck = simulate(jammed, progress=not args.quiet)
        (out / "jammed").mkdir()
        write_run(stuck, out / "jammed")
        rows = hard_point_rows(lubricated)
        write_csv(out / "hard_points.csv", table_columns(rows))
        write_report(out / "report.md", settled, sweep, stuck, time.perf_counter() - began,
                     rows)
    print(f"wrote {args.out} (report: {args.out / 'report.md'})")


def console():
    """The console script ``drake-car-car-checks``."""
    cli.run_main(main)


if __name__ == "__main__":
    console()
