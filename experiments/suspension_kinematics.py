"""Suspension kinematics rig: chassis fixed, each front wheel through ±80 mm, rack through its
stroke. Loops are closed by Newton's method (closure error at round-off).

Writes DIR/kinematics.csv (side, wheel_travel_m, camber_deg, toe_deg [toe-in +], caster_deg,
kingpin_deg, strut_length_m, overlap_m, closure_error_m), DIR/steering.csv (rack_m [+ = rack to
the left], steer_left_deg, steer_right_deg [+ = wheel steered left], closure_error_m),
DIR/kinematics.png and DIR/steering.png.

Example:  python experiments/suspension_kinematics.py --out results/kinematics
"""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from drake_car import cli  # noqa: E402
from drake_car.model.kinematics_sweep import run_kinematics_sweep  # noqa: E402
from drake_car.results.files import write_csv, write_json  # noqa: E402
from drake_car.results.folder import output_folder  # noqa: E402
from drake_car.results.provenance import provenance  # noqa: E402


def main(argv=None):
    p = cli.parser(__doc__)
    p.add_argument("--travel_m", type=cli.positive("travel_m"), default=0.08)
    p.add_argument("--points", type=int, default=33)
    p.add_argument("--model", default=None,
                   help="a car model file to use instead of the one generated from the scene's "
                        "car parameters")
    cli.add_scene_options(p, help_scene="the car's parameters from this scene (FILE[:ENTRY]; "
                                        "default: the default car)")
    args = p.parse_args(argv)
    if not 3 <= args.points <= 1001:
        p.error("--points must lie in [3, 1001]")
    if args.travel_m > 0.2:
        p.error("--travel_m must be <= 0.2 m (a strut's whole travel)")
    cli.check_out(args)
    params = cli.scene_from_args(args).car
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


def plot_kinematics(table, path):
    fields = [("camber_deg", "camber [deg]"), ("toe_deg", "toe-in [deg]"),
              ("caster_deg", "caster [deg]"), ("kingpin_deg", "kingpin incl. [deg]"),
              ("strut_length_m", "strut length [m]"), ("overlap_m", "overlap d [m]")]
    fig, axes = plt.subplots(2, 3, figsize=(12, 6.5))
    side = np.array(table["side"])
    travel = 1e3 * np.array(table["wheel_travel_m"])
    for ax, (name, label) in zip(axes.flat, fields):
        for s, style in (("left", "-"), ("right", "--")):
            mask = side == s
            ax.plot(np.array(table[name])[mask], travel[mask], style, label=s)
        ax.set_xlabel(label)
        ax.set_ylabel("wheel travel [mm] (bump +)")
        ax.grid(alpha=0.3)
    axes[0, 0].legend()
    fig.suptitle("Front suspension kinematics (chassis fixed)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_steering(table, path):
    fig, ax = plt.subplots(figsize=(6, 4.5))
    rack = 1e3 * np.array(table["rack_m"])
    ax.plot(rack, table["steer_left_deg"], label="left wheel")
    ax.plot(rack, table["steer_right_deg"], "--", label="right wheel")
    ax.set_xlabel("rack displacement [mm] (to the left +)")
    ax.set_ylabel("wheel steer angle [deg] (left +)")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    cli.run_main(main)
