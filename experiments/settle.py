"""The car settles under gravity from its design position.

Writes DIR/settle.json (corner_loads_N, ride_height_m, strut_overlap_m, design_axle_loads_N,
total_mass_kg, ...), DIR/settle_history.csv and DIR/settle.png; with --scene also
DIR/scene.yaml, and DIR/replay.html if the scene asks for visualization meshcat_html.

Example:  python experiments/settle.py --out results/settle
"""

import _common  # noqa: F401  (sets the path and the plotting backend)

import matplotlib.pyplot as plt

from drake_car.law.frd_friction import StrutFrictionParameters
from drake_car.model.parameters import CarParameters
from drake_car.outputs import output_folder, provenance, write_csv, write_json
from drake_car.scene import dump_scene, resolve
from drake_car.scene_run import run_scene
from drake_car.settle import run_settle
from drake_car.systems.strut_friction import StrutFrictionSetup


def main():
    p = _common.parser(__doc__)
    p.add_argument("--duration_s", type=_common.positive("duration_s"), default=5.0)
    p.add_argument("--time_step_s", type=_common.positive("time_step_s"), default=1e-3)
    p.add_argument("--mu_s", type=_common.nonnegative("mu_s"), default=0.0,
                   help="strut friction (0: lubricated strut with 1250 N s/m damping)")
    p.add_argument("--mu_d", type=_common.nonnegative("mu_d"), default=0.0)
    p.add_argument("--scheme", choices=["fast", "reference"], default="fast")
    _common.add_scene_options(p)
    args = p.parse_args()
    scene = _common.load_scene_option(p, args)
    params = CarParameters()
    friction = None
    if scene is not None:
        if scene.manoeuvre.kind != "settle":
            p.error(f"--scene: {scene.name!r} is not a settle scene")
        resolved = resolve(scene)
        friction = resolved.friction
        result = run_scene(scene)
    else:
        if args.mu_s > 0:
            try:
                law = StrutFrictionParameters(mu_s=args.mu_s, mu_d=args.mu_d)
            except ValueError as e:
                p.error(str(e))
            friction = StrutFrictionSetup(law, scheme=args.scheme)
            params.front.strut_damping_Nspm = 0.0  # dry strut (paper section 4)
        result = run_settle(params, friction=friction, duration_s=args.duration_s,
                            time_step_s=args.time_step_s)
    with output_folder(args.out) as out:
        summary = result.summary()
        summary["friction"] = ({"mu_s": friction.params.mu_s, "mu_d": friction.params.mu_d,
                                "scheme": friction.scheme}
                               if friction else "off (lubricated, 1250 N s/m)")
        if scene is not None:
            (out / "scene.yaml").write_text(dump_scene(scene))
        if result.html is not None:  # the scene asked for visualization: meshcat_html
            (out / "replay.html").write_text(result.html)
        summary["provenance"] = provenance()
        write_json(out / "settle.json", summary)
        write_csv(out / "settle_history.csv", result.history)
        plot(result, out / "settle.png")
    loads = result.corner_loads_N
    front, rear = loads["fl"] + loads["fr"], loads["rl"] + loads["rr"]
    design = result.design_axle_loads_N
    print(f"front axle {front:.0f} N (design {design['front']:.0f} N, "
          f"{100 * (front / design['front'] - 1):+.2f} %), rear axle {rear:.0f} N "
          f"(design {design['rear']:.0f} N, {100 * (rear / design['rear'] - 1):+.2f} %)")
    print(f"ride height front {result.ride_height_m['front']:.4f} m, rear "
          f"{result.ride_height_m['rear']:.4f} m; overlap d left "
          f"{result.strut_overlap_m['left']:.5f} m, right {result.strut_overlap_m['right']:.5f} m")
    print(f"wrote {args.out}/settle.json")


def plot(result, path):
    h = result.history
    fig, axes = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    for w in ("fl", "fr", "rl", "rr"):
        axes[0].plot(h["t"], h[f"Fz_{w}_N"], label=w)
    axes[0].set_ylabel("wheel load Fz [N]")
    axes[0].legend(ncol=4)
    for s in ("left", "right"):
        axes[1].plot(h["t"], 1e3 * h[f"d_{s}_m"], label=f"overlap d {s}")
    axes[1].set_ylabel("strut overlap d [mm]")
    axes[1].set_xlabel("t [s]")
    axes[1].legend()
    fig.suptitle("Settling from the design position")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
