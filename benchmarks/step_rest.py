"""Where "the rest" of a step goes (issue 32, item 7): the parts of a study run's step beyond
the plant and the Python systems' own callbacks, each measured by a variant of the same run
that leaves the physics bit for bit as it is (checked: each variant's plant state after the
last chunk is compared with the study run's) or that doubles a part instead of removing it.

Every variant is built once, brought to ``--t0_s``, and then all are advanced alternately in
chunks of ``--chunk_s`` (in a new random order each round), this process's CPU time taken per
chunk; a shared machine's load then hits all alike. Reported per variant: the median CPU
µs/step, and the median and interquartile range of its chunk-by-chunk difference to the study
run's chunk of the same round (a part's cost is minus a removal's difference, or a doubling's
difference).

Variants:
- study run: as ``sim.simulate`` runs it;
- gain writes x2: the strut friction writes its PD gains and effort limits into the plant's
  actuators twice per step (the same values: the physics is unchanged). Drake keeps them as
  plain members of the actuators (``JointActuator::set_controller_gains`` stores them; no
  context, no cache entry is told), so a write can cost only its own call;
- no per-step state log: without the VectorLogSink of the car's state every step (the
  monitor's frozen-step count; a publish event every step);
- no SAP pacer: ``simulator.sap_pacer: false`` (the same physics while SAP iterates anyway;
  the check says whether it did);
- no logged channels: ``logging.channels: []`` (no CarChannels, no loggers at the record
  period);
- monitor per chunk: ``simulator.monitor_period_s`` = the chunk (its checks 10x rarer);
- Python's GC off: ``gc.disable()`` around each chunk (the cyclic collector's share);
- plant alone: ``step_cost.plant_alone_simulator`` (inputs held by C++ sources; other
  physics, so no bit check).

Then the plant alone's step, timed call by call (CPU), one step per call: each right after the
last, or each right after one step of the study run (``--interleaved_steps``): the same C++
work (one SAP Newton iteration per step in both, counted with breakpoints in issue 32) run
between other code. The difference is what the plant's step loses to caches and predictors
that the study run's other systems have filled.

How to read it: "the rest" (step_cost.py) is the study run's step less the plant alone less
the Python callbacks timed inside it; the variants put numbers on the parts of it that can be
removed without changing a history (under load their differences carry tens of µs of noise:
step_instructions.py counts the same variants' instructions, which load does not change). The
parts none of them removes, Drake's own per-step work around a Diagram of ~30 systems and the
plant's step slowed between the other systems' code, are split by step_profile.py.

  python benchmarks/step_rest.py [--run a_3] [--time_step_s 1e-3] [--rounds 30]
"""

import gc
import os
import random
import statistics
import time

import numpy as np
from pydrake.systems import primitives

from step_cost import plant_alone_simulator

import drake_car.sim.build as build_module
from drake_car.commands import cli
from drake_car.data import resource
from drake_car.scene.load import load_scene
from drake_car.sim.build import build_diagram
from drake_car.sim.simulate import SceneRunner


def _without_state_log(scene):
    """The scene's Diagram without the per-step VectorLogSink of the car's state."""
    original = build_module.LogVectorOutput

    class _NoLogger:
        def set_name(self, name):
            pass

    def log_unless_every_step(port, builder, period):
        if period == scene.time_step_s and port.get_system().get_name() == "plant":
            return _NoLogger()
        return original(port, builder, period)

    build_module.LogVectorOutput = log_unless_every_step
    try:
        built = build_diagram(scene)
    finally:
        build_module.LogVectorOutput = original
    assert build_module.LogVectorOutput is primitives.LogVectorOutput
    built.velocity_logger = None  # no frozen-step count
    return built


def _gain_writes_doubled(runner):
    friction = runner.built.friction
    once = friction._set_gains

    def twice(values):
        once(values)
        once(values)
    friction._set_gains = twice  # the instance's; the update looks it up every step


