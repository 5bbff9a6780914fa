"""Where a study run's step goes, part by part, against the plant alone's: Linux ``perf``
samples (call stacks through Drake's C++ and Python) of the study run's Diagram and of its plant
alone (``step_cost.plant_alone_simulator``), each sample put into one part by the frames on its
stack (``PARTS``), each part's share turned into µs per step with the CPU time of an unprofiled
span of the same run just before. ``--repeats`` spans of each, alternately; the table gives the
median and the range over the repeats.

How to read it: the plant's parts (SAP's solve, its contact problem, its reaction forces) are
the same work in both: one SAP Newton iteration per step in each (issue 32 counted the calls
with breakpoints), so where the study run's figure is the larger, the same C++ ran slower
between the other systems' code (caches and branch predictors refilled), it did not do more.
"its inputs" is work the plant alone does not have: the C++ systems feeding the plant
(multiplexers, matrix gains, the trajectories, the drive's chain, the tyres' force applier)
evaluated every step. "time advance", "next update time", "applying its update", "discrete
updates: framework", "event collections" are Drake's framework: per step it scans every
system for its next event, advances the time (invalidating every cache entry that depends on
it: sources, gains, the plant's inputs and what depends on them), dispatches the events and
applies the new state (invalidating again). The Python parts are the tyres' and the friction's
updates and the logged channels' calculations (``step_cost.py`` times their callbacks).

Needs ``perf`` on the PATH and permission to sample this process (perf_event_paranoid <= 2).

  python benchmarks/step_profile.py [--run a_3] [--time_step_s 1e-3] [--repeats 3]
"""

import collections
import os
import re
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from step_cost import plant_alone_simulator

from drake_car.commands import cli
from drake_car.data import resource
from drake_car.scene.load import load_scene
from drake_car.sim.simulate import SceneRunner

_PYTHON = ("_PyEval_EvalFrameDefault", "nanobind::", "PyObject_Vectorcall")


def _has(stack, pattern):
    return any(pattern in frame for frame in stack)


def _python(stack):
    return any(p in frame for frame in stack for p in _PYTHON)


def part(stack):
    """The part of a step a sample (frames from the root, below ``Simulator::AdvanceTo``; None
    outside it) is in."""
    if stack is None:
        return "outside the simulator (monitor, runner)"
    top = stack[0] if stack else ""
    if "HandleUnrestrictedUpdate" in top:
        if _has(stack, "SolveWithGuess"):
            return "plant: SAP solve"
        if _has(stack, "EvalConnectedSubsystemInput") or _has(stack, "EvalSubsystemOutputPort"):
            return "plant: its inputs (the C++ systems feeding it)"
        if _has(stack, "CalcReactionForces"):
            return "plant: reaction forces (sampled ports)"
        if _has(stack, "CalcContactProblemCache"):
            return "plant: contact problem"
        if _has(stack, "DoApplyUnrestrictedUpdate"):
            return "plant: applying its update (copy, invalidation)"
        return "plant: the rest of its step"
    if "HandleDiscreteUpdate" in top:
        return ("discrete updates: Python (tyres, friction)" if _python(stack)
                else "discrete updates: framework")
    if "HandlePublish" in top:
        return "publish: Python (logged channels)" if _python(stack) else "publish: loggers"
    if "IntegrateContinuousState" in top:
        return "time advance (integrator, time's invalidation)"
    if "CalcNextUpdateTime" in top:
        return "next update time (event scan)"
    return "event collections, other"


def samples(perf_data):
    """Call stacks (root first, below ``Simulator::AdvanceTo``) of ``perf script``'s samples;
    None for a sample outside ``AdvanceTo`` (the monitor's checks, the runner's loop)."""
    text = subprocess.run(["perf", "script", "-i", str(perf_data), "--no-inline", "-F",
                           "comm,tid,time,ip,sym"], capture_output=True, text=True,
                          errors="replace").stdout
    out, current = [], None
    for line in text.splitlines() + [""]:
        if not line.strip():
            if current:
                stack = list(reversed(current))
                at = next((i for i, f in enumerate(stack)
                           if "Simulator<double>::AdvanceTo" in f), None)
                out.append(None if at is None else stack[at + 1:])
            current = None
        elif not line[0].isspace():
            current = []
        elif current is not None:
            fields = line.strip().split(None, 1)
            current.append(re.sub(r"\(.*", "", fields[1] if len(fields) > 1 else "?"))
    return out


