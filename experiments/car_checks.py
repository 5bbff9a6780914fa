"""The car checked on its own: the lubricated car settling from its design position (corner
loads against the real car's axle loads, ride heights, strut overlaps), the suspension's
kinematics (chassis fixed), the Diagram of the car with strut friction, and a Meshcat replay of
the car settling with jammed struts. Writes into DIR:

  settle/      the lubricated car settling (python -m drake_car.run's files, settle.json)
  kinematics/  kinematics.csv, steering.csv and their plots
  jammed/      the car settling with μs = 0.4 (scene car.yaml:settle_jammed), its replay.html
               and diagram.svg (the Diagram with strut friction, as it ran)
  report.md    the figures, how they were made, and where to look

(The paper's phase I with the three friction sets is part of the paper's study,
experiments/lane_change.py.)

Example:  python experiments/car_checks.py --out results/car
"""

import dataclasses
import time

import numpy as np

import suspension_kinematics as kinematics_script
from drake_car import cli
from drake_car.data import resource
from drake_car.model.kinematics_sweep import run_kinematics_sweep
from drake_car.scene.load import load_scene
from drake_car.scene.scene import MeshcatReplay
from drake_car.results.files import write_csv, write_json, write_run
from drake_car.results.folder import output_folder
from drake_car.results.provenance import provenance
from drake_car.sim.simulate import simulate

CAR_SCENES = resource("scenes/car.yaml")


def main(argv=None):
    p = cli.parser(__doc__)
    p.add_argument("--scene_text", default="",
                   help="YAML laid over both settling scenes (e.g. the car's parameters)")
    args = p.parse_args(argv)
    cli.check_out(args)
    text = args.scene_text or None
    lubricated = load_scene(CAR_SCENES, child="settle", scene_text=text)
    jammed = load_scene(CAR_SCENES, child="settle_jammed", scene_text=text)
    jammed = dataclasses.replace(jammed, visualization=MeshcatReplay(camera="follow"))
    began = time.perf_counter()
    with output_folder(args.out) as out:
        settled = simulate(lubricated, progress=True)
        (out / "settle").mkdir()
        write_run(settled, out / "settle")
        write_json(out / "settle" / "settle.json",
                   {k: v for k, v in settled.final.items() if k != "positions"})
        sweep = run_kinematics_sweep(lubricated.car)
        (out / "kinematics").mkdir()
        write_csv(out / "kinematics" / "kinematics.csv", sweep.kinematics)
        write_csv(out / "kinematics" / "steering.csv", sweep.steering)
        kinematics_script.plot_kinematics(sweep.kinematics, out / "kinematics" / "kinematics.png")
        kinematics_script.plot_steering(sweep.steering, out / "kinematics" / "steering.png")
        stuck = simulate(jammed, progress=True)
        (out / "jammed").mkdir()
        write_run(stuck, out / "jammed")
        write_report(out / "report.md", settled, sweep, stuck, time.perf_counter() - began)
    print(f"wrote {args.out} (report: {args.out / 'report.md'})")


def write_report(path, settled, sweep, stuck, wall):
    final = settled.final
    loads, design = final["corner_loads_N"], final["design_axle_loads_N"]
    front, rear = loads["fl"] + loads["fr"], loads["rl"] + loads["rr"]
    k = sweep.kinematics
    left = np.array(k["side"]) == "left"

    def span(name):
        values = np.array(k[name])[left]
        return f"{values.min():.2f} … {values.max():.2f}"

    h = stuck.history
    late = h["t"] >= 0.8
    moved = max(float(np.ptp(h[f"d_{s}_m"][late])) for s in ("left", "right"))
    prov = provenance()
    lines = [
        "# drake_car: the car on its own", "",
        f"Made by `{prov['command']}`; {prov['created_utc']}, drake {prov['drake']}, commit "
        f"{(prov['git_commit'] or 'unknown')[:10]}; {wall:.1f} s wall.", "",
        "## The settled car (lubricated struts)", "",
        "| quantity | model | real car [ESC] |", "|---|---|---|",
        f"| front axle load | {front:.0f} N | {design['front']:.0f} N "
        f"({100 * (front / design['front'] - 1):+.2f} %) |",
        f"| rear axle load | {rear:.0f} N | {design['rear']:.0f} N "
        f"({100 * (rear / design['rear'] - 1):+.2f} %) |",
        f"| total mass | {final['total_mass_kg']:.1f} kg | "
        f"{settled.scene.car.mass.total_mass_kg} kg |",
        f"| ride height front / rear | {final['ride_height_m']['front']:.4f} / "
        f"{final['ride_height_m']['rear']:.4f} m | design "
        f"{settled.scene.car.tyre.unloaded_radius_m} m |",
        f"| strut overlap d left / right | {final['strut_overlap_m']['left']:.5f} / "
        f"{final['strut_overlap_m']['right']:.5f} m | design "
        f"{settled.scene.car.front.guide_length_l_m} m |",
        f"| loop-closure error (SAP) | {final['loop_closure_error_m']:.1e} m | |", "",
        "[ESC]: Ford Escort data, see `drake_car/model/parameters.py`. The scene as it ran: "
        "`settle/scene.yaml`.", "",
        "## Kinematics (chassis fixed, ±80 mm, left wheel)", "",
        f"camber {span('camber_deg')} deg, toe-in {span('toe_deg')} deg, caster "
        f"{span('caster_deg')} deg, kingpin {span('kingpin_deg')} deg, strut length "
        f"{span('strut_length_m')} m, overlap d {span('overlap_m')} m; largest loop-closure "
        f"error {max(k['closure_error_m']):.1e} m (Newton). Plots: `kinematics/*.png`.", "",
        "## Jammed struts (μs = 0.4)", "",
        f"Settling from the design position, the rods move {1e6 * moved:.1f} µm after 0.8 s "
        "(the creep bound Δmax is 5 µm). Replay: `jammed/replay.html`; the Diagram with strut "
        "friction, as it ran: `jammed/diagram.svg`.", ""]
    path.write_text("\n".join(lines))


if __name__ == "__main__":
    cli.run_main(main)
