"""The car settles under gravity (a !Settle scene: by default the lubricated car dropping from
its design position onto its tyres, scenes/car.yaml:settle). Writes into DIR what
``python -m drake_car.run`` writes (history.csv, scene.yaml, run.json, diagram.svg) and:

  settle.json   corner loads, ride heights, strut overlaps, total mass, loop-closure error,
                against the real car's design axle loads
  settle.png    wheel loads and strut overlaps against time

Examples:
  python experiments/settle.py --out results/settle
  python experiments/settle.py --out results/jammed --scene scenes/car.yaml:settle_jammed
"""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from drake_car import cli  # noqa: E402
from drake_car.data import resource  # noqa: E402
from drake_car.scene.load import SceneError  # noqa: E402
from drake_car.scene.manoeuvres import Settle  # noqa: E402
from drake_car.results.files import write_json, write_run  # noqa: E402
from drake_car.results.folder import output_folder  # noqa: E402
from drake_car.results.provenance import provenance  # noqa: E402
from drake_car.sim.simulate import simulate  # noqa: E402


def main(argv=None):
    p = cli.parser(__doc__)
    cli.add_scene_options(p, default=f"{resource('scenes/car.yaml')}:settle")
    args = p.parse_args(argv)
    cli.check_out(args)
    scene = cli.scene_from_args(args)
    if not isinstance(scene.manoeuvre, Settle):
        raise SceneError(f"--scene: {scene.name!r} is not a !Settle scene (manoeuvre "
                         f"{type(scene.manoeuvre).__name__})")
    with output_folder(args.out) as out:
        run = simulate(scene, progress=True)
        write_run(run, out)
        final = run.final
        write_json(out / "settle.json", {k: v for k, v in final.items() if k != "positions"}
                   | {"scene": scene.name, "provenance": provenance()})
        plot(run, out / "settle.png")
    loads, design = final["corner_loads_N"], final["design_axle_loads_N"]
    front, rear = loads["fl"] + loads["fr"], loads["rl"] + loads["rr"]
    print(f"front axle {front:.0f} N (design {design['front']:.0f} N, "
          f"{100 * (front / design['front'] - 1):+.2f} %), rear axle {rear:.0f} N "
          f"(design {design['rear']:.0f} N, {100 * (rear / design['rear'] - 1):+.2f} %)")
    print(f"ride height front {final['ride_height_m']['front']:.4f} m, rear "
          f"{final['ride_height_m']['rear']:.4f} m; overlap d left "
          f"{final['strut_overlap_m']['left']:.5f} m, right "
          f"{final['strut_overlap_m']['right']:.5f} m; wrote {args.out}")


def plot(run, path):
    h = run.history
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
    for ax in axes:
        ax.grid(alpha=0.3)
    fig.suptitle(f"Settling: {run.scene.name}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    cli.run_main(main)
