"""Runs any scene and writes what it made:

  DIR/history.csv   every logged channel (t, phase, ...; SI units in the column names)
  DIR/scene.yaml    the scene as it ran, every value (rerun it: --scene DIR/scene.yaml, from
                    the folder it ran in when it names a car or tyre file relative to it:
                    run.json's provenance.working_folder)
  DIR/run.json      how the run went: wall time, frozen SAP steps, the end state, provenance
  DIR/diagram.svg   the Diagram that ran, drawn by Graphviz; DIR/diagram.dot its Graphviz
                    source
  DIR/replay.html   the Meshcat replay, when the scene's visualization is !MeshcatReplay

The manoeuvre adapts to the car: a launch left out is the paper's 3 s or as long as the car's
drive allows (scene.launch); a lane change without amplitude_m and second_lobe has its rack
calibrated for the car the first time its inputs are seen (a few runs, kept in the calibration
cache: drake-car-cache), and scene.yaml holds what ran. A run that
does not do what its manoeuvre says (its speed at place a, a lane change's shift or its
parallel end: scene.manoeuvre_targets) is warned of on stderr. Bad input (a scene key, a
value out of range, a tyre file, an output folder): one line on stderr naming it, exit status
2, nothing written.

  drake-car-run --scene scenes/paper_study.yaml --child a_3 --out results/a_3
  drake-car-run --scene scenes/car.yaml:bump --scene_text "plant: {time_step: 5e-4}" \\
      --out results/bump
"""

import logging
import sys

from drake_car.commands import cli
from drake_car.law.errors import InputError
from drake_car.scene.load import load_scene, parse_scene_option
from drake_car.scene.manoeuvre_targets import (
    dry_friction, manoeuvre_failures, manoeuvre_measures)
from drake_car.results.files import write_run
from drake_car.results.folder import output_folder
from drake_car.results.record import rerun_note
from drake_car.sim.simulate import simulate


def main(argv=None):
    p = cli.parser(__doc__, name="run", scene=True, scene_required=True)
    p.add_argument("--child", default=None, help="the entry of the scene file to run")
    args = p.parse_args(argv)
    cli.check_out(args)
    path, child = parse_scene_option(args.scene)
    if args.child is not None:
        if child is not None and child != args.child:
            p.error(f"--scene names the entry {child!r} and --child {args.child!r}")
        child = args.child
    try:
        scene = load_scene(path, child=child, scene_text=args.scene_text or None)
    except InputError as e:  # a run's saved scene naming files of the folder it ran in
        note = rerun_note(path, child)
        if not note:
            raise
        raise InputError(f"{e}{note}") from None
    with output_folder(args.out) as out:
        run = simulate(scene, progress=not args.quiet)
        write_run(run, out)
    dry = dry_friction(run.scene)
    off = manoeuvre_failures(run.history, run.scene.manoeuvre, dry)
    if off:
        logging.getLogger("drake_car.commands.run").warning(
            "%s does not do what its manoeuvre says: %s", scene.name, "; ".join(off))
    moved = [m.describe() for m in manoeuvre_measures(run.history, run.scene.manoeuvre, dry)
             if not m.within and m.friction_effect]
    if moved:  # not judged: said, with how to judge the rack itself
        logging.getLogger("drake_car.commands.run").warning(
            "%s: %s; to check the rack itself, run the scene again with --scene_text "
            "\"friction: null\"", scene.name, "; ".join(moved))
    print(f"{scene.name}: {run.history['t'][-1]:g} s simulated in {run.wall_s:.1f} s "
          f"({run.frozen_sap_steps} frozen SAP steps); wrote {args.out}", file=sys.stderr)


def console():
    """The console script ``drake-car-run``."""
    cli.run_main(main)


if __name__ == "__main__":
    console()
