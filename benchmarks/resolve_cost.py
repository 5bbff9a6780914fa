"""Accuracy on demand, local against global, on the main job (``drake-car-paper``): the job run
without accuracy on demand (``--no_verify``), with its slips resolved locally (``--refine
local``, the default) and with its runs halved whole (``--refine global``, the reference), each
in a process of its own, alternately, ``--repeats`` times; the CPU time of each job (all its
processes: the job's own ``summary.json`` cpu_s, RUSAGE_SELF + RUSAGE_CHILDREN, the Dask
workers included), the medians and their ratios; then every deciding outcome of the two
accurate routes side by side with its error, and whether they agree within their errors
(|local - global| <= error_local + error_global, each the step's plus the solver's; an outcome
without an error is compared by its difference only). ``local_no_solver`` is the local route
without its windows' solver twins (``--no_solver_axis``): what the solver axis costs.

First one unmeasured ``--no_verify`` job (``--no_warm_up``: none): it fills what a checkout's
first job pays for once (numba's on-disk cache of the compiled laws, beside the sources: a fresh
clone compiles them all; the static equilibria and the lane change's calibration, keyed by the
code). Without it the first measured job carries that: a sitting on a fresh clone (2026-11-26)
measured ``--no_verify`` at 60.8 s, 42 s of it outside the runs' loops, against 39 s and 21 s on
a warm checkout, which moved the local route's ratio from 5.6 to 3.3. Each round's ratios are
printed, and their medians beside the medians' ratio.

``--reference DIR`` takes the global route's outcomes (and its CPU time) from a main job run
earlier (its outcomes.csv and summary.json), instead of running it: the global route costs
5-10 times the local one. Say so where you quote the ratio: it is then not of one sitting.

  python benchmarks/resolve_cost.py --out DIR [--repeats 1] [--reference DIR]
"""

import json
import math
import statistics
import subprocess
import sys
import time
from pathlib import Path

from drake_car.commands import cli
from drake_car.study.paper.outcomes import DRIVES, read_outcomes

ROUTES = {"no_verify": ["--no_verify"], "local": ["--refine", "local"],
          "local_no_solver": ["--refine", "local", "--no_solver_axis"],
          "global": ["--refine", "global"]}


def run_job(route, out, extra):
    """One main job in a process of its own; its summary's CPU time (s) and wall time."""
    began = time.perf_counter()
    subprocess.run([sys.executable, "-m", "drake_car.commands.paper", "--out", str(out),
                    "--no_html", *ROUTES[route], *extra], check=True,
                   stdout=subprocess.DEVNULL)
    summary = json.loads((out / "summary.json").read_text())
    return summary["cpu_s"], time.perf_counter() - began


def budget(row):
    """An outcome's whole error: the step's plus the solver's (None without a step error)."""
    if row["error"] is None or math.isnan(row["error"]):
        return None
    solver = row.get("solver_error")
    return row["error"] + (0.0 if solver is None or math.isnan(solver) else solver)


def agreement(local, reference):
    """Rows (subject, outcome, local value, its whole error, global value, its whole error,
    diff, agree) of the deciding outcomes both routes have (``budget``)."""
    rows = []
    for key in sorted(set(local) & set(reference)):
        if key[1] not in DRIVES:
            continue
        a, b = local[key], reference[key]
        diff = abs(a["value"] - b["value"])
        errors = [budget(a), budget(b)]
        agree = (diff <= sum(errors) * (1 + 1e-9) if None not in errors else None)
        rows.append((*key, a["value"], errors[0], b["value"], errors[1], diff, agree,
                     a["unit"]))
    return rows


def main():
    p = cli.parser(__doc__, prog="benchmarks/resolve_cost.py", out=True,
                   scene_text="YAML laid over every run's scene of every job")
    p.add_argument("--repeats", type=int, default=1)
    p.add_argument("--no_warm_up", action="store_true",
                   help="measure from the first job (the caches as they are)")
    p.add_argument("--reference", type=Path, default=None,
                   help="a global-route main job's folder (outcomes.csv, summary.json) "
                        "instead of running the global route")
    args = p.parse_args()
    if args.repeats < 1:
        p.error("--repeats must be >= 1")
    extra = ["--scene_text", args.scene_text] if args.scene_text else []
    routes = ["no_verify", "local", "local_no_solver"] + ([] if args.reference else ["global"])
    args.out.mkdir(parents=True, exist_ok=True)
    if not args.no_warm_up:
        run_job("no_verify", args.out / "warm_up", extra)
    cpu = {r: [] for r in routes}
    for k in range(args.repeats):
        for route in routes:
            out = args.out / f"{route}_{k}"
            seconds, wall = run_job(route, out, extra)
            cpu[route].append(seconds)
            print(f"{route:9s} repeat {k}: {seconds:7.1f} s CPU, {wall:7.1f} s wall",
                  flush=True)
        print(f"round {k}: " + ", ".join(f"{r} {cpu[r][-1] / cpu['no_verify'][-1]:.2f} x"
                                         for r in routes[1:]), flush=True)
    median = {r: statistics.median(v) for r, v in cpu.items()}
    ratios = {r: statistics.median(a / b for a, b in zip(cpu[r], cpu["no_verify"]))
              for r in routes[1:]}
    reference = args.reference or args.out / "global_0"
    if args.reference:
        median["global"] = json.loads((reference / "summary.json").read_text())["cpu_s"]
        print(f"global (reference {reference}): {median['global']:.1f} s CPU, not of this "
              "sitting")
    base = median["no_verify"]
    for route, value in median.items():
        per_round = (f" (the rounds' ratios' median {ratios[route]:.2f} x)"
                     if route in ratios else "")
        print(f"{route:9s} median {value:7.1f} s CPU = {value / base:.2f} x --no_verify"
              + per_round)
    rows = agreement(read_outcomes(args.out / "local_0" / "outcomes.csv"),
                     read_outcomes(reference / "outcomes.csv"))
    print("\nrun | outcome | local ± error | global ± error | |diff| | agree")
    for subject, outcome, lv, le, gv, ge, diff, agree, unit in rows:
        scale = 1e3 if unit == "m" else 100.0 if unit == "fraction" else 1.0

        def shown(value, error):
            return (f"{scale * value:.4f}" + ("" if error is None or math.isnan(error)
                                               else f" ± {scale * error:.4f}"))
        print(f"{subject} | {outcome} | {shown(lv, le)} | {shown(gv, ge)} | "
              f"{scale * diff:.4f} | {'-' if agree is None else 'yes' if agree else 'NO'}")
    (args.out / "resolve_cost.json").write_text(json.dumps(
        {"cpu_s": cpu, "median_cpu_s": median, "median_round_ratio": ratios,
         "warm_up": not args.no_warm_up, "agreement": rows}, indent=1, default=str))


if __name__ == "__main__":
    main()
