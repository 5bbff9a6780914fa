"""Calibrates a lane change's rack profile for the scene's car, now: the Akima knots of one sine
period (their amplitude and the return turn's relative amplitude) that move the car's track
``shift_m`` (3.7 m) sideways during phase III (2.4 s at 60 km/h) and end parallel, from static
equilibrium, with lubricated struts (sim.lane_change_calibration).

Every run does this by itself: a lane change without amplitude_m and second_lobe is calibrated
for the car that runs it the first time its inputs (car, tyres, road, drive, timeline) are
seen, and kept in the calibration cache (drake-car-cache); the
shipped Escort's calibration (drake_car/scene/lane_change_profile.json) is used where its
recorded inputs match. This command calibrates anew (from the shipped profile: a car it still
fits takes one run), keeps the result in the cache and prints it; --out FILE also writes it
(profile, inputs' content hash, residual, iterations, cost, provenance). After a change that
leaves the Escort's car as it was but changes the form of its inputs (a new scene key with its
default), rewrite the shipped calibration's record with
--out drake_car/scene/lane_change_profile.json.

  drake-car-calibrate [--scene FILE[:ENTRY]] [--scene_text YAML] [--out FILE]
"""

import dataclasses
import json

from drake_car.commands import cli
from drake_car.law.errors import InputError
from drake_car.results.files import write_text
from drake_car.results.folder import check_output_file
from drake_car.results.provenance import provenance
from drake_car.scene.manoeuvres import LaneChange
from drake_car.sim import lane_change_cache
from drake_car.sim.lane_change_calibration import calibrate, calibration_scene
from drake_car.sim.simulate import simulate


def main(argv=None):
    p = cli.parser(__doc__, name="calibrate", out="optional", out_help="also write the "
                   "calibration to this JSON file", scene=True,
                   scene_help="the car, tyres, road, drive and timeline from this scene "
                              "(FILE[:ENTRY]; default: the default scene)")
    p.add_argument("--shift_m", type=cli.positive("shift_m"), default=None,
                   help="the lateral shift to calibrate for (default: the scene's lane "
                        "change's shift_m, 3.7 m)")
    args = p.parse_args(argv)
    if args.out is not None:
        check_output_file(args.out)  # before the calibration's runs
    scene = cli.scene_from_args(args)
    if not isinstance(scene.manoeuvre, LaneChange):
        raise InputError(f"scene {scene.name}: manoeuvre = {type(scene.manoeuvre).__name__}; "
                         "the calibration needs a !LaneChange")
    if args.shift_m is not None:
        scene = dataclasses.replace(scene, manoeuvre=dataclasses.replace(
            scene.manoeuvre, shift_m=args.shift_m))
    calibrating = calibration_scene(scene)
    content = lane_change_cache.content_sha256(calibrating)
    found = calibrate(calibrating, run=simulate)
    lane_change_cache.store(content, found)
    profile, residual, cost = found["profile"], found["residual"], found["cost"]
    if args.out is not None:
        record = {"profile": profile,
                  "inputs": {"content_sha256": content,
                             "what": "sim.lane_change_cache.content_sha256 of the calibration "
                                     f"scene of {args.scene or 'the default scene'}"},
                  "residual": residual, "cost": cost, "calibration": found["iterations"],
                  "provenance": provenance(target_shift_m=calibrating.manoeuvre.shift_m,
                                           scene=scene.name)}
        args.out.parent.mkdir(parents=True, exist_ok=True)
        write_text(args.out, json.dumps(record, indent=2) + "\n")  # whole, or not at all
    print(f"amplitude {profile['amplitude_m']:.6f} m, second lobe {profile['second_lobe']:.4f}: "
          f"shift {residual['shift_m']:.4f} m, heading change "
          f"{residual['heading_change_deg']:+.4f} deg; {cost['runs']} runs, "
          f"{cost['wall_s']:.0f} s wall, {cost['cpu_s']:.0f} s CPU; kept in "
          f"{lane_change_cache.cache_folder() or 'this process only (cache off)'}"
          + (f"; wrote {args.out}" if args.out is not None else ""))


def console():
    """The console script ``drake-car-calibrate``."""
    cli.run_main(main)


if __name__ == "__main__":
    console()
