"""Calibrates the lane change's rack profile (Akima knots of one sine period: its amplitude and
the return turn's relative amplitude) so that the car's track shifts 3.7 m during the 2.4 s of
phase III at 60 km/h and ends parallel, starting at rest in static equilibrium as every study
run does. Writes the result, with every iteration, to the package's lane-change calibration
(drake_car/scene/lane_change_profile.json: the !LaneChange defaults) or to --out FILE.

  drake-car-calibrate [--scene FILE[:ENTRY]] [--scene_text YAML]
"""

import importlib.resources
from pathlib import Path

from drake_car.commands import cli
from drake_car.results.provenance import provenance
from drake_car.study.paper.calibration import calibrate_lane_change, save_calibration

DEFAULT = Path(str(importlib.resources.files("drake_car.scene").joinpath(
    "lane_change_profile.json")))


def main(argv=None):
    p = cli.parser(__doc__, name="calibrate", out=DEFAULT, out_help="where to write (a JSON "
                   "file; default: the package's calibration, %(default)s)", scene=True,
                   scene_help="the car, tyres and timeline from this scene (FILE[:ENTRY]; "
                              "default: the default scene)")
    p.add_argument("--shift_m", type=cli.positive("shift_m"), default=3.7)
    args = p.parse_args(argv)
    scene = cli.scene_from_args(args)
    manoeuvre, history = calibrate_lane_change(scene, shift_m=args.shift_m)
    tmp = args.out.with_suffix(".partial")
    save_calibration(tmp, manoeuvre, history, provenance(target_shift_m=args.shift_m,
                                                         scene=scene.name))
    tmp.replace(args.out)
    print(f"amplitude {manoeuvre.amplitude_m:.6f} m, second lobe {manoeuvre.second_lobe:.4f}; "
          f"wrote {args.out}")


def console():
    """The console script ``drake-car-calibrate``."""
    cli.run_main(main)


if __name__ == "__main__":
    console()
