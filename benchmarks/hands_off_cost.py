"""What letting go of the steering costs per step: a hands-off run against the same run held,
after the release, whole Diagram and plant alone (``step_cost``'s measures), for the column in
its reflected form (the default) and, for comparison in the same sitting, the coupler form it
replaced.

The scene: the design study's base (scenes/studies/design.yaml, the paper's lane change with
the dry strut) driven on after the manoeuvre as the study's hands-off runs are; held: the same
scene with the rack held (``!HeldRack``). Each configuration is advanced over the same span
after the release, interleaved, ``--repeats`` times; the report gives medians of wall and CPU
time per step and the ratios hands-off / held (the target: ≤ 1.15). Compare ratios, not
seconds: this machine is shared.

  python benchmarks/hands_off_cost.py [--repeats 5] [--span_s 1.0] [--forms reflected coupler]
"""

import dataclasses
import os
import statistics

from step_cost import plant_alone, whole_diagram

from drake_car.commands import cli
from drake_car.data import resource
from drake_car.scene.load import hands_off_release_s
from drake_car.scene.scene import HeldRack
from drake_car.study.design.runs import hands_off
from drake_car.study.design.spec import load_study


def main():
    p = cli.parser(__doc__, prog="benchmarks/hands_off_cost.py", out=False)
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--span_s", type=float, default=1.0,
                   help="simulated seconds measured, from 0.2 s after the release")
    p.add_argument("--forms", nargs="+", default=["reflected", "coupler"],
                   choices=["reflected", "coupler"])
    args = p.parse_args()
    if not (args.repeats >= 1 and args.span_s > 0):
        p.error("--repeats must be >= 1 and --span_s > 0")
    study = load_study(resource("scenes/studies/design.yaml"), "study")
    off = hands_off(study, study.base)
    held = dataclasses.replace(off, steering=HeldRack())
    t0 = hands_off_release_s(off) + 0.2
    steps = round(args.span_s / off.time_step_s)
    configs = {"held": (held, "reflected")} | {f"hands-off ({form})": (off, form)
                                                for form in args.forms}
    times = {name: {"whole": [], "alone": []} for name in configs}
    load_before = os.getloadavg()
    for _ in range(args.repeats):  # interleaved: drift hits all alike
        for name, (scene, form) in configs.items():
            (wall, cpu), runner = whole_diagram(scene, t0, args.span_s, column_form=form)
            times[name]["whole"].append(1e6 * cpu / steps)
            times[name]["alone"].append(1e6 * plant_alone(scene, runner, args.span_s)[1] / steps)
    load_after = os.getloadavg()
    print(f"design base, {off.time_step_s:g} s steps, {args.span_s:g} s from t = {t0:g} s "
          f"(released at {t0 - 0.2:g} s); CPU µs/step, median of {args.repeats}; load average "
          f"{load_before[0]:.2f} before, {load_after[0]:.2f} after ({os.cpu_count()} cores):")
    median = {name: {k: statistics.median(v) for k, v in t.items()}
              for name, t in times.items()}
    base = median["held"]
    for name, m in median.items():
        print(f"  {name:22s} whole Diagram {m['whole']:5.0f} ({m['whole'] / base['whole']:.2f}"
              f" × held), plant alone {m['alone']:5.0f} ({m['alone'] / base['alone']:.2f} × "
              f"held); whole/alone {m['whole'] / m['alone']:.2f}")


if __name__ == "__main__":
    main()
