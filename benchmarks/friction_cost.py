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

import dataclasses
import statistics
import sys

from drake_car.commands import cli
from drake_car.data import resource
from drake_car.law.friction.frd import StrutFrictionParameters
from drake_car.scene.load import load_scene
from drake_car.scene.scene import Friction
from drake_car.results.files import write_json
from drake_car.results.folder import output_folder
from drake_car.results.provenance import provenance
from drake_car.sim.simulate import simulate

SETTLE = (resource("scenes/car.yaml"), "settle")
JAMMED = StrutFrictionParameters(mu_s=0.4, mu_d=0.3)
# scene text on top of the settling car
SETTLE_CASES = {
    "friction off (lubricated)": None,
    "friction off, undamped": "car: {front: {strut_damping_Nspm: 0.0}}",
    "friction on, translation pair": Friction(pairs="translation", law=JAMMED),
    "friction on, both pairs": Friction(law=JAMMED),
}
# scene text on top of scenes/paper_study.yaml's entry
LANE_CHANGE_CASES = {
    "a_3, friction off": ("a_3", "friction: null"),
    "a_3, friction on (fast)": ("a_3", ""),
    "a_1 (lubricated)": ("a_1", ""),
}


def settle_wall_per_simulated_second(case, sim_s, time_step_s):
    scene = load_scene(SETTLE[0], child=SETTLE[1], scene_text=(
        f"plant: {{time_step: {time_step_s!r}}}\nmanoeuvre: !Settle {{duration_s: {sim_s!r}}}"
        + (f"\n{case}" if isinstance(case, str) else "")))
    if isinstance(case, Friction):
        scene = dataclasses.replace(scene, friction=case, car=dataclasses.replace(
            scene.car, front=dataclasses.replace(scene.car.front, strut_damping_Nspm=0.0)))
    return simulate(scene).wall_s / sim_s


def lane_change_wall_s(child, scene_text, time_step_s):
    text = f"plant: {{time_step: {time_step_s!r}}}" + (f"\n{scene_text}" if scene_text else "")
    scene = load_scene(resource("scenes/paper_study.yaml"), child=child, scene_text=text)
    return simulate(scene).wall_s


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
    p = cli.parser(__doc__, prog="benchmarks/friction_cost.py", out="optional")
    p.add_argument("--repeats", type=int, default=5, help="repeats of the settling car")
    p.add_argument("--sim_s", type=float, default=2.0, help="settling car: simulated s")
    p.add_argument("--lane_change_repeats", type=int, default=3,
                   help="repeats of the 10 s lane-change runs (0: skip them)")
    p.add_argument("--time_step_s", type=float, default=1e-3)
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
        for name, (child, text) in LANE_CHANGE_CASES.items():
            lane[name].append(lane_change_wall_s(child, text, args.time_step_s))
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
