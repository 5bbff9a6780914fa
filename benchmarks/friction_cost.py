"""What the strut friction costs in time, at the default step (1 ms). Medians over repeats,
cases interleaved within one run so that machine drift hits all alike; the ratios are what to
read, not the absolute times.

Two scenes:
* the settling car (vertical tyres only, no drive): the cheapest run the friction can be added
  to, so the worst ratio;
* the paper's hardest run, a_3 (lane change at 60 km/h, μs = 0.4, Magic Formula tyres), against
  the same run with the friction switched off (scene text ``friction: {mode: "off"}``), and
  against a_1 (the lubricated strut: no friction system at all).

  python benchmarks/friction_cost.py [--repeats 5] [--sim_s 2] [--lane_change_repeats 3]
                                     [--out results/bench]
"""

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from pydrake.systems.analysis import Simulator  # noqa: E402

from drake_car.assembly import build_car_diagram  # noqa: E402
from drake_car.law.frd_friction import StrutFrictionParameters  # noqa: E402
from drake_car.model.parameters import CarParameters  # noqa: E402
from drake_car.outputs import output_folder, provenance, write_json  # noqa: E402
from drake_car.study import RunConfig, run_one  # noqa: E402
from drake_car.systems.strut_friction import StrutFrictionSetup  # noqa: E402

SETTLE_CASES = {
    "friction off (lubricated)": None,
    "friction off, undamped": "undamped",
    "friction on, translation pair": StrutFrictionSetup(
        StrutFrictionParameters(mu_s=0.4, mu_d=0.3), rotation=False),
    "friction on, both pairs": StrutFrictionSetup(StrutFrictionParameters(mu_s=0.4, mu_d=0.3)),
}
# (case, friction set, scene text on top of scenes/paper_study.yaml)
LANE_CHANGE_CASES = {
    "a_3, friction off": ("a", 3, 'friction: {mode: "off"}'),
    "a_3, friction on (fast)": ("a", 3, ""),
    "a_1 (lubricated)": ("a", 1, ""),
}


def settle_wall_per_simulated_second(friction, sim_s, time_step_s):
    params = CarParameters()
    if friction is not None:
        params.front.strut_damping_Nspm = 0.0
    if friction == "undamped":
        friction = None
    built = build_car_diagram(params, friction=friction, time_step_s=time_step_s)
    simulator = Simulator(built.diagram)
    simulator.Initialize()
    start = time.perf_counter()
    simulator.AdvanceTo(sim_s)
    return (time.perf_counter() - start) / sim_s


def lane_change_wall_s(case, number, scene_text, time_step_s):
    config = RunConfig(case, number, time_step_s=time_step_s, scene_text=scene_text)
    _, info, _ = run_one(config)
    return info["wall_s"]


def report(title, samples, base_name, unit, per_step=None):
    medians = {name: statistics.median(v) for name, v in samples.items()}
    base = medians[base_name]
    print(title)
    for name, value in medians.items():
        extra = f" ({1e6 * value * per_step:5.0f} µs/step)" if per_step else ""
        print(f"  {name:32s} {value:7.3f} {unit}{extra}, ratio to '{base_name}' "
              f"{value / base:.2f}")
    return medians, {name: value / base for name, value in medians.items()}


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--repeats", type=int, default=5, help="repeats of the settling car")
    p.add_argument("--sim_s", type=float, default=2.0, help="settling car: simulated s")
    p.add_argument("--lane_change_repeats", type=int, default=3,
                   help="repeats of the 10 s lane-change runs (0: skip them)")
    p.add_argument("--time_step_s", type=float, default=1e-3)
    p.add_argument("--out", type=Path, default=None)
    args = p.parse_args()
    for name in ("repeats", "lane_change_repeats"):
        if getattr(args, name) < (1 if name == "repeats" else 0):
            p.error(f"--{name} must be >= {1 if name == 'repeats' else 0}")
    settle = {name: [] for name in SETTLE_CASES}
    for r in range(args.repeats):
        for name, friction in SETTLE_CASES.items():  # interleaved
            settle[name].append(settle_wall_per_simulated_second(friction, args.sim_s,
                                                                 args.time_step_s))
        print(f"settling car: repeat {r + 1}/{args.repeats} done", file=sys.stderr)
    lane = {name: [] for name in LANE_CHANGE_CASES}
    for r in range(args.lane_change_repeats):
        for name, (case, number, text) in LANE_CHANGE_CASES.items():
            lane[name].append(lane_change_wall_s(case, number, text, args.time_step_s))
        print(f"lane change: repeat {r + 1}/{args.lane_change_repeats} done", file=sys.stderr)
    results = {}
    results["settle"] = report(
        f"settling car, dt = {args.time_step_s:g} s, {args.sim_s:g} s simulated, median of "
        f"{args.repeats}:", settle, "friction off (lubricated)", "s wall per simulated s",
        per_step=args.time_step_s)
    if args.lane_change_repeats:
        results["lane_change"] = report(
            f"lane change (10 s simulated), dt = {args.time_step_s:g} s, median of "
            f"{args.lane_change_repeats}:", lane, "a_3, friction off", "s wall")
    if args.out:
        with output_folder(args.out) as out:
            write_json(out / "friction_cost.json", provenance(
                medians={k: v[0] for k, v in results.items()},
                ratios={k: v[1] for k, v in results.items()},
                samples={"settle": settle, "lane_change": lane},
                **vars(args) | {"out": str(args.out)}))


if __name__ == "__main__":
    main()
