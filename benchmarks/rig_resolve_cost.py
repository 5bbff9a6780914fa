"""Accuracy on demand, local against global, on the friction rig's closed-form cases
(``drake_car.study.rig.routes``, issue 32 item 3): each case (the belt, the oscillator, the
incline at 8° and 14°) run plain (at its own step, no resolution), on the local route (its
slips resolved in windows at halved steps, ``sim.resolve``) and on the global route (the whole
run at h, h/2, ... until every reading has converged by ``sim.convergence.classify``, or the
finest step), alternately (the order rotated each repeat), ``--repeats`` times, in this
process after one unmeasured warm-up run; the CPU time (``time.process_time``: build, run and
reading) medians and the ratios local/global and local/plain; then every reading of the two
accurate routes side by side with its error and whether they agree (|local - global| <=
error_local + error_global; '-' where the local route states no error: no window before the
reading). The tolerances and how a window's position error maps to each reading:
``study.rig.routes``.

  python benchmarks/rig_resolve_cost.py [--repeats 3] [--scheme fast] [--time_step_s 1e-3]
      [--finest_step_s 3.125e-5] [--cases belt oscillator incline_8 incline_14] [--out DIR]
"""

import json
import math
import statistics

import numpy as np

from drake_car.commands import cli
from drake_car.study.rig.routes import (
    CASES, FINEST_STEP_S, compare, global_route, local_route, plain_route)

ROUTES = ("plain", "local", "global")


def main():
    p = cli.parser(__doc__, prog="benchmarks/rig_resolve_cost.py", out="optional",
                   out_help="a folder for rig_resolve_cost.json")
    p.add_argument("--repeats", type=cli.count, default=3)
    p.add_argument("--scheme", choices=("fast", "reference"), default="fast")
    p.add_argument("--time_step_s", type=cli.positive("--time_step_s"), default=1e-3)
    p.add_argument("--finest_step_s", type=cli.positive("--finest_step_s"),
                   default=FINEST_STEP_S)
    p.add_argument("--cases", nargs="+", choices=CASES, default=list(CASES))
    args = p.parse_args()
    repeats = args.repeats
    if args.finest_step_s > args.time_step_s / 2:
        p.error("--finest_step_s must be at most half of --time_step_s")
    do = {"plain": lambda c: plain_route(c, args.scheme, args.time_step_s),
          "local": lambda c: local_route(c, args.scheme, args.time_step_s, args.finest_step_s),
          "global": lambda c: global_route(c, args.scheme, args.time_step_s,
                                           args.finest_step_s)}
    do["plain"](args.cases[0])  # warm-up: the law's compiled kernels, Drake's first build
    report = {}
    for case in args.cases:
        cpu, last = {r: [] for r in ROUTES}, {}
        for k in range(repeats):
            for route in ROUTES[k % 3:] + ROUTES[:k % 3]:
                last[route] = do[route](case)
                cpu[route].append(last[route]["cpu_s"])
        median = {r: statistics.median(v) for r, v in cpu.items()}
        resolution = last["local"]["resolution"]
        print(f"\n{case} ({args.scheme}, {args.time_step_s:g} s): CPU medians of {repeats}: "
              f"plain {median['plain']:.2f} s, local {median['local']:.2f} s, global "
              f"{median['global']:.2f} s; local/global {median['local'] / median['global']:.2f}"
              f", local/plain {median['local'] / median['plain']:.2f}")
        print(f"  local: {resolution['window_count']} windows, {resolution['resolved']} "
              f"resolved, finest step {resolution['finest_step_s']}, window steps "
              f"{resolution['window_steps']}; global: steps {last['global']['steps_s']}")
        rows = compare(last["local"], last["global"])
        print("  reading | # | local ± error | global ± error | |diff| | agree")
        for reading, k, lv, le, gv, ge, diff, agree in rows:
            converged = (last["global"]["converged"][reading][k] if k != "count" else "")
            print(f"  {reading} | {k} | {lv:.9g} ± {le:.3g} | {gv:.9g} ± {ge:.3g}"
                  f"{'' if converged in ('', True) else ' (not converged)'} | {diff:.3g} | "
                  f"{'-' if agree is None else 'yes' if agree else 'NO'}")
        report[case] = {"cpu_s": cpu, "median_cpu_s": median,
                        "local_over_global": median["local"] / median["global"],
                        "local_over_plain": median["local"] / median["plain"],
                        "global_steps_s": last["global"]["steps_s"],
                        "resolution": resolution, "agreement": rows}
    if args.out:
        args.out.mkdir(parents=True, exist_ok=True)
        (args.out / "rig_resolve_cost.json").write_text(json.dumps(
            report, indent=1, default=lambda o: o.tolist() if isinstance(o, np.ndarray)
            else None if isinstance(o, float) and math.isnan(o) else str(o)))


if __name__ == "__main__":
    main()
