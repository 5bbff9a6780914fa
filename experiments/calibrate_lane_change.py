"""Calibrates the lane-change rack profile (Akima knots of one sine period, amplitude and the
right turn's relative amplitude) so that at 60 km/h the car's track shifts 3.7 m during the
2.4 s of phase III and ends parallel; writes the result, with every iteration, to
scenes/lane_change_profile.json (or --out FILE).

  python experiments/calibrate_lane_change.py [--scene FILE[:ENTRY]] [--scene_text YAML]
"""

import _common

from drake_car.calibration import calibrate_lane_change, calibrated_profile, save_profile
from drake_car.manoeuvre import LaneChangeProfile
from drake_car.outputs import provenance

DEFAULT = _common.REPO_ROOT / "scenes" / "lane_change_profile.json"


def main():
    import argparse
    from pathlib import Path
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", type=Path, default=DEFAULT)
    p.add_argument("--shift_m", type=_common.positive("shift_m"), default=3.7)
    _common.add_scene_options(p)
    args = p.parse_args()
    scene = _common.load_scene_option(p, args)  # the car, its tyres and the timeline
    setup = {}
    if scene is not None:
        built = _common.resolve_or_exit(p, scene)
        setup = {"params": built.params, "tyres": built.tyres, "timeline": built.timeline}
    profile, history = calibrate_lane_change(
        shift_m=args.shift_m, start=calibrated_profile() if DEFAULT.is_file() else
        LaneChangeProfile(amplitude_m=0.0094, second_lobe=1.0), **setup)
    tmp = args.out.with_suffix(".partial")
    save_profile(tmp, profile, history, provenance(target_shift_m=args.shift_m))
    tmp.replace(args.out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
