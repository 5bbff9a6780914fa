"""What accuracy costs, on the outcomes that decide the paper's claims: runs of the study
(default a_3, b_3, a_2, b_2, a_1) with the fast friction scheme at several steps and with the
explicit scheme (the law as stated) at steps where it has converged, on the sweep runner
(``drake_car.sweep.runner.run_scenes``, one worker per core; each scheme's runs kept in
--runs_dir/<scheme>/ and reused by a rerun).

Outcomes per run (their definitions are the study's, ``study.paper.claims``):
  split_pct      the lasting change of the front left-right load split from place a to place b,
                 in % of the run's static front corner load (claim 3's load split)
  dd_{left,right}_{a,b}_mm   Δd at places a and b (``place_values``)
  mirror_mm      claim 4's residual max_t |Δd(a_k, side) - Δd(b_k, other side)| (a_k, b_k both run)
  rotation_deg   the rod's largest |rotation| in the cylinder (claim 5)
  mu1_peak       the largest μ1/μs over both struts (claim 6)
The reference of a run is its explicit scheme at the finest explicit step; it counts as
converged where two explicit steps agree (their difference is in the table as
``explicit_change``). A run without explicit runs is compared with its finest fast step
(marked ``vs_fast``). Cost: the CPU seconds of the run's simulation loop (a run that branches
from a prefix shared with its mirror run carries the prefix's CPU, as a single run would).
Wall times on a shared machine are unreliable and only written beside.

Writes DIR/accuracy_cost.csv (a row per run, scheme, step and outcome: value, reference,
error, cpu_s, wall_s), DIR/outcomes_by_step.csv (the values in one table), DIR/
accuracy_cost_<outcome>.png (work-precision: |error| against CPU seconds per run),
DIR/branches.txt (where the fast steps disagree on the lasting split: which branch the explicit
scheme takes), DIR/accuracy_cost.json (provenance).

  drake-car-accuracy --out results/accuracy_cost
  drake-car-accuracy --out results/accuracy_cost --explicit_runs a_3,b_3
"""

import dataclasses
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from pydrake.multibody.plant import MultibodyPlantConfig  # noqa: E402

from drake_car.commands import cli  # noqa: E402
from drake_car.data import resource  # noqa: E402
from drake_car.results.files import write_csv, write_json  # noqa: E402
from drake_car.results.folder import output_folder  # noqa: E402
from drake_car.results.provenance import provenance  # noqa: E402
from drake_car.scene.load import load_scene  # noqa: E402
from drake_car.law.errors import InputError  # noqa: E402
from drake_car.scene.limits import check_limits  # noqa: E402
from drake_car.sim.lane_change_calibration import adapted  # noqa: E402
from drake_car.sim.simulate import simulate  # noqa: E402
from drake_car.study.paper.claims import place_values, study_columns  # noqa: E402
from drake_car.sweep.runner import run_scenes  # noqa: E402

PAPER_STUDY = resource("scenes/paper_study.yaml")
RUNS = ("a_3", "b_3", "a_2", "b_2", "a_1")
FAST_STEPS = (2e-3, 1e-3, 5e-4, 2.5e-4, 1e-4)
EXPLICIT_STEPS = (5e-6, 2.5e-6)
OUTCOMES = {  # name: (unit, label)
    "split_pct": ("%", "lasting front load split change [% corner load]"),
    "dd_left_a_mm": ("mm", "Δd left at place a"), "dd_right_a_mm": ("mm", "Δd right at place a"),
    "dd_left_b_mm": ("mm", "Δd left at place b"), "dd_right_b_mm": ("mm", "Δd right at place b"),
    "mirror_mm": ("mm", "claim 4: mirror residual a_k vs b_k"),
    "rotation_deg": ("deg", "rod's largest rotation"),
    "mu1_peak": ("1", "μ1/μs peak"),
}
COLUMNS = ("run", "scheme", "time_step_s", "outcome", "unit", "value", "reference",
           "reference_kind", "error", "explicit_change", "cpu_s", "wall_s")