def main():
    p = cli.parser(__doc__, prog="benchmarks/step_rest.py", out=False)
    p.add_argument("--run", default="a_3", help="an entry of scenes/paper_study.yaml")
    p.add_argument("--time_step_s", type=float, default=1e-3)
    p.add_argument("--t0_s", type=float, default=3.0, help="where the measured chunks start")
    p.add_argument("--chunk_s", type=float, default=0.1, help="simulated seconds per chunk")
    p.add_argument("--rounds", type=int, default=30, help="chunks per variant")
    p.add_argument("--interleaved_steps", type=int, default=2000,
                   help="plant-alone steps timed one by one, each way")
    args = p.parse_args()
    if not (args.time_step_s > 0 and args.chunk_s >= 10 * args.time_step_s
            and args.rounds >= 2 and args.t0_s > 0):
        p.error("--time_step_s > 0, --chunk_s >= 10 steps, --rounds >= 2, --t0_s > 0")
    step = f"plant: {{time_step: {args.time_step_s!r}}}"

    def scene_of(text=""):
        return load_scene(resource("scenes/paper_study.yaml"), child=args.run,
                          scene_text=step + ("\n" + text if text else ""))

    study = scene_of()
    runners = {
        "study run": SceneRunner(study),
        "gain writes x2": SceneRunner(study),
        "no per-step state log": SceneRunner(study, built=_without_state_log(study)),
        "no SAP pacer": SceneRunner(scene_of("simulator: {sap_pacer: false}")),
        "no logged channels": SceneRunner(scene_of("logging: {channels: []}")),
        "monitor per chunk": SceneRunner(scene_of(
            f"simulator: {{monitor_period_s: {args.chunk_s!r}}}")),
        "Python's GC off": SceneRunner(study),
    }
    if runners["study run"].built.friction is not None:
        _gain_writes_doubled(runners["gain writes x2"])
    else:
        del runners["gain writes x2"]
    advance = {}
    for name, runner in runners.items():
        runner.start()
        runner.advance_to(args.t0_s)
        advance[name] = runner.advance_to
    alone = plant_alone_simulator(study, runners["study run"])
    advance["plant alone"] = alone.AdvanceTo

    def without_gc(t, _advance=advance["Python's GC off"]):
        gc.disable()
        try:
            _advance(t)
        finally:
            gc.enable()
    advance["Python's GC off"] = without_gc

    steps = round(args.chunk_s / args.time_step_s)
    load_before = os.getloadavg()
    cpu = {name: [] for name in advance}
    names = list(advance)
    # A fixed cycle would have each variant always follow the same other one, and a chunk
    # after the plant alone's starts with the Python systems' code out of the caches (with the
    # order rotated, the study run, always after the plant alone, came out 28 µs/step slower
    # than its own bit-identical variants): the order is shuffled every round instead.
    shuffle = random.Random(32)
    for k in range(args.rounds):
        t = args.t0_s + (k + 1) * args.chunk_s
        for name in shuffle.sample(names, len(names)):  # each after any other, by chance
            began = time.process_time()
            advance[name](t)
            cpu[name].append(1e6 * (time.process_time() - began) / steps)
    load_after = os.getloadavg()

    def state(runner):
        plant = runner.built.plant
        return plant.GetPositionsAndVelocities(plant.GetMyContextFromRoot(runner.root))

    reference = state(runners["study run"])
    same = {name: "-" if name == "plant alone" else
            "yes" if np.array_equal(state(runners[name]), reference) else "NO"
            for name in cpu}
    print(f"{args.run} at {args.time_step_s:g} s from t = {args.t0_s:g} s, {args.rounds} "
          f"chunks of {steps} steps per variant, alternately; CPU µs/step; load average "
          f"{load_before[0]:.2f} before, {load_after[0]:.2f} after ({os.cpu_count()} cores)")
    interleaved = cold_cache(runners["study run"], alone, args.time_step_s,
                             args.interleaved_steps)
    print(f"  {'variant':24s} {'median':>7s}  {'- study run: median':>20s} {'IQR':>15s}  "
          "same physics")
    for name, values in cpu.items():
        diff = np.subtract(values, cpu["study run"])
        q1, q3 = np.percentile(diff, [25, 75])
        print(f"  {name:24s} {statistics.median(values):7.1f}  {np.median(diff):+20.1f} "
              f"{q1:+7.1f}..{q3:+6.1f}  {same[name]}")
    print("  the plant alone's step, one per call (CPU µs, median of blocks of 100, quartiles):")
    for name, values in interleaved.items():
        q1, q3 = np.percentile(values, [25, 75])
        print(f"    {name:44s} {statistics.median(values):6.1f}  ({q1:.1f}..{q3:.1f})")


def cold_cache(runner, alone, dt, steps, block=100):
    """The plant alone's AdvanceTo, one step per call, timed per call: back to back, and each
    after one step of ``runner``'s simulator (the study run, without its monitor). Blocks of
    ``block`` steps alternate between the two; returns name -> per-block median µs."""
    study, plant = runner.simulator, alone
    out = {"back to back": [], "each after one step of the study run": []}
    names = list(out)
    for k in range(2 * max(1, steps // block)):
        name = names[k % 2]
        times = []
        for _ in range(block):
            if k % 2:
                study.AdvanceTo(study.get_context().get_time() + dt)
            t = plant.get_context().get_time() + dt
            began = time.process_time_ns()
            plant.AdvanceTo(t)
            times.append(1e-3 * (time.process_time_ns() - began))
        out[name].append(statistics.median(times))
    return out


if __name__ == "__main__":
    main()
