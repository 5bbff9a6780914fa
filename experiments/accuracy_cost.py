"""What accuracy costs in time: the paper's hardest run (a_3: lane change with μs = 0.4) and a
frictionless run (a_1), swept over the time step, the friction scheme and the tyre fidelity,
against a converged reference (the fast scheme at --reference_step_s; accuracy_cost.json shows
how much doubling that step changes Δd, to compare with the errors it is used to measure).
The explicit reference scheme is not swept on the car: it is stable there only below ~1e-5 s
(see tests/test_strut_friction.py and benchmarks/friction_convergence.py for its convergence
on the one-DOF rig).

Writes DIR/accuracy_cost.csv (scene, time_step_s, friction_scheme, tyre_model,
max_abs_dd_error_m, final_dd_error_m, wall_s, real_time_factor, status) and
DIR/accuracy_cost.png (log-log: error vs wall time), DIR/accuracy_cost.json.

  python experiments/accuracy_cost.py --out results/accuracy   (about 20 minutes)
"""

import dataclasses
import time

import _common

import matplotlib.pyplot as plt
import numpy as np

from drake_car.assembly import TyreSetup
from drake_car.law.tyre_slip import SlipOptions
from drake_car.monitor import DivergenceError
from drake_car.outputs import Progress, output_folder, provenance, write_csv, write_json
from drake_car.study import RunConfig, run_one

TYRES = {
    "mf_combined_relaxed": TyreSetup(),
    "mf_pure_slip": TyreSetup(combined=False),
    "mf_no_relaxation": TyreSetup(slip=SlipOptions(relaxation=False)),
}
D_STATIC = {"left": 0.14, "right": 0.14}  # a common offset; errors are differences of Δd


def simulate(scene, dt, scheme, tyre_model, scale):
    config = RunConfig(scene[0], int(scene[2]), time_step_s=dt, scheme=scheme,
                       record_period_s=0.01, tyres=TYRES[tyre_model])
    if scale != 1.0:
        t = config.timeline
        config.timeline = dataclasses.replace(
            t, settle_s=t.settle_s * scale, speed_up_s=t.speed_up_s * scale,
            straight_s=t.straight_s * scale, lane_change_s=t.lane_change_s * scale,
            calm_s=t.calm_s * scale)
    start = time.perf_counter()
    try:
        columns, _, _ = run_one(config, D_STATIC)
        return columns, time.perf_counter() - start, "ok"
    except DivergenceError as e:
        return None, time.perf_counter() - start, f"diverged: {e}"