def case_scene(base, scheme, dt):
    """The study's scene ``base`` with its step and friction scheme replaced."""
    friction = base.friction
    if friction is not None:
        friction = dataclasses.replace(friction, scheme=scheme)
    return dataclasses.replace(
        base, name=f"{base.name} {scheme} dt={dt:g}", friction=friction,
        plant=MultibodyPlantConfig(time_step=dt, discrete_contact_approximation="sap"))


def outcomes(run):
    """The outcomes (``OUTCOMES`` but the mirror residual) of one run, and its study columns."""
    h = study_columns(run.history)
    timeline = run.scene.manoeuvre.timeline
    values = {}
    for side in ("left", "right"):
        a, b = place_values(h, timeline, f"dd_{side}_m")
        values[f"dd_{side}_a_mm"], values[f"dd_{side}_b_mm"] = 1e3 * a, 1e3 * b
    fl, fr = place_values(h, timeline, "Fz_fl_N"), place_values(h, timeline, "Fz_fr_N")
    corner = 0.5 * (float(h["Fz_fl_N"][0]) + float(h["Fz_fr_N"][0]))
    values["split_pct"] = 100 * ((fl[1] - fr[1]) - (fl[0] - fr[0])) / corner
    values["rotation_deg"] = math.degrees(max(float(np.max(np.abs(h[f"rot_{s}_rad"])))
                                              for s in ("left", "right")))
    mu_s = run.scene.friction.law.mu_s if run.scene.friction is not None else 0.0
    values["mu1_peak"] = (max(float(np.max(h[f"mu1_{s}"])) for s in ("left", "right")) / mu_s
                          if mu_s > 0 else math.nan)
    return values, h


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


def mirror_residual_mm(ha, hb):
    """Claim 4's residual between a_k and b_k (mm), on their common samples."""
    n = min(len(ha["t"]), len(hb["t"]))
    return 1e3 * max(float(np.max(np.abs(ha[f"dd_{s}_m"][:n] - hb[f"dd_{o}_m"][:n])))
                     for s, o in (("left", "right"), ("right", "left")))


def steps_of(p, text, name):
    try:
        steps = sorted({float(s) for s in text.split(",") if s.strip()}, reverse=True)
    except ValueError:
        p.error(f"--{name}: {text!r} is not a list of numbers")
    if not steps or not all(0 < s < 1 for s in steps):
        p.error(f"--{name}: {text!r} must be steps in (0, 1) s")
    return steps


