"""What the strut friction costs in time: wall time per simulated second of the settling car,
friction off vs on, at the default step (1 ms). Medians over repeats, ratios within one run.

  python benchmarks/friction_cost.py [--repeats 5] [--sim_s 2] [--out results/bench]
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
from drake_car.systems.strut_friction import StrutFrictionSetup  # noqa: E402

CASES = {
    "friction off (lubricated)": None,
    "friction off, undamped": "undamped",
    "friction on, translation pair": StrutFrictionSetup(
        StrutFrictionParameters(mu_s=0.4, mu_d=0.3), rotation=False),
    "friction on, both pairs": StrutFrictionSetup(StrutFrictionParameters(mu_s=0.4, mu_d=0.3)),
}


def wall_per_simulated_second(friction, sim_s, time_step_s):
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


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--sim_s", type=float, default=2.0)
    p.add_argument("--time_step_s", type=float, default=1e-3)
    p.add_argument("--out", type=Path, default=None)
    args = p.parse_args()
    samples = {name: [] for name in CASES}
    for r in range(args.repeats):
        for name, friction in CASES.items():  # interleaved, so drift hits all cases alike
            samples[name].append(wall_per_simulated_second(friction, args.sim_s,
                                                           args.time_step_s))
        print(f"repeat {r + 1}/{args.repeats} done", file=sys.stderr)
    medians = {name: statistics.median(v) for name, v in samples.items()}
    base = medians["friction off (lubricated)"]
    print(f"settling car, dt = {args.time_step_s:g} s, {args.sim_s:g} s simulated, "
          f"median of {args.repeats}:")
    for name, value in medians.items():
        print(f"  {name:32s} {value:6.3f} s wall per simulated s "
              f"({1e6 * value * args.time_step_s:5.0f} µs/step), ratio to off "
              f"{value / base:.2f}")
    if args.out:
        with output_folder(args.out) as out:
            write_json(out / "friction_cost.json", provenance(
                medians_wall_per_sim_s=medians, samples=samples,
                ratio_to_off={n: v / base for n, v in medians.items()}, **vars(args) | {
                    "out": str(args.out)}))


if __name__ == "__main__":
    main()