def main():
    p = _common.parser(__doc__)
    p.add_argument("--steps", default="5e-3,2e-3,1e-3,5e-4,2e-4,5e-5",
                   help="time steps to sweep (s), comma separated")
    p.add_argument("--reference_step_s", type=_common.positive("reference_step_s"),
                   default=2.5e-5)
    p.add_argument("--scale_time", type=_common.positive("scale_time"), default=1.0,
                   help="shorten the timeline (quick checks)")
    args = p.parse_args()
    try:
        steps = sorted({float(s) for s in args.steps.split(",")}, reverse=True)
    except ValueError:
        p.error(f"--steps: {args.steps!r} is not a list of numbers")
    if len(steps) < 4 or steps[0] / steps[-1] < 100:
        p.error("--steps: give at least 4 steps over at least 2 decades")
    cases = []
    for scene in ("a_3", "a_1"):
        for dt in steps:
            cases.append((scene, dt, "fast", "mf_combined_relaxed"))
        for tyre_model in ("mf_pure_slip", "mf_no_relaxation"):
            for dt in (1e-3, 2e-4):
                cases.append((scene, dt, "fast", tyre_model))
    progress = Progress("accuracy-cost sweep", len(cases) + 4)
    references = {}
    for k, scene in enumerate(("a_3", "a_1")):
        for dt in (args.reference_step_s, 2 * args.reference_step_s):
            columns, wall, status = simulate(scene, dt, "fast", "mf_combined_relaxed",
                                             args.scale_time)
            if columns is None:
                raise SystemExit(f"reference {scene} at {dt:g} s {status}")
            references[(scene, dt)] = (columns, wall)
            progress.update(len(references), f"reference {scene} dt = {dt:g} s: {wall:.0f} s")
    convergence = {}
    for scene in ("a_3", "a_1"):
        fine = references[(scene, args.reference_step_s)][0]
        coarse = references[(scene, 2 * args.reference_step_s)][0]
        convergence[scene] = max(float(np.max(np.abs(fine[f"dd_{s}_m"] - coarse[f"dd_{s}_m"])))
                                 for s in ("left", "right"))
    rows = {c: [] for c in ("scene", "time_step_s", "friction_scheme", "tyre_model",
                            "max_abs_dd_error_m", "final_dd_error_m", "wall_s",
                            "real_time_factor", "status")}
    for i, (scene, dt, scheme, tyre_model) in enumerate(cases):
        columns, wall, status = simulate(scene, dt, scheme, tyre_model, args.scale_time)
        reference = references[(scene, args.reference_step_s)][0]
        if columns is None:
            max_error = final = float("nan")
            simulated = float("nan")
        else:
            errors = [np.abs(columns[f"dd_{s}_m"] - reference[f"dd_{s}_m"])
                      for s in ("left", "right")]
            max_error = float(max(np.max(e) for e in errors))
            final = float(max(e[-1] for e in errors))
            simulated = float(columns["t"][-1])
        for key, value in (("scene", scene), ("time_step_s", dt), ("friction_scheme", scheme),
                           ("tyre_model", tyre_model), ("max_abs_dd_error_m", max_error),
                           ("final_dd_error_m", final), ("wall_s", wall),
                           ("real_time_factor", simulated / wall), ("status", status)):
            rows[key].append(value)
        progress.update(i + 5, f"{scene} dt = {dt:g} s {tyre_model}: error "
                        f"{1e3 * max_error:.3f} mm, {wall:.1f} s ({status[:20]})")
    with output_folder(args.out) as out:
        write_csv(out / "accuracy_cost.csv", rows)
        write_json(out / "accuracy_cost.json", provenance(
            reference_time_step_s=args.reference_step_s,
            reference_change_on_halving_m=convergence,
            reference_wall_s={f"{k[0]}@{k[1]:g}": v[1] for k, v in references.items()}))
        plot(rows, out / "accuracy_cost.png")
    print(f"reference converged: halving its step changes Δd by at most "
          f"{ {k: f'{1e3 * v:.4f} mm' for k, v in convergence.items()} }; wrote {args.out}")


def plot(rows, path):
    fig, ax = plt.subplots(figsize=(7, 5))
    scene = np.array(rows["scene"])
    tyre = np.array(rows["tyre_model"])
    err = np.array(rows["max_abs_dd_error_m"])
    wall = np.array(rows["wall_s"])
    steps = np.array(rows["time_step_s"])
    for s, marker in (("a_3", "o"), ("a_1", "s")):
        for t, style in (("mf_combined_relaxed", "-"), ("mf_pure_slip", ":"),
                         ("mf_no_relaxation", "--")):
            m = (scene == s) & (tyre == t) & np.isfinite(err) & (err > 0)
            if m.any():
                order = np.argsort(wall[m])
                ax.loglog(wall[m][order], 1e3 * err[m][order], style, marker=marker,
                          label=f"{s}, {t}")
                for x, y, dt in zip(wall[m], 1e3 * err[m], steps[m]):
                    ax.annotate(f"{1e3 * dt:g} ms", (x, y), fontsize=7,
                                textcoords="offset points", xytext=(3, 3))
    ax.axhline(0.1, color="k", lw=0.6, ls=":")
    ax.set_xlabel("wall time per 10 s run [s]")
    ax.set_ylabel("max |Δd - Δd_ref| [mm]")
    ax.set_title("Work-precision: strut displacement error vs wall time")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
