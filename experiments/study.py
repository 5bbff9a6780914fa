"""The car checked: settling, kinematics, and the settling part of phase I of the paper's study
(the paper's study itself is experiments/lane_change.py).

Runs, into one output folder (default results/car/):
  settle/          the lubricated car settling from its design position (settle.json, plots)
  kinematics/      the kinematics rig (kinematics.csv, steering.csv, plots)
  phase_I.csv/png  the rod displacement Δd while the car settles, for the paper's three friction
                   sets (μs, μd) = (0, 0) + 1250 N s/m, (0.2, 0.15), (0.4, 0.3) (Fig. 14, phase I)
  diagram.svg      the car's Diagram with strut friction (Graphviz)
  car.html         the car settling with μs = 0.4, recorded in Meshcat (self-contained page)
  report.md        the figures, how they were made, and where to look
"""

import sys
import time

import _common  # noqa: F401

import matplotlib.pyplot as plt
import numpy as np
from pydrake.systems.analysis import Simulator

import settle as settle_script
import suspension_kinematics as kinematics_script
from drake_car.assembly import build_car_diagram
from drake_car.kinematics_rig import run_kinematics_sweep
from drake_car.model.parameters import CarParameters
from drake_car.outputs import Progress, output_folder, provenance, write_csv, write_json
from drake_car.pictures import record_html, start_meshcat, write_diagram_svg
from drake_car.settle import run_settle
from drake_car.scene import SceneError
from drake_car.study import FRICTION_SETS, RunConfig



def car_for_set(number, scene_file=None, scene_text=""):
    """The car and strut friction of the paper's friction set ``number`` (1, 2, 3)."""
    config = RunConfig("a", number, scene_text=scene_text)
    if scene_file:
        config.scene_file = scene_file
    return config.car()


def main():
    p = _common.parser(__doc__, default_out=_common.REPO_ROOT / "results" / "car")
    p.add_argument("--settle_s", type=_common.positive("settle_s"), default=4.0,
                   help="simulated settling time per run (s)")
    p.add_argument("--html_s", type=_common.positive("html_s"), default=1.5,
                   help="simulated time recorded in car.html (s)")
    p.add_argument("--scene", default=None,
                   help="the study's scenes (entries a_1 ... b_3; default "
                        "scenes/paper_study.yaml)")
    p.add_argument("--scene_text", default="",
                   help="YAML laid over every friction set's scene")
    args = p.parse_args()
    try:
        cars = {n: car_for_set(n, args.scene, args.scene_text) for n in FRICTION_SETS}
    except (SceneError, ValueError) as e:
        p.error(str(e))
    progress = Progress("study", 6)
    figures = {}
    with output_folder(args.out) as out:
        start = time.perf_counter()
        lubricated = run_settle(cars[1][0], duration_s=args.settle_s)
        (out / "settle").mkdir()
        summary = lubricated.summary() | {"provenance": provenance()}
        write_json(out / "settle" / "settle.json", summary)
        write_csv(out / "settle" / "settle_history.csv", lubricated.history)
        settle_script.plot(lubricated, out / "settle" / "settle.png")
        progress.update(1, "settled the lubricated car")

        sweep = run_kinematics_sweep(cars[1][0])
        (out / "kinematics").mkdir()
        write_csv(out / "kinematics" / "kinematics.csv", sweep.kinematics)
        write_csv(out / "kinematics" / "steering.csv", sweep.steering)
        kinematics_script.plot_kinematics(sweep.kinematics, out / "kinematics" / "kinematics.png")
        kinematics_script.plot_steering(sweep.steering, out / "kinematics" / "steering.png")
        progress.update(2, "kinematics rig")

        runs = {}
        for number in FRICTION_SETS:
            params, friction = cars[number]
            runs[number] = run_settle(params, friction=friction, duration_s=args.settle_s)
            progress.update(2 + number, f"phase I, friction set {number}")
        columns = {"t": runs[1].history["t"]}
        for number, run in runs.items():
            for side in ("left", "right"):
                d = run.history[f"d_{side}_m"]
                columns[f"dd_{side}_set{number}_m"] = d - d[0]  # Δd: overlap growth (rod in) +
        write_csv(out / "phase_I.csv", columns)
        figures["phase_I"] = plot_phase_one(columns, out / "phase_I.png")

        params, friction = cars[3]
        meshcat = start_meshcat()
        built = build_car_diagram(params, friction=friction, meshcat=meshcat)
        write_diagram_svg(built.diagram, out / "diagram.svg")
        simulator = Simulator(built.diagram)
        simulator.Initialize()
        record_html(meshcat, simulator, args.html_s, out / "car.html")
        progress.update(6, "pictures")
        wall = time.perf_counter() - start
        write_report(out / "report.md", lubricated, sweep, runs, wall, args)
    print(f"wrote {args.out} (report: {args.out / 'report.md'})")


