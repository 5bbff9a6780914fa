"""What accuracy on demand costs the design study (``drake-car-design --quick``): the study run
without it (``--no_verify``), with its jam cases resolving their events locally (``--refine
local``, the default) and halved whole (``--refine global``, the reference), each in a process
of its own, alternately, ``--repeats`` times, after one unmeasured ``--no_verify`` run that
fills the disk caches (static equilibria, the rack's calibration) the others then share.

Per job: the CPU time of all its processes (RUSAGE_CHILDREN around it: the command, its Dask
scheduler, nannies and workers; what ``/usr/bin/time`` says) and its wall time; the CPU of its
runs' simulation loops (``table.csv``'s ``run_cpu_s`` over its distinct runs, windows
included; for the global route the halved runs' too, from its sweep folder), which a busy
machine inflates less than the whole job's (Dask's event loops tick for as long as the job's
wall time); then the medians, their ratios to ``--no_verify``, and the jam cases' lasting
splits of the two accurate routes side by side with their errors, and whether they agree
(|local - global| <= error_local + error_global).

  python benchmarks/design_cost.py --out DIR [--repeats 3] [--routes no_verify local global]
      [--full]   (the whole study: about 80 CPU-minutes a route; not --quick)
"""

import csv
import json
import resource
import statistics
import subprocess
import sys
import time

from drake_car.commands import cli

ROUTES = {"no_verify": ["--no_verify"], "local": ["--refine", "local"],
          "global": ["--refine", "global"]}


def run_job(route, out, quick):
    """One design study in a process of its own: (CPU s of all its processes, wall s)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    began = time.perf_counter()
    subprocess.run([sys.executable, "-m", "drake_car.commands.design", "--out", str(out),
                    *(["--quick"] if quick else []), *ROUTES[route]], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, time.perf_counter() - began


def rows_of(out):
    with open(out / "study" / "table.csv", newline="") as f:
        return list(csv.DictReader(f))


def runs_cpu(out):
    """The simulation loops' CPU of every run in the job's sweep folder (each run once)."""
    total = 0.0
    for path in (out / "sweep" / "runs").glob("*/run.json"):
        total += json.loads(path.read_text()).get("cpu_s") or 0.0
    return total


def agreement(local, reference):
    """(name, role, local value, error, how, global value, error, |diff|, agree) of every row
    the global route refined (its own steps) that the local route has."""
    out = []
    mine = {r["name"]: r for r in local}
    for g in reference:
        if g["split_change_rel_error_from"] != "own steps" or g["name"] not in mine:
            continue
        m = mine[g["name"]]
        lv, le = float(m["split_change_rel"]), float(m["split_change_rel_error"])
        gv, ge = float(g["split_change_rel"]), float(g["split_change_rel_error"])
        out.append((g["name"], g["role"], lv, le, m["split_change_rel_error_from"], gv, ge,
                    abs(lv - gv), abs(lv - gv) <= (le + ge) * (1 + 1e-9)))
    return out


def main():
    p = cli.parser(__doc__, prog="benchmarks/design_cost.py", out=True)
    p.add_argument("--repeats", type=int, default=1)
    p.add_argument("--routes", nargs="+", choices=list(ROUTES), default=list(ROUTES))
    p.add_argument("--full", action="store_true", help="the whole study, not --quick")
    p.add_argument("--no_warm_up", action="store_true",
                   help="measure from the first job (the caches as they are)")
    args = p.parse_args()
    if args.repeats < 1:
        p.error("--repeats must be >= 1")
    args.out.mkdir(parents=True, exist_ok=True)
    quick = not args.full
    if not args.no_warm_up:
        run_job("no_verify", args.out / "warm_up", quick)
    cpu = {r: [] for r in args.routes}
    loops = {r: [] for r in args.routes}
    for k in range(args.repeats):
        for route in args.routes:
            out = args.out / f"{route}_{k}"
            seconds, wall = run_job(route, out, quick)
            cpu[route].append(seconds)
            loops[route].append(runs_cpu(out))
            print(f"{route:9s} repeat {k}: {seconds:7.1f} s CPU ({loops[route][-1]:6.1f} s in "
                  f"the runs' loops), {wall:6.1f} s wall", flush=True)
    median = {r: statistics.median(v) for r, v in cpu.items()}
    median_loops = {r: statistics.median(v) for r, v in loops.items()}
    base = median.get("no_verify")
    for route in args.routes:
        ratio = (f" = {median[route] / base:.2f} x --no_verify (runs' loops "
                 f"{median_loops[route] / median_loops['no_verify']:.2f} x)" if base else "")
        print(f"{route:9s} median {median[route]:7.1f} s CPU, {median_loops[route]:6.1f} s in "
              f"the runs' loops{ratio}")
    rows = []
    if "local" in args.routes and "global" in args.routes:
        rows = agreement(rows_of(args.out / "local_0"), rows_of(args.out / "global_0"))
        print("\njam case | lasting split, local ± error [how] | global ± error | |diff| | "
              "agree  (% of the corner load)")
        for name, role, lv, le, how, gv, ge, diff, agree in rows:
            print(f"{name} | {100 * lv:+.3f} ± {100 * le:.3f} [{how}] | {100 * gv:+.3f} ± "
                  f"{100 * ge:.3f} | {100 * diff:.3f} | {'yes' if agree else 'NO'}")
        print(f"{sum(r[-1] for r in rows)} of {len(rows)} agree within their errors")
    (args.out / "design_cost.json").write_text(json.dumps(
        {"cpu_s": cpu, "runs_cpu_s": loops, "median_cpu_s": median,
         "median_runs_cpu_s": median_loops, "quick": quick, "agreement": rows}, indent=1))


if __name__ == "__main__":
    main()
