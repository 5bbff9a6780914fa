"""Suspension kinematics rig: chassis fixed, each front wheel through ±80 mm, rack through its
stroke. Loops are closed by Newton's method (closure error at round-off).

Writes DIR/kinematics.csv (side, wheel_travel_m, camber_deg, toe_deg [toe-in +], caster_deg,
kingpin_deg, strut_length_m, overlap_m, closure_error_m), DIR/steering.csv (rack_m [+ = rack to
the left], steer_left_deg, steer_right_deg [+ = wheel steered left], closure_error_m),
DIR/kinematics.png and DIR/steering.png.

Example:  drake-car-kinematics --out results/kinematics
"""

from drake_car.commands import cli
from drake_car.model.kinematics_sweep import run_kinematics_sweep
from drake_car.results.files import write_csv, write_json
from drake_car.results.folder import output_folder
from drake_car.results.provenance import provenance
from drake_car.study.car.figures import plot_kinematics, plot_steering


def main(argv=None):
    p = cli.parser(__doc__, name="kinematics", scene=True,
                   scene_help="the car's parameters from this scene (FILE[:ENTRY]; default: "
                              "the default car)")
    p.add_argument("--travel_m", type=cli.positive("travel_m"), default=0.08)
    p.add_argument("--points", type=int, default=33)
    p.add_argument("--model", default=None,
                   help="a car model file to use instead of the one generated from the scene's "
                        "car parameters")
    args = p.parse_args(argv)
    if not 3 <= args.points <= 1001:
        p.error("--points must lie in [3, 1001]")
    if args.travel_m > 0.2:
        p.error("--travel_m must be <= 0.2 m (a strut's whole travel)")
    cli.check_out(args)
    params = cli.scene_from_args(args, runs=False).car  # the car alone: nothing drives
    with output_folder(args.out) as out:
        sweep = run_kinematics_sweep(params, travel_m=args.travel_m, points=args.points,
                                     model_path=args.model)
        write_csv(out / "kinematics.csv", sweep.kinematics)
        write_csv(out / "steering.csv", sweep.steering)
        write_json(out / "kinematics_meta.json", provenance(travel_m=args.travel_m,
                                                             points=args.points))
        plot_kinematics(sweep.kinematics, out / "kinematics.png")
        plot_steering(sweep.steering, out / "steering.png")
    worst = max(max(sweep.kinematics["closure_error_m"]), max(sweep.steering["closure_error_m"]))
    print(f"largest loop-closure error {worst:.1e} m; wrote {args.out}")


def console():
    """The console script ``drake-car-kinematics``."""
    cli.run_main(main)


if __name__ == "__main__":
    console()
