"""What accuracy costs in time: the paper's hardest run (a_3: lane change with μs = 0.4) and a
frictionless run (a_1), swept over the time step, the friction scheme and the tyre fidelity,
against a converged reference.

Reference: the fast scheme at --reference_step_s (25 µs), shown converged by repeating it at
twice its step (the change is written to accuracy_cost.json and printed; it must be well below
the errors it measures). Every run counts SAP's frozen steps (steps in which the solver
returned its initial guess, drake_car/systems/sap_pacer.py); a reference with frozen steps is
refused. The explicit "reference" friction scheme is run once on a_3 at --explicit_step_s
(5 µs, about 20 minutes of the sweep; at 10 µs it is not yet converged on the car: halving that
step moved Δd by 0.70 mm): its distance to the fast reference checks that the fast scheme
converges to the law on the car. Rows with sap_pacer False show what the frozen steps cost.

Writes DIR/accuracy_cost.csv (scene, time_step_s, friction_scheme, tyre_model, sap_pacer,
max_abs_dd_error_m, final_dd_error_m, wall_s, real_time_factor, frozen_sap_steps, status),
DIR/accuracy_cost.png (log-log: error vs wall time), DIR/accuracy_cost.json and
DIR/reference_<scene>.csv (the reference's Δd at its step and at twice it).

  python experiments/accuracy_cost.py --out results/accuracy   (about 45 minutes)
  python experiments/accuracy_cost.py --out /tmp/quick --scale_time 0.3 --explicit_step_s 0 \
      --steps 5e-3,2e-3,1e-3,5e-5                                     (a quick check)
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
from drake_car.study import PAPER_STUDY_SCENES, RunConfig, run_one, static_equilibrium

TYRES = {
    "mf_combined_relaxed": TyreSetup(),
    "mf_pure_slip": TyreSetup(combined=False),
    "mf_no_relaxation": TyreSetup(slip=SlipOptions(relaxation=False)),
    "linear": TyreSetup(linear=True),
}
DEFAULT_TYRE = "mf_combined_relaxed"
SCENES = ("a_3", "a_1")
COLUMNS = ("scene", "time_step_s", "friction_scheme", "tyre_model", "sap_pacer",
           "max_abs_dd_error_m", "final_dd_error_m", "wall_s", "real_time_factor",
           "frozen_sap_steps", "status")


@dataclasses.dataclass(frozen=True)
class Case:
    scene: str
    time_step_s: float
    scheme: str = "fast"
    tyre_model: str = DEFAULT_TYRE
    sap_pacer: bool = True


def simulate(case: Case, scale, start, scene_file, scene_text):
    config = RunConfig(case.scene[0], int(case.scene[2]), time_step_s=case.time_step_s,
                       scheme=case.scheme, record_period_s=0.01, tyres=TYRES[case.tyre_model],
                       sap_pacer=case.sap_pacer, scene_file=scene_file, scene_text=scene_text)
    if scale != 1.0:
        t = config.timeline
        config.timeline = dataclasses.replace(
            t, settle_s=t.settle_s * scale, speed_up_s=t.speed_up_s * scale,
            straight_s=t.straight_s * scale, lane_change_s=t.lane_change_s * scale,
            calm_s=t.calm_s * scale)
    began = time.perf_counter()
    try:
        columns, info, _ = run_one(config, start)
        return columns, info, time.perf_counter() - began, "ok"
    except DivergenceError as e:
        return None, None, time.perf_counter() - began, f"diverged: {e}"
    except RuntimeError as e:  # a system refused the state (e.g. a rod out of its guide)
        return None, None, time.perf_counter() - began, f"failed: {e}"


def dd_difference(a, b):
    """max over time and side of |Δd_a - Δd_b|, and the same at the last sample."""
    errors = [np.abs(a[f"dd_{s}_m"] - b[f"dd_{s}_m"]) for s in ("left", "right")]
    return float(max(np.max(e) for e in errors)), float(max(e[-1] for e in errors))


def main():
    p = _common.parser(__doc__)
    p.add_argument("--steps", default="5e-3,2e-3,1e-3,5e-4,2e-4,1e-4,5e-5",
                   help="time steps to sweep (s), comma separated")
    p.add_argument("--reference_step_s", type=_common.positive("reference_step_s"),
                   default=2.5e-5)
    p.add_argument("--explicit_step_s", type=_common.nonnegative("explicit_step_s"),
                   default=5e-6, help="step of the explicit friction scheme on a_3 (0: skip)")
    p.add_argument("--scale_time", type=_common.positive("scale_time"), default=1.0,
                   help="shorten the timeline (quick checks)")
    p.add_argument("--scene", default=str(PAPER_STUDY_SCENES),
                   help="scenes file with entries a_1 and a_3 (default: %(default)s)")
    p.add_argument("--scene_text", default="", help="YAML laid over both scenes")
    args = p.parse_args()
    try:
        for name in SCENES:
            RunConfig(name[0], int(name[2]), scene_file=args.scene,
                      scene_text=args.scene_text).car()
    except ValueError as e:  # SceneError names the file, the entry and the key
        p.error(str(e))
    try:
        steps = sorted({float(s) for s in args.steps.split(",")}, reverse=True)
    except ValueError:
        p.error(f"--steps: {args.steps!r} is not a list of numbers")
    if len(steps) < 4 or steps[0] / steps[-1] < 100:
        p.error("--steps: give at least 4 steps over at least 2 decades")
    if args.explicit_step_s > 2e-5:
        p.error("--explicit_step_s: the explicit scheme is unstable on the car above 2e-5 s")
    cases = []
    for scene in SCENES:
        cases += [Case(scene, dt) for dt in steps]
        cases += [Case(scene, dt, tyre_model=t) for t in TYRES if t != DEFAULT_TYRE
                  for dt in (1e-3, 2e-4)]
        cases += [Case(scene, dt, sap_pacer=False) for dt in (1e-3, 1e-4)]
    if args.explicit_step_s > 0:
        cases.append(Case("a_3", args.explicit_step_s, scheme="reference"))
    progress = Progress("accuracy-cost sweep", len(cases) + 2 * len(SCENES))
    # One initial state for every run, whatever its step: the lubricated car's static
    # equilibrium (a_1 and a_3 share the car; they differ in friction and strut damping).
    start = static_equilibrium(RunConfig("a", 1, scene_file=args.scene,
                                         scene_text=args.scene_text).car()[0])
    references, reference_info, reference_runs = {}, {}, {}
    for scene in SCENES:
        for dt in (args.reference_step_s, 2 * args.reference_step_s):
            columns, info, wall, status = simulate(Case(scene, dt), args.scale_time,
                                                   start, args.scene, args.scene_text)
            if columns is None:
                raise SystemExit(f"reference {scene} at {dt:g} s {status}")
            if info["frozen_sap_steps"]:
                raise SystemExit(f"reference {scene} at {dt:g} s has {info['frozen_sap_steps']}"
                                 f" frozen SAP steps (from t = "
                                 f"{info['first_frozen_sap_step_s']:.3f} s): not a reference")
            references[(scene, dt)] = columns
            reference_runs[Case(scene, dt)] = (columns, info, wall, status)
            reference_info[f"{scene}@{dt:g}"] = {"wall_s": wall,
                                                 "frozen_sap_steps": info["frozen_sap_steps"]}
            progress.update(len(references), f"reference {scene} dt = {dt:g} s: {wall:.0f} s")
    convergence = {scene: dd_difference(references[(scene, args.reference_step_s)],
                                        references[(scene, 2 * args.reference_step_s)])[0]
                   for scene in SCENES}
    rows = {c: [] for c in COLUMNS}
    for i, case in enumerate(cases):
        if case in reference_runs:  # the reference's own runs: not repeated
            columns, info, wall, status = reference_runs[case]
        else:
            columns, info, wall, status = simulate(case, args.scale_time, start, args.scene,
                                                   args.scene_text)
        reference = references[(case.scene, args.reference_step_s)]
        max_error = final = simulated = float("nan")
        frozen = -1
        if columns is not None:
            max_error, final = dd_difference(columns, reference)
            simulated = float(columns["t"][-1])
            frozen = info["frozen_sap_steps"]
        values = dataclasses.asdict(case) | {
            "friction_scheme": case.scheme, "max_abs_dd_error_m": max_error,
            "final_dd_error_m": final, "wall_s": wall, "real_time_factor": simulated / wall,
            "frozen_sap_steps": frozen, "status": status}
        for key in COLUMNS:
            rows[key].append(values[key])
        progress.update(i + 1 + 2 * len(SCENES),
                        f"{case.scene} dt = {case.time_step_s:g} s {case.scheme} "
                        f"{case.tyre_model}{'' if case.sap_pacer else ' no pacer'}: "
                        f"error {1e3 * max_error:.3f} mm, {wall:.1f} s, {frozen} frozen")
    with output_folder(args.out) as out:
        write_csv(out / "accuracy_cost.csv", rows)
        for scene in SCENES:  # the references themselves, to look at where errors arise
            fine = references[(scene, args.reference_step_s)]
            coarse = references[(scene, 2 * args.reference_step_s)]
            write_csv(out / f"reference_{scene}.csv", {
                "t": fine["t"], "dd_left_m": fine["dd_left_m"], "dd_right_m": fine["dd_right_m"],
                "dd_left_2dt_m": coarse["dd_left_m"], "dd_right_2dt_m": coarse["dd_right_m"]})
        write_json(out / "accuracy_cost.json", provenance(
            reference_time_step_s=args.reference_step_s,
            reference_change_on_doubling_m=convergence, references=reference_info,
            scale_time=args.scale_time,
            initial_state=f"static equilibrium: lubricated car settled {start.duration_s:g} s "
                          f"at {start.time_step_s:g} s (max |v| over its last 0.5 s "
                          f"{start.max_abs_velocity:.2g})"))
        plot(rows, out / "accuracy_cost.png", args.reference_step_s)
    print("reference: doubling its step changes Δd by at most "
          + ", ".join(f"{k} {1e3 * v:.4f} mm" for k, v in convergence.items())
          + f"; wrote {args.out}")


def plot(rows, path, reference_step_s):
    fig, ax = plt.subplots(figsize=(8, 5.5))
    scene = np.array(rows["scene"])
    tyre = np.array(rows["tyre_model"])
    scheme = np.array(rows["friction_scheme"])
    pacer = np.array(rows["sap_pacer"], dtype=bool)
    err = np.array(rows["max_abs_dd_error_m"])
    wall = np.array(rows["wall_s"])
    steps = np.array(rows["time_step_s"])
    styles = {"mf_combined_relaxed": "-", "mf_pure_slip": ":", "mf_no_relaxation": "--",
              "linear": "-."}
    for s, marker in (("a_3", "o"), ("a_1", "s")):
        groups = [(f"{s}, fast, {t}", (scene == s) & (tyre == t) & (scheme == "fast") & pacer,
                   style) for t, style in styles.items()]
        groups.append((f"{s}, fast, no SAP pacer", (scene == s) & ~pacer, "none"))
        groups.append((f"{s}, explicit friction scheme", (scene == s) & (scheme == "reference"),
                       "none"))
        for label, m, style in groups:
            m = m & np.isfinite(err) & (err > 0)
            if not m.any():
                continue
            order = np.argsort(wall[m])
            ax.loglog(wall[m][order], 1e3 * err[m][order], linestyle=style, marker=marker,
                      label=label, mfc="none" if "pacer" in label else None,
                      ms=9 if "explicit" in label else 5)
            for x, y, dt in zip(wall[m], 1e3 * err[m], steps[m]):
                ax.annotate(f"{1e3 * dt:g} ms", (x, y), fontsize=7,
                            textcoords="offset points", xytext=(3, 3))
    ax.axhline(0.1, color="k", lw=0.6, ls=":")
    ax.text(ax.get_xlim()[0], 0.1, " target 0.1 mm", fontsize=7, va="bottom")
    ax.set_xlabel("wall time per run [s]")
    ax.set_ylabel("max |Δd - Δd_ref| [mm]")
    ax.set_title(f"Work-precision: strut displacement error vs wall time "
                 f"(reference: fast scheme at {1e6 * reference_step_s:g} µs)", fontsize=9)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
