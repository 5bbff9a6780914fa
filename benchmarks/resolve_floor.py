"""Why the main job's local route costs what it does: from a locally resolved main job's folder
(``drake-car-paper --out DIR``, the default route) and, for the ratio, the same job without
accuracy on demand (``--no_verify``), where the CPU went and what the least the convergence
rule allows on the same windows would cost. Nothing is run: it reads the jobs' run.json and
summary.json files (the CPU of all processes, RUSAGE_SELF + RUSAGE_CHILDREN).

A window is counted once: a case's b run branches from its a run at the lane change and takes
over the windows before it (their records are the same in both runs' run.json), as it takes
over their CPU. Per window: its span, the levels it took (the rule, ``sim.convergence``, needs
three values that agree within the rest-position tolerance and shrink as a first-order scheme
makes them shrink), the largest difference of a rod's rest position between successive levels
(µm, the largest over the rods) and the window's CPU without its solver twins (levels, merged
windows, bookkeeping). The solver twins (the one beside the finest level, and those of the gap
and of the inherited state, run at the coarser levels) are counted apart.

The floor: every window settled at its third level (h, h/2, h/4: the fewest values the rule can
judge), i.e. the window's CPU less what its levels beyond the third cost; the job's other costs
(its 1 ms runs, the runs without dry friction halved whole with their twins, the job's own
work) as measured; the windows' solver twins scaled with the windows' CPU (an estimate: the
twin's gap at 1 ms does not shrink with them). It is the floor for these windows and this rule,
not for any route (shorter windows could go lower). What the floor leaves above ``--no_verify``
is what no choice of these windows' levels removes; what the job spends above it is what
converging the windows' rest positions to their tolerance costs.

  python benchmarks/resolve_floor.py LOCAL_DIR --no_verify NO_VERIFY_DIR
"""

import json
from pathlib import Path

from drake_car.commands import cli
from drake_car.law.errors import InputError


def load(path):
    if not path.is_file():
        raise InputError(f"{path}: missing (not a whole main job's folder: drake-car-paper --out)")
    return json.loads(path.read_text())


def window_row(name, w):
    """A window's line: run, start, end, span, levels in ms, successive differences in µm, its
    CPU without the solver twins, the floor's share of it, the twins' CPU."""
    levels = w["levels"]
    diffs = [1e6 * max(abs(a["positions"][k] - b["positions"][k]) for k in a["positions"])
             for a, b in zip(levels, levels[1:])]
    twin_finest = (w.get("solver_twin") or {}).get("cpu_s", 0.0)  # inside the finest level
    twins = twin_finest + w["merged"].get("solver_cpu_s", 0.0)
    cpu = w["cpu_s"] - twins  # levels, merged windows, bookkeeping
    beyond = sum(lv["cpu_s"] for lv in levels[3:]) - (twin_finest if len(levels) > 3 else 0.0)
    return {"run": name, "start": w["start_s"], "end": w["end_s"],
            "span": w["end_s"] - w["start_s"], "levels_ms": [1e3 * lv["step_s"] for lv in levels],
            "diffs_um": diffs, "cpu": cpu, "floor": cpu - beyond, "twins": twins}


def windows(local, runs):
    """Every window of the locally resolved runs, once (a branch's adopted windows are the
    same records as its prefix's)."""
    seen, rows = set(), []
    for name, info in sorted(runs.items()):
        if info["route"] != "local":
            continue
        for w in load(local / name / "run.json")["resolution"]["windows"]:
            key = json.dumps(w, sort_keys=True)
            if key not in seen:
                seen.add(key)
                rows.append(window_row(name, w))
    return rows


def main(argv=None):
    p = cli.parser(__doc__, prog="benchmarks/resolve_floor.py", out=False)
    p.add_argument("local", type=Path, help="a main job's folder, resolved locally")
    p.add_argument("--no_verify", type=Path, required=True,
                   help="the same job's folder without accuracy on demand")
    args = p.parse_args(argv)
    summary, base = load(args.local / "summary.json"), load(args.no_verify / "summary.json")
    runs = (summary.get("refinement") or {}).get("runs") or {}
    if not any(info.get("route") == "local" for info in runs.values()):
        raise InputError(f"{args.local}: no locally resolved run (a job of drake-car-paper's "
                         "default route, --refine local)")
    if base.get("refinement"):
        raise InputError(f"--no_verify {args.no_verify}: a job with accuracy on demand (give "
                         "one of drake-car-paper --no_verify)")
    commits = {summary["provenance"].get("git_commit"), base["provenance"].get("git_commit")}
    rows = windows(args.local, runs)
    print(f"jobs' commits: {', '.join(sorted(str(c) for c in commits))}"
          + (" (not the same code)" if len(commits) > 1 else ""))
    print("run  window [s]       span  levels [ms]                  successive differences "
          "[µm]      CPU [s]")
    for r in rows:
        print(f"{r['run']:4} {r['start']:5.2f}-{r['end']:5.2f}  {r['span']:5.2f}  "
              f"{' '.join(f'{h:g}' for h in r['levels_ms']):28} "
              f"{' '.join(f'{d:.1f}' for d in r['diffs_um']):30} {r['cpu']:6.1f}")
    cpu, floor, twins = (sum(r[k] for r in rows) for k in ("cpu", "floor", "twins"))
    job, unverified = summary["cpu_s"], base["cpu_s"]
    rest = job - cpu - twins
    print(f"\nthe job: {job:.1f} s CPU = {job / unverified:.2f} x --no_verify "
          f"({unverified:.1f} s)")
    print(f"  {len(rows)} windows {cpu:.1f} s, their solver twins {twins:.1f} s, the rest (1 ms "
          f"runs, runs without dry friction halved whole with their twins, the job's own work) "
          f"{rest:.1f} s")
    least = rest + floor + (twins * floor / cpu if cpu else 0.0)
    print(f"  every window at its third level: {floor:.1f} s; the floor {least:.1f} s = "
          f"{least / unverified:.2f} x --no_verify"
          + (f" (the windows' twins scaled; without them {(rest + floor) / unverified:.2f} x, "
             "set 1's twins kept)" if twins else ""))


if __name__ == "__main__":
    cli.run_main(main)