def profiled(advance, target, data, frequency):
    """``advance(target)`` under ``perf record`` of this process, into ``data``."""
    recorder = subprocess.Popen(
        ["perf", "record", "-F", str(frequency), "--call-graph", "dwarf,32768", "-p",
         str(os.getpid()), "-o", str(data)], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    time.sleep(1.0)  # perf attaches
    advance(target)
    recorder.send_signal(signal.SIGINT)
    _, error = recorder.communicate()
    if recorder.returncode not in (0, -signal.SIGINT) or not data.exists():
        raise RuntimeError(f"perf record failed: {error.decode(errors='replace').strip()}")


def main():
    p = cli.parser(__doc__, prog="benchmarks/step_profile.py", out=False)
    p.add_argument("--run", default="a_3", help="an entry of scenes/paper_study.yaml")
    p.add_argument("--time_step_s", type=float, default=1e-3)
    p.add_argument("--t0_s", type=float, default=3.0, help="where the measured spans start")
    p.add_argument("--span_s", type=float, default=1.0, help="simulated seconds per span")
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--frequency", type=int, default=999, help="perf's samples per second")
    args = p.parse_args()
    if shutil.which("perf") is None:
        p.error("needs Linux perf on the PATH")
    if not (args.time_step_s > 0 and args.span_s >= 100 * args.time_step_s
            and args.repeats >= 1):
        p.error("--time_step_s > 0, --span_s >= 100 steps, --repeats >= 1")
    scene = load_scene(resource("scenes/paper_study.yaml"), child=args.run,
                       scene_text=f"plant: {{time_step: {args.time_step_s!r}}}")
    runner = SceneRunner(scene)
    runner.start()
    runner.advance_to(args.t0_s)
    alone = plant_alone_simulator(scene, runner)
    steps = round(args.span_s / args.time_step_s)
    clocks = {"study run": [runner.advance_to, args.t0_s],
              "plant alone": [alone.AdvanceTo, args.t0_s]}
    table = collections.defaultdict(lambda: collections.defaultdict(list))
    with tempfile.TemporaryDirectory() as folder:
        for repeat in range(args.repeats):
            for name, clock in clocks.items():
                advance = clock[0]
                clock[1] += args.span_s
                began = time.process_time()
                advance(clock[1])  # unprofiled: the CPU per step
                us = 1e6 * (time.process_time() - began) / steps
                clock[1] += args.span_s
                data = Path(folder) / f"{repeat}.data"
                profiled(advance, clock[1], data, args.frequency)
                stacks = samples(data)
                data.unlink()
                counts = collections.Counter(part(s) for s in stacks)
                for key, count in counts.items():
                    table[key][name].append(us * count / len(stacks))
                for key in table:
                    if key != "whole step" and len(table[key][name]) < repeat + 1:
                        table[key][name].append(0.0)
                table["whole step"][name].append(us)
                print(f"  {name} repeat {repeat + 1}: {us:.0f} µs/step unprofiled, "
                      f"{len(stacks)} samples", file=sys.stderr, flush=True)
    print(f"{args.run} at {args.time_step_s:g} s from t = {args.t0_s:g} s; {args.repeats} "
          f"spans of {steps} steps each; CPU µs per step, median (range); load average "
          f"{os.getloadavg()[0]:.2f} ({os.cpu_count()} cores)")
    print(f"  {'part':48s} {'study run':>22s} {'plant alone':>22s}")
    order = sorted(table, key=lambda k: (k != "whole step",
                                         -statistics.median(table[k]["study run"] or [0])))
    for key in order:
        cells = []
        for name in clocks:
            values = table[key][name] or [0.0] * args.repeats
            values += [0.0] * (args.repeats - len(values))
            cells.append(f"{statistics.median(values):6.1f} "
                         f"({min(values):5.1f}..{max(values):5.1f})")
        print(f"  {key:48s} {cells[0]:>22s} {cells[1]:>22s}")


if __name__ == "__main__":
    main()