def plot_phase_one(columns, path):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4), sharey=True)
    t = columns["t"]
    for ax, side in zip(axes, ("left", "right")):
        for number, (mu_s, mu_d) in FRICTION_SETS.items():
            ax.plot(t, 1e3 * columns[f"dd_{side}_set{number}_m"],
                    label=f"{number}: μs={mu_s}, μd={mu_d}")
        ax.set_title(f"{side} strut")
        ax.set_xlabel("t [s]")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("Δd from the design position [mm] (rod in +)")
    axes[0].legend()
    fig.suptitle("Phase I: the car settles from its design position (cf. paper Fig. 14)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path.name


def late_window(t):
    """Samples after the paper's 0.8 s of settling (the last half of a shorter run)."""
    return t >= min(0.8, t[-1] / 2)


def write_report(path, lubricated, sweep, runs, wall, args):
    loads, design = lubricated.corner_loads_N, lubricated.design_axle_loads_N
    front, rear = loads["fl"] + loads["fr"], loads["rl"] + loads["rr"]
    k = sweep.kinematics
    side = np.array(k["side"])
    left = side == "left"
    lines = [
        "# drake_car: the car and phase I of the paper's study",
        "",
        f"Made by `{' '.join(sys.argv)}`; {provenance()['created_utc']}, drake "
        f"{provenance()['drake']}, commit {provenance()['git_commit'][:10]}; {wall:.1f} s wall.",
        "",
        "## The settled car (lubricated struts, 1250 N s/m)",
        "",
        "| quantity | model | real car [ESC] |",
        "|---|---|---|",
        f"| front axle load | {front:.0f} N | {design['front']:.0f} N "
        f"({100 * (front / design['front'] - 1):+.2f} %) |",
        f"| rear axle load | {rear:.0f} N | {design['rear']:.0f} N "
        f"({100 * (rear / design['rear'] - 1):+.2f} %) |",
        f"| total mass | {lubricated.total_mass_kg:.1f} kg | 1225.9 kg |",
        f"| ride height front / rear | {lubricated.ride_height_m['front']:.4f} / "
        f"{lubricated.ride_height_m['rear']:.4f} m | design "
        f"{CarParameters().tyre.unloaded_radius_m} m |",
        f"| strut overlap d left / right | {lubricated.strut_overlap_m['left']:.5f} / "
        f"{lubricated.strut_overlap_m['right']:.5f} m | design 0.14 m |",
        f"| loop-closure error (SAP) | {lubricated.loop_closure_error_m:.1e} m | |",
        "",
        "Plots: `settle/settle.png`. [ESC]: Ford Escort data, see "
        "`drake_car/model/parameters.py`.",
        "",
        "## Kinematics rig (chassis fixed, ±80 mm)",
        "",
        f"- camber {min(np.array(k['camber_deg'])[left]):.2f} … "
        f"{max(np.array(k['camber_deg'])[left]):.2f} deg, toe-in "
        f"{min(np.array(k['toe_deg'])[left]):.2f} … {max(np.array(k['toe_deg'])[left]):.2f} deg,"
        f" strut length {min(np.array(k['strut_length_m'])[left]):.3f} … "
        f"{max(np.array(k['strut_length_m'])[left]):.3f} m, overlap d "
        f"{min(np.array(k['overlap_m'])[left]):.3f} … {max(np.array(k['overlap_m'])[left]):.3f} m",
        f"- largest loop-closure error {max(k['closure_error_m']):.1e} m (Newton)",
        f"- rack ±{1e3 * max(sweep.steering['rack_m']):.0f} mm steers the left wheel "
        f"{min(sweep.steering['steer_left_deg']):.1f} … "
        f"{max(sweep.steering['steer_left_deg']):.1f} deg",
        "",
        "Plots: `kinematics/kinematics.png`, `kinematics/steering.png`.",
        "",
        "## Phase I with the paper's friction sets (fast scheme, 1 ms)",
        "",
        "| set | μs, μd | Δd left at end [mm] | rod moved after 0.8 s [µm] | wall [s] |",
        "|---|---|---|---|---|",
    ]
    for number, run in runs.items():
        d = run.history["d_left_m"]
        after = late_window(run.history["t"])
        lines.append(
            f"| {number} | {FRICTION_SETS[number]} | {1e3 * (d[-1] - d[0]):.3f} | "
            f"{1e6 * np.ptp(d[after]):.1f} | {run.wall_s:.2f} |")
    jammed = 1e6 * np.ptp(runs[3].history["d_left_m"][late_window(runs[3].history["t"])])
    lines += [
        "",
        f"Paper claim (Fig. 14, curve 3): with (0.4, 0.3) the rods do not return in phase I. "
        f"Here the rod moves {jammed:.1f} µm after 0.8 s (Δmax = 5 µm): "
        f"{'reproduced' if jammed <= 10 else 'not reproduced'}. Plot: `phase_I.png`.",
        "",
        "Pictures: `diagram.svg` (the Diagram, plant ports split by I/O), `car.html` "
        "(Meshcat replay of the car settling with μs = 0.4).",
        "",
    ]
    path.write_text("\n".join(lines))


if __name__ == "__main__":
    main()
