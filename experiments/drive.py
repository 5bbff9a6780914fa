"""The car drives the paper's manoeuvre on Magic Formula tyres: settles, speeds up to 60 km/h in
3 s (prescribed front-wheel rotation), drives straight, changes lane (case a: left turn first,
b: right turn first; the calibrated Akima rack profile) and calms down; ~10 s in all.

Writes DIR/history.csv (t, phase, x_m, y_m, yaw_rad, speed_mps, rack_m, steer_fl_deg,
steer_fr_deg, Fz_*, Fy_*, Fx_* [N, per wheel fl fr rl rr], d_*_m, rot_*_rad), DIR/drive.json
(lane-change metrics, wall time, provenance), DIR/path.png, DIR/speed.png, DIR/wheel_loads.png,
and with a scene: DIR/scene.yaml, and DIR/replay.html if the scene asks for meshcat_html.

Example:  python experiments/drive.py --out results/drive_a --case a
"""

import _common  # noqa: F401

import matplotlib.pyplot as plt
import numpy as np

from drake_car.drive import lane_change_metrics, run_drive
from drake_car.manoeuvre import Timeline
from drake_car.outputs import Progress, output_folder, provenance, write_csv, write_json
from drake_car.scene import dump_scene, resolve
from drake_car.scene_run import run_scene
from drake_car.systems.tyre import WHEELS


def main():
    p = _common.parser(__doc__)
    p.add_argument("--case", choices=["a", "b", "straight"], default="a")
    p.add_argument("--time_step_s", type=_common.positive("time_step_s"), default=1e-3)
    p.add_argument("--duration_s", type=_common.positive("duration_s"), default=None,
                   help="stop early (default: the whole timeline, 10 s)")
    _common.add_scene_options(p)
    args = p.parse_args()
    scene = _common.load_scene_option(p, args)
    bar = Progress(f"drive {args.case}", 100)

    def progress(t, end):
        bar.update(int(100 * t / end), f"t = {t:.1f} s")

    if scene is None:
        timeline = Timeline()
        run = run_drive(args.case, time_step_s=args.time_step_s, end_time_s=args.duration_s,
                        progress=progress)
    else:
        if scene.manoeuvre.kind == "settle":
            p.error(f"--scene {args.scene}: a settle scene; use experiments/settle.py")
        if args.duration_s:
            scene.simulator.end_time_s = args.duration_s
        timeline = resolve(scene).timeline
        run = run_scene(scene, progress=progress)
    h = run.history
    metrics = lane_change_metrics(h, timeline)
    with output_folder(args.out) as out:
        write_csv(out / "history.csv", h)
        if scene is not None:
            (out / "scene.yaml").write_text(dump_scene(scene))
        if run.html is not None:  # the scene asked for visualization: meshcat_html
            (out / "replay.html").write_text(run.html)
        write_json(out / "drive.json", {
            "case": args.case if scene is None else scene.manoeuvre.case, "lane_change": metrics, "wall_s": run.wall_s,
            "simulated_s": float(h["t"][-1]),
            "real_time_factor": float(h["t"][-1] / run.wall_s),
            "provenance": provenance()})
        plot(h, out, args.case)
    if metrics:
        print(f"shift over phase III {metrics['shift_m']:.3f} m, heading change "
              f"{metrics['heading_change_deg']:+.2f} deg")
    print(f"{h['t'][-1]:.1f} s simulated in {run.wall_s:.1f} s wall; wrote {args.out}")


def plot(h, out, case):
    fig, ax = plt.subplots(figsize=(9, 3.5))
    ax.plot(h["x_m"], h["y_m"])
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"Path of the car's reference point, case {case}")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "path.png", dpi=110)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(8, 3.5))
    ax.plot(h["t"], 3.6 * h["speed_mps"])
    ax.set_xlabel("t [s]")
    ax.set_ylabel("speed [km/h]")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "speed.png", dpi=110)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(9, 4))
    for w in WHEELS:
        ax.plot(h["t"], h[f"Fz_{w}_N"], label=w)
    phases = np.array(h["phase"])
    for name in ("II", "III", "IV"):
        idx = np.flatnonzero(phases == name)
        if idx.size:
            ax.axvline(h["t"][idx[0]], color="k", lw=0.6, ls=":")
            ax.text(h["t"][idx[0]], ax.get_ylim()[1], f" {name}", va="top")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("wheel load Fz [N]")
    ax.legend(ncol=4)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "wheel_loads.png", dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