def main(argv=None):
    p = cli.parser(__doc__, name="accuracy", scene=True, scene_default=str(PAPER_STUDY),
                   scene_help="the study's scenes file", cluster=True,
                   scene_text="YAML laid over every run's scene")
    p.add_argument("--runs", default=",".join(RUNS), help="runs of the study's scenes file")
    p.add_argument("--fast_steps", default=",".join(f"{s:g}" for s in FAST_STEPS))
    p.add_argument("--explicit_steps", default=",".join(f"{s:g}" for s in EXPLICIT_STEPS),
                   help="steps of the explicit scheme (s); two, to show it converged")
    p.add_argument("--explicit_runs", default=",".join(RUNS),
                   help="the runs the explicit scheme runs for (it costs ~1e3 times the fast)")
    p.add_argument("--scale_time", type=cli.positive("scale_time"), default=1.0,
                   help="shorten every phase of the timeline by this factor (quick checks)")
    p.add_argument("--runs_dir", default="results/accuracy_cost_runs",
                   help="the sweeps' folders (<runs_dir>/fast, <runs_dir>/reference), kept "
                        "and reused by a rerun, outside --out: --out is written whole, the "
                        "runs are added to (default: %(default)s)")
    p.add_argument("--schemes", default="fast,reference", choices=("fast,reference", "fast",
                                                                   "reference"),
                   metavar="{fast,reference | fast | reference}",
                   help="run only one scheme's sweep (no analysis): to start the long one")
    args = p.parse_args(argv)
    cli.check_out(args, kept=("runs_dir",))
    runs = [r for r in args.runs.split(",") if r]
    explicit_runs = [r for r in args.explicit_runs.split(",") if r]
    if not runs or not set(explicit_runs) <= set(runs):
        p.error(f"--explicit_runs {explicit_runs} must be among --runs {runs}")
    fast = steps_of(p, args.fast_steps, "fast_steps")
    explicit = steps_of(p, args.explicit_steps, "explicit_steps")
    # each run as it runs on its car (its lane change's rack found), then shortened
    bases = {r: scaled(adapted(load_scene(args.scene, child=r, scene_text=args.scene_text
                                          or None), run=simulate)[0], args.scale_time)
             for r in runs}
    cases = {}
    for r in runs:
        for dt in fast:
            cases[(r, "fast", dt)] = case_scene(bases[r], "fast", dt)
        for dt in explicit if r in explicit_runs and bases[r].friction is not None else ():
            cases[(r, "reference", dt)] = case_scene(bases[r], "reference", dt)
    for (run, scheme, dt), scene in cases.items():  # each case's step, before anything runs
        try:
            check_limits(scene)
        except InputError as e:
            option = "--explicit_steps" if scheme == "reference" else "--fast_steps"
            raise InputError(f"{option}: {dt:g} s for {run}: {e}") from None
    runs_dir = Path(args.runs_dir)
    results = {}
    with cli.cluster_client(args, len(cases)) as client:
        for scheme in ("reference", "fast"):  # the long runs first; each its own sweep
            if scheme not in args.schemes.split(","):
                continue
            chosen = {scene.name: scene for key, scene in cases.items() if key[1] == scheme}
            if chosen:
                results.update(run_scenes(chosen, out_dir=runs_dir / scheme, client=client,
                                          progress=not args.quiet))
    if args.schemes != "fast,reference":
        print(f"ran {len(results)} runs into {runs_dir}; the analysis needs both schemes")
        return
    rows, table = analyse({key: results[scene.name] for key, scene in cases.items()}, runs)
    with output_folder(args.out) as out:
        write_csv(out / "accuracy_cost.csv", rows)
        write_csv(out / "outcomes_by_step.csv", table)
        (out / "branches.txt").write_text(branches(rows))
        for outcome in OUTCOMES:
            plot(rows, outcome, out / f"accuracy_cost_{outcome}.png")
        write_json(out / "accuracy_cost.json", provenance(
            runs=runs, fast_steps_s=fast, explicit_steps_s=explicit,
            explicit_runs=explicit_runs, runs_dir=str(runs_dir),
            cost="CPU seconds of each run's simulation loop (time.process_time); wall beside, "
                 "unreliable on a shared machine"))
    print(branches(rows))
    print(f"wrote {args.out}")


def analyse(results, runs):
    """Rows of ``COLUMNS`` and the outcomes-by-step table from name -> Run."""
    values, columns = {}, {}
    for key, run in results.items():
        values[key], columns[key] = outcomes(run)
    for (r, scheme, dt) in list(values):
        mate = ("b" if r[0] == "a" else "a") + r[1:]
        if (mate, scheme, dt) in columns:
            values[(r, scheme, dt)]["mirror_mm"] = mirror_residual_mm(
                columns[(r, scheme, dt)], columns[(mate, scheme, dt)])
    rows = {c: [] for c in COLUMNS}
    table = {c: [] for c in ("run", "scheme", "time_step_s", "cpu_s", *OUTCOMES)}
    for r in runs:
        keys = sorted((k for k in values if k[0] == r), key=lambda k: (k[1], -k[2]))
        explicit = [k for k in keys if k[1] == "reference"]
        fast = [k for k in keys if k[1] == "fast"]
        ref_key, kind = (explicit[-1], "explicit") if explicit else (fast[-1], "vs_fast")
        for k in keys:
            table["run"].append(r)
            table["scheme"].append(k[1])
            table["time_step_s"].append(k[2])
            table["cpu_s"].append(results[k].cpu_s)
            for outcome, (unit, _) in OUTCOMES.items():
                value = values[k].get(outcome, math.nan)
                table[outcome].append(value)
                reference = values[ref_key].get(outcome, math.nan)
                change = (abs(values[explicit[-1]].get(outcome, math.nan)
                              - values[explicit[-2]].get(outcome, math.nan))
                          if len(explicit) >= 2 else math.nan)
                row = {"run": r, "scheme": k[1], "time_step_s": k[2], "outcome": outcome,
                       "unit": unit, "value": value, "reference": reference,
                       "reference_kind": kind, "error": value - reference,
                       "explicit_change": change, "cpu_s": results[k].cpu_s,
                       "wall_s": results[k].wall_s}
                for c in COLUMNS:
                    rows[c].append(row[c])
    return rows, table


