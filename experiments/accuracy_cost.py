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
DIR/reference_<scene>.csv (the reference's Δd at its step and at twice it), DIR/scenes/ (the
references' scenes as they ran). Every case is the study's scene with its step, friction scheme,
tyre model and SAP pacer replaced; each starts at its own scene's static equilibrium.

  python experiments/accuracy_cost.py --out results/accuracy   (about 45 minutes)
  python experiments/accuracy_cost.py --out /tmp/quick --scale_time 0.3 --explicit_step_s 0 \
      --steps 5e-3,2e-3,1e-3,5e-5                                     (a quick check)
"""

import dataclasses

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from pydrake.multibody.plant import MultibodyPlantConfig  # noqa: E402

from drake_car import cli  # noqa: E402
from drake_car.data import resource  # noqa: E402
from drake_car.law.tyre.slip import SlipOptions  # noqa: E402
from drake_car.scene.load import dump_scene_file, load_scene  # noqa: E402
from drake_car.scene.scene import LinearTyre, MagicFormula  # noqa: E402
from drake_car.sim.build import check_stability  # noqa: E402
from drake_car.results.files import write_csv, write_json
from drake_car.results.folder import output_folder
from drake_car.results.provenance import provenance
from drake_car.sim.simulate import simulate  # noqa: E402
from drake_car.study.paper.claims import study_columns  # noqa: E402
from drake_car.systems.failure import SimulationFailure  # noqa: E402

PAPER_STUDY = resource("scenes/paper_study.yaml")
TYRES = {
    "mf_combined_relaxed": MagicFormula(),
    "mf_pure_slip": MagicFormula(combined_slip=False),
    "mf_no_relaxation": MagicFormula(slip=SlipOptions(relaxation=False)),
    "linear": LinearTyre(),
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


def case_scene(base, case: Case):
    """The scene of a case: the study's scene with its step, scheme, tyres and pacer."""
    plant = MultibodyPlantConfig(time_step=case.time_step_s,
                                 discrete_contact_approximation="sap")
    friction = base.friction
    if friction is not None:
        friction = dataclasses.replace(friction, scheme=case.scheme)
    return dataclasses.replace(
        base, name=f"{base.name} dt={case.time_step_s:g} {case.scheme} {case.tyre_model}"
                   + ("" if case.sap_pacer else " no-pacer"),
        plant=plant, friction=friction, tyres=TYRES[case.tyre_model],
        simulator=dataclasses.replace(base.simulator, sap_pacer=case.sap_pacer))


def simulate_case(base, case):
    scene = case_scene(base, case)
    try:
        run = simulate(scene)
    except SimulationFailure as e:
        return scene, None, None, f"failed: {e}"
    return scene, study_columns(run.history), run, "ok"


def dd_difference(a, b):
    """max over time and side of |Δd_a - Δd_b|, and the same at the last sample."""
    errors = [np.abs(a[f"dd_{s}_m"] - b[f"dd_{s}_m"]) for s in ("left", "right")]
    return float(max(np.max(e) for e in errors)), float(max(e[-1] for e in errors))


def scaled(scene, scale):
    """The scene with every phase of its timeline shortened by ``scale`` (quick checks)."""
    if scale == 1.0:
        return scene
    t = scene.manoeuvre.timeline
    timeline = dataclasses.replace(
        t, settle_s=t.settle_s * scale, speed_up_s=t.speed_up_s * scale,
        straight_s=t.straight_s * scale, steer_s=t.steer_s * scale, calm_s=t.calm_s * scale)
    return dataclasses.replace(scene, manoeuvre=dataclasses.replace(scene.manoeuvre,
                                                                    timeline=timeline))


def main(argv=None):
    p = cli.parser(__doc__)
    p.add_argument("--steps", default="5e-3,2e-3,1e-3,5e-4,2e-4,1e-4,5e-5",
                   help="time steps to sweep (s), comma separated")
    p.add_argument("--reference_step_s", type=cli.positive("reference_step_s"),
                   default=2.5e-5)
    p.add_argument("--explicit_step_s", type=cli.nonnegative("explicit_step_s"),
                   default=5e-6, help="step of the explicit friction scheme on a_3 (0: skip)")
    p.add_argument("--scale_time", type=cli.positive("scale_time"), default=1.0,
                   help="shorten every phase of the timeline by this factor (quick checks)")
    p.add_argument("--scene", default=str(PAPER_STUDY),
                   help="scenes file with entries a_1 and a_3 (default: %(default)s)")
    p.add_argument("--scene_text", default="", help="YAML laid over both scenes")
    args = p.parse_args(argv)
    try:
        steps = sorted({float(s) for s in args.steps.split(",")}, reverse=True)
    except ValueError:
        p.error(f"--steps: {args.steps!r} is not a list of numbers")
    if len(steps) < 4 or steps[0] / steps[-1] < 100:
        p.error("--steps: give at least 4 steps over at least 2 decades")
    cli.check_out(args)
    bases = {name: scaled(load_scene(args.scene, child=name, scene_text=args.scene_text or None),
                          args.scale_time) for name in SCENES}
    cases = []
    for scene in SCENES:
        cases += [Case(scene, dt) for dt in steps]
        cases += [Case(scene, dt, tyre_model=t) for t in TYRES if t != DEFAULT_TYRE
                  for dt in (1e-3, 2e-4)]
        cases += [Case(scene, dt, sap_pacer=False) for dt in (1e-3, 1e-4)]
    if args.explicit_step_s > 0:
        cases.append(Case("a_3", args.explicit_step_s, scheme="reference"))
        # Refused at once (stability limit) rather than after the references have run.
        check_stability(case_scene(bases["a_3"], cases[-1]))
    from tqdm import tqdm
    bar = tqdm(total=len(cases) + 2 * len(SCENES), desc="accuracy-cost sweep", disable=None)
    with output_folder(args.out) as out:
        references, reference_info, done = {}, {}, {}
        for scene in SCENES:
            for dt in (args.reference_step_s, 2 * args.reference_step_s):
                case = Case(scene, dt)
                ran, columns, run, status = simulate_case(bases[scene], case)
                if columns is None:
                    raise SystemExit(f"reference {scene} at {dt:g} s {status}")
                if run.frozen_sap_steps:
                    raise SystemExit(f"reference {scene} at {dt:g} s has "
                                     f"{run.frozen_sap_steps} frozen SAP steps: not a reference")
                references[(scene, dt)] = columns
                done[case] = (ran, columns, run, status)
                reference_info[f"{scene}@{dt:g}"] = {"wall_s": run.wall_s,
                                                     "frozen_sap_steps": run.frozen_sap_steps}
                (out / "scenes").mkdir(exist_ok=True)
                (out / "scenes" / f"reference_{scene}_{dt:g}.yaml").write_text(
                    dump_scene_file(ran))
                bar.update(1)
        convergence = {scene: dd_difference(references[(scene, args.reference_step_s)],
                                            references[(scene, 2 * args.reference_step_s)])[0]
                       for scene in SCENES}
        rows = {c: [] for c in COLUMNS}
        for case in cases:
            ran, columns, run, status = done.get(case) or simulate_case(bases[case.scene], case)
            reference = references[(case.scene, args.reference_step_s)]
            max_error = final = float("nan")
            wall, rtf, frozen = float("nan"), float("nan"), -1
            if columns is not None:
                max_error, final = dd_difference(columns, reference)
                wall, frozen = run.wall_s, run.frozen_sap_steps
                rtf = float(columns["t"][-1]) / wall
            values = dataclasses.asdict(case) | {
                "friction_scheme": case.scheme, "max_abs_dd_error_m": max_error,
                "final_dd_error_m": final, "wall_s": wall, "real_time_factor": rtf,
                "frozen_sap_steps": frozen, "status": status}
            for key in COLUMNS:
                rows[key].append(values[key])
            bar.update(1)
            bar.set_postfix_str(f"{case.scene} dt={case.time_step_s:g} {case.scheme} "
                                f"{case.tyre_model}: {1e3 * max_error:.3f} mm")
        bar.close()
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
            initial_state="static equilibrium of each run's own scene (simulator.start)"))
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
    cli.run_main(main)
