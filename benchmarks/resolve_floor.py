"""Why the main job's local route costs what it does: from a locally resolved main job's folder
(``drake-car-paper --out DIR``, the default route) and, for the ratio, the same job without
accuracy on demand (``--no_verify``), where the CPU went and what the least the convergence
rule allows on the same windows would cost. Nothing is run: it reads the jobs' run.json and
summary.json files (the CPU of all processes, RUSAGE_SELF + RUSAGE_CHILDREN).

Per window: its span, the levels it took (the rule, ``sim.convergence``, needs three values
that agree within the rest-position tolerance and shrink as a first-order scheme makes them
shrink), the largest difference between successive levels of any rod's rest position (µm) and
its levels' CPU (the solver twin, run beside the finest level, counted apart). The floor: every
window settled at its third level (h, h/2, h/4: the fewest values the rule can judge), the CPU
its first three levels measured; the job's other costs (its 1 ms runs, the runs without dry
friction halved whole with their twins, the job's own work) as measured, and the windows' solver
twins scaled with the windows' CPU. What the floor leaves above ``--no_verify`` is what no choice
of windows' levels can remove; what the job spends above the floor is what converging the
windows' rest positions to their tolerance costs.

  python benchmarks/resolve_floor.py LOCAL_DIR --no_verify NO_VERIFY_DIR
"""

import json
from pathlib import Path

from drake_car.commands import cli


def load(path):
    return json.loads(Path(path).read_text())


def window_rows(run):
    """Per window of a run's resolution: start, end, span, levels' steps in ms, the largest
    successive difference of a rest position per level pair in µm, the levels' CPU without the
    solver twin, the CPU of its first three levels (the floor) and the twin's CPU."""
    rows = []
    for w in run["resolution"]["windows"]:
        levels = w["levels"]
        diffs = []
        for a, b in zip(levels, levels[1:]):
            diffs.append(1e6 * max(abs(a["positions"][k] - b["positions"][k])
                                   for k in a["positions"]))
        span = w["end_s"] - w["start_s"]
        twin = (w.get("solver_twin") or {}).get("cpu_s", 0.0)  # run at the finest level
        cpu = sum(lv["cpu_s"] for lv in levels) - twin
        floor = sum(lv["cpu_s"] for lv in levels[:3]) - (twin if len(levels) <= 3 else 0.0)
        rows.append({"start": w["start_s"], "end": w["end_s"], "span": span,
                     "levels_ms": [1e3 * lv["step_s"] for lv in levels], "diffs_um": diffs,
                     "cpu": cpu, "floor_cpu": floor, "twin_cpu": twin})
    return rows


def main(argv=None):
    p = cli.parser(__doc__, prog="benchmarks/resolve_floor.py", out=False)
    p.add_argument("local", type=Path, help="a main job's folder, resolved locally")
    p.add_argument("--no_verify", type=Path, required=True,
                   help="the same job's folder without accuracy on demand")
    args = p.parse_args(argv)
    for folder in (args.local, args.no_verify):
        if not (folder / "summary.json").is_file():
            p.error(f"{folder}: no summary.json (not a main job's folder: drake-car-paper --out)")
    summary, base = load(args.local / "summary.json"), load(args.no_verify / "summary.json")
    runs = (summary.get("refinement") or {}).get("runs") or {}
    if not any(info.get("route") == "local" for info in runs.values()):
        p.error(f"{args.local}: no locally resolved run (a job of drake-car-paper's default "
                "route, --refine local)")
    window_cpu = floor_cpu = twin_cpu = 0.0
    print("run  window [s]        span   levels [ms]                  successive differences "
          "[µm]          CPU [s]")
    for name, info in sorted(runs.items()):
        if info["route"] != "local":
            continue
        for r in window_rows(load(args.local / name / "run.json")):
            window_cpu += r["cpu"]
            floor_cpu += r["floor_cpu"]
            twin_cpu += r["twin_cpu"]
            print(f"{name:4} {r['start']:6.3f}-{r['end']:6.3f}  {r['span']:5.2f}  "
                  f"{' '.join(f'{h:g}' for h in r['levels_ms']):28} "
                  f"{' '.join(f'{d:.1f}' for d in r['diffs_um']):34} {r['cpu']:6.1f}")
    job, unverified = summary["cpu_s"], base["cpu_s"]
    rest = job - window_cpu - twin_cpu
    print(f"\nthe job: {job:.1f} s CPU, {job / unverified:.2f} x --no_verify ({unverified:.1f} s)")
    print(f"  windows' levels {window_cpu:.1f} s, their solver twins {twin_cpu:.1f} s, the rest "
          f"(1 ms runs, runs without dry friction halved whole with their twins, the job's own "
          f"work) {rest:.1f} s")
    print(f"  every window at its third level (h, h/2, h/4): {floor_cpu:.1f} s")
    least = rest + floor_cpu + (twin_cpu * floor_cpu / window_cpu if window_cpu else 0.0)
    print(f"the floor: {least:.1f} s = {least / unverified:.2f} x --no_verify with the solver "
          f"twins (scaled with the windows), {(rest + floor_cpu) / unverified:.2f} x without "
          "the windows' (the rest keeps what it measured))")


if __name__ == "__main__":
    main()