def branches(rows, outcome="split_pct", tolerance_pct=0.5):
    """Where the fast scheme's steps disagree on the lasting split by more than
    ``tolerance_pct`` (the two branches are ~1.7 points apart): the values, and the explicit
    scheme's."""
    lines = []
    runs = list(dict.fromkeys(rows["run"]))
    for r in runs:
        sel = [i for i, (rr, o) in enumerate(zip(rows["run"], rows["outcome"]))
               if rr == r and o == outcome]
        fast = {rows["time_step_s"][i]: rows["value"][i] for i in sel
                if rows["scheme"][i] == "fast"}
        exp = {rows["time_step_s"][i]: rows["value"][i] for i in sel
               if rows["scheme"][i] == "reference"}
        spread = max(fast.values()) - min(fast.values()) if fast else 0.0
        text = ", ".join(f"{1e3 * dt:g} ms {v:+.2f}" for dt, v in sorted(fast.items(),
                                                                         reverse=True))
        law = (", ".join(f"{1e6 * dt:g} µs {v:+.2f}" for dt, v in sorted(exp.items(),
                                                                      reverse=True))
               or "not run")
        verdict = "steps disagree" if spread > tolerance_pct else "steps agree"
        lines.append(f"{r}: lasting split [%]: fast {text} ({verdict}); explicit {law}")
    return "\n".join(lines) + "\n"


def plot(rows, outcome, path):
    fig, ax = plt.subplots(figsize=(7, 4.5))
    unit, label = OUTCOMES[outcome]
    runs = list(dict.fromkeys(rows["run"]))
    for r in runs:
        sel = [i for i in range(len(rows["run"])) if rows["run"][i] == r
               and rows["outcome"][i] == outcome and rows["scheme"][i] == "fast"]
        if not sel:
            continue
        kind = rows["reference_kind"][sel[0]]
        if kind != "explicit":  # the reference itself (error 0) is not a point
            sel = [i for i in sel if rows["value"][i] != rows["reference"][i]]
        cpu = np.array([rows["cpu_s"][i] for i in sel])
        err = np.abs(np.array([rows["error"][i] for i in sel]))
        dts = [rows["time_step_s"][i] for i in sel]
        if not sel or not np.any(np.isfinite(err)):
            continue
        floor = max(float(np.nanmin(err[err > 0])) / 10 if np.any(err > 0) else 1e-6, 1e-9)
        line, = ax.loglog(cpu, np.maximum(err, floor), "o-",
                          label=f"{r} fast (vs {'explicit' if kind == 'explicit' else 'finest fast step'})",
                          mfc="none" if kind != "explicit" else None)
        for x, y, dt in zip(cpu, np.maximum(err, floor), dts):
            ax.annotate(f"{1e3 * dt:g}", (x, y), fontsize=7, textcoords="offset points",
                        xytext=(3, 3))
        change = [rows["explicit_change"][i] for i in sel][0]
        exp = [i for i in range(len(rows["run"])) if rows["run"][i] == r
               and rows["outcome"][i] == outcome and rows["scheme"][i] == "reference"]
        if exp and np.isfinite(change):
            ax.loglog([rows["cpu_s"][i] for i in exp][:1], [max(change, floor)], "*", ms=11,
                      color=line.get_color(), label=f"{r} explicit: change on halving its step")
    ax.set_xlabel("CPU seconds per run")
    ax.set_ylabel(f"|error| [{unit}]")
    ax.set_title(f"Work-precision: {label} (labels: step in ms)", fontsize=9)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def console():
    """The console script ``drake-car-accuracy``."""
    cli.run_main(main)


if __name__ == "__main__":
    console()
