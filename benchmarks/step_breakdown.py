"""Where a step's time beyond the plant goes, measured so that a shared machine's load cancels:
every variant of a study run is built once, brought to ``--t0_s``, and then all of them are
advanced *alternately* in chunks of ``--chunk_s`` (100 steps at 1 ms), this process's CPU time
taken per chunk; the report gives each variant's median µs/step, its ratio to the plant alone
and the median of its paired differences to the study run (chunks taken side by side).

Variants (scene keys only; the physics is the same in each):

- the study run as it runs (loggers every ``logging.record_period_s``, the divergence monitor
  every ``simulator.monitor_period_s``);
- only the tyres' and the friction's diagnostics logged (their state output ports, no Python:
  the car's channels computed by ``model.channels.CarChannels`` left out);
- without the logged channels (``logging: {channels: []}``: no CarChannels, no VectorLogSinks
  but the car's state every step for the monitor's frozen-step count);
- and the monitor checked every chunk only (``simulator.monitor_period_s`` = ``--chunk_s``);
- the plant alone (``step_cost.plant_alone_simulator``: its inputs held by C++ constant
  sources at the study run's values at ``--t0_s``).

What is left between the third and the plant alone is the two Python systems (tyres and
driveshafts, strut friction: one discrete update each per step) and Drake's framework around a
Diagram of ~30 systems whose inputs change every step.

  python benchmarks/step_breakdown.py [--run a_3] [--time_step_s 1e-3] [--rounds 30]
"""

import os
import statistics
import time

from step_cost import plant_alone_simulator

from drake_car.commands import cli
from drake_car.data import resource
from drake_car.scene.load import load_scene
from drake_car.sim.simulate import SceneRunner


def main():
    p = cli.parser(__doc__, prog="benchmarks/step_breakdown.py", out=False)
    p.add_argument("--run", default="a_3", help="an entry of scenes/paper_study.yaml")
    p.add_argument("--time_step_s", type=float, default=1e-3)
    p.add_argument("--t0_s", type=float, default=3.0, help="where the measured chunks start")
    p.add_argument("--chunk_s", type=float, default=0.1, help="simulated seconds per chunk")
    p.add_argument("--rounds", type=int, default=30, help="chunks per variant")
    args = p.parse_args()
    if not (args.time_step_s > 0 and args.chunk_s >= 10 * args.time_step_s
            and args.rounds >= 1 and args.t0_s > 0):
        p.error("--time_step_s > 0, --chunk_s >= 10 steps, --rounds >= 1, --t0_s > 0")
    step = f"plant: {{time_step: {args.time_step_s!r}}}"
    texts = {
        "study run": step,
        "logged: tyres and friction only": step + "\nlogging: {channels: [tyres, friction]}",
        "no logged channels": step + "\nlogging: {channels: []}",
        "no logged channels, monitor per chunk": step + "\nlogging: {channels: []}"
        + f"\nsimulator: {{monitor_period_s: {args.chunk_s!r}}}",
    }
    advance = {}
    for name, text in texts.items():
        runner = SceneRunner(load_scene(resource("scenes/paper_study.yaml"), child=args.run,
                                   scene_text=text))
        runner.start()
        runner.advance_to(args.t0_s)
        advance[name] = runner.advance_to
        if name == "study run":
            alone = plant_alone_simulator(runner.scene, runner)
            advance["plant alone"] = alone.AdvanceTo
    steps = round(args.chunk_s / args.time_step_s)
    load_before = os.getloadavg()
    cpu = {name: [] for name in advance}
    names = list(advance)
    for k in range(args.rounds):
        t = args.t0_s + (k + 1) * args.chunk_s
        for name in names[k % len(names):] + names[:k % len(names)]:  # rotate the order
            began = time.process_time()
            advance[name](t)
            cpu[name].append(1e6 * (time.process_time() - began) / steps)
    load_after = os.getloadavg()
    plant = statistics.median(cpu["plant alone"])
    print(f"{args.run} at {args.time_step_s:g} s, {args.rounds} chunks of {steps} steps per "
          f"variant, alternately; CPU µs/step, medians; load average {load_before[0]:.2f} "
          f"before, {load_after[0]:.2f} after ({os.cpu_count()} cores):")
    for name, values in cpu.items():
        paired = statistics.median(a - b for a, b in zip(values, cpu["study run"]))
        print(f"  {name:40s} {statistics.median(values):6.1f}  x plant "
              f"{statistics.median(values) / plant:4.2f}  paired - study run {paired:+7.1f}")


if __name__ == "__main__":
    main()
