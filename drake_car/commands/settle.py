"""The car settles under gravity (a !Settle scene: by default the lubricated car dropping from
its design position onto its tyres, scenes/car.yaml:settle). Writes into DIR what
``drake-car-run`` writes (history.csv, scene.yaml, run.json, diagram.svg) and:

  settle.json   corner loads, ride heights, strut overlaps, total mass, loop-closure error,
                against the real car's design axle loads
  settle.png    wheel loads and strut overlaps against time

Examples:
  drake-car-settle --out results/settle
  drake-car-settle --out results/jammed --scene scenes/car.yaml:settle_jammed
"""

from drake_car.commands import cli
from drake_car.data import resource
from drake_car.scene.load import SceneError
from drake_car.scene.manoeuvres import Settle
from drake_car.results.files import write_json, write_run
from drake_car.results.folder import output_folder
from drake_car.results.provenance import provenance
from drake_car.sim.simulate import simulate
from drake_car.study.car.figures import plot_settle


def main(argv=None):
    p = cli.parser(__doc__, name="settle", scene=True,
                   scene_default=f"{resource('scenes/car.yaml')}:settle")
    args = p.parse_args(argv)
    cli.check_out(args)
    scene = cli.scene_from_args(args)
    if not isinstance(scene.manoeuvre, Settle):
        raise SceneError(f"--scene: {scene.name!r} is not a !Settle scene (manoeuvre "
                         f"{type(scene.manoeuvre).__name__})")
    with output_folder(args.out) as out:
        run = simulate(scene, progress=not args.quiet)
        write_run(run, out)
        final = run.final
        write_json(out / "settle.json", {k: v for k, v in final.items() if k != "positions"}
                   | {"scene": scene.name, "provenance": provenance()})
        plot_settle(run, out / "settle.png")
    loads, design = final["corner_loads_N"], final["design_axle_loads_N"]
    front, rear = loads["fl"] + loads["fr"], loads["rl"] + loads["rr"]
    print(f"front axle {front:.0f} N (design {design['front']:.0f} N, "
          f"{100 * (front / design['front'] - 1):+.2f} %), rear axle {rear:.0f} N "
          f"(design {design['rear']:.0f} N, {100 * (rear / design['rear'] - 1):+.2f} %)")
    print(f"ride height front {final['ride_height_m']['front']:.4f} m, rear "
          f"{final['ride_height_m']['rear']:.4f} m; overlap d left "
          f"{final['strut_overlap_m']['left']:.5f} m, right "
          f"{final['strut_overlap_m']['right']:.5f} m; wrote {args.out}")


def console():
    """The console script ``drake-car-settle``."""
    cli.run_main(main)


if __name__ == "__main__":
    console()
