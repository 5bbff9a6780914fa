"""A step's work counted in instructions, which a shared machine's load does not change:
Valgrind's callgrind counts the instructions (Ir) of ``--span_s`` of a study run and of each
variant of ``step_rest.py`` that keeps its physics bit for bit (the same state at the same
time, advanced over the same span), and of the plant alone (``step_cost.py``). Each variant's
difference to the study run is exactly the instructions of the part it removes (or doubles).
Then the inclusive instructions of the plant's step and of Drake's framework parts, the study
run against the plant alone.

How to read it: time is instructions over their rate. The study run does about 1.4 times the
plant alone's instructions per step (issue 32: 1.66 M against 1.17 M at t = 1 s) but takes 2.2
to 3 times its time: the plant's own step does nearly the same instructions in both (+5 %: the
C++ systems feeding its inputs) yet takes longer between the other systems' code, which has
refilled the caches and branch predictors (step_rest.py times the plant alone's step back to
back and after a step of the study run). A part's instruction count says what removing it
saves at most in work; what it saves in time can be more (less code between the plant's
steps) and is measured by step_rest.py.

Needs valgrind (callgrind_control, callgrind_annotate) on the PATH. Slow: about 50 times the
instrumented span's own time, plus bringing each variant to ``--t0_s`` under valgrind.

  python benchmarks/step_instructions.py [--run a_3] [--t0_s 1.0] [--span_s 0.1]
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from drake_car.commands import cli
from drake_car.data import resource
from drake_car.scene.load import load_scene

# Drake's functions whose inclusive instructions the report compares (study run, plant alone).
FUNCTIONS = (
    ("the step (Simulator::AdvanceTo)", "Simulator<double>::AdvanceTo("),
    ("the plant's step", "Simulator<double>::HandleUnrestrictedUpdate("),
    ("  SAP's solve", "SapSolver<double>::SolveWithGuess("),
    ("  its contact problem", "SapDriver<double>::EvalContactProblemCache("),
    ("  its reaction forces", "MultibodyPlant<double>::CalcReactionForces("),
    ("  its input ports' forces", "DiscreteUpdateManager<double>::CalcInputPortForces("),
    ("  its actuation input", "DiscreteUpdateManager<double>::CalcJointActuationForces("),
    ("  its desired-state input", "MultibodyPlant<double>::EvalDesiredStateInput("),
    ("the Python systems' updates", "Simulator<double>::HandleDiscreteUpdate("),
    ("the loggers' publish", "Simulator<double>::HandlePublish("),
    ("the time advance", "Simulator<double>::IntegrateContinuousState("),
    ("the event scan", "Diagram<double>::DoCalcNextUpdateTime("),
    ("applying the plant's update", "Diagram<double>::DoApplyUnrestrictedUpdate("),
)


def inside(args):
    """Runs under callgrind: each variant brought to t0 uninstrumented, then its span
    instrumented and dumped apart (named by the variant)."""
    from step_cost import plant_alone_simulator
    from step_rest import _gain_writes_doubled, _without_state_log

    from drake_car.sim.simulate import SceneRunner

    pid = str(os.getpid())

    def control(*options):
        subprocess.run(["callgrind_control", *options, pid], check=True, capture_output=True)

    def scene_of(text=""):
        return load_scene(resource("scenes/paper_study.yaml"), child=args.run,
                          scene_text=text or None)

    study = scene_of()
    runners = {
        "study run": SceneRunner(study),
        "no per-step state log": SceneRunner(study, built=_without_state_log(study)),
        "monitor once per span": SceneRunner(scene_of(
            f"simulator: {{monitor_period_s: {args.span_s!r}}}")),
        "gain writes x2": SceneRunner(study),
        "no logged channels": SceneRunner(scene_of("logging: {channels: []}")),
    }
    _gain_writes_doubled(runners["gain writes x2"])
    for runner in runners.values():
        runner.start()
        runner.advance_to(args.t0_s)
    alone = plant_alone_simulator(study, runners["study run"])
    advance = {name: runner.advance_to for name, runner in runners.items()}
    advance["plant alone"] = alone.AdvanceTo
    for index, (name, step) in enumerate(advance.items()):
        control("-z")
        control("-i", "on")
        step(args.t0_s + args.span_s)
        control("-i", "off")
        control(f"--dump=variant {index}")
    return list(advance)


def totals(dump):
    """The instructions of a callgrind dump."""
    for line in Path(dump).read_text(errors="replace").splitlines():
        if line.startswith("totals:"):
            return int(line.split()[1])
    raise RuntimeError(f"{dump}: no totals line")


def inclusive(dump):
    """Function name -> inclusive instructions (``callgrind_annotate --inclusive=yes``)."""
    text = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100", dump],
                          capture_output=True, text=True, errors="replace").stdout
    out = {}
    for line in text.splitlines():
        m = re.match(r"\s*([\d,]+) \(\s*[\d.]+%\)\s+(.*)", line)
        if m:
            out.setdefault(m.group(2), int(m.group(1).replace(",", "")))
    return out


def find(functions, pattern):
    """The outermost (non-recursive) entry of a function: its name without callgrind's
    recursion mark."""
    for name, ir in functions.items():
        if pattern in name and "'" not in name.split(pattern, 1)[1].split(")", 1)[0]:
            return ir
    return 0


def main():
    p = cli.parser(__doc__, prog="benchmarks/step_instructions.py", out=False)
    p.add_argument("--run", default="a_3", help="an entry of scenes/paper_study.yaml")
    p.add_argument("--t0_s", type=float, default=1.0, help="where the counted span starts")
    p.add_argument("--span_s", type=float, default=0.1, help="simulated seconds counted")
    p.add_argument("--inside", action="store_true", help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.inside:
        inside(args)
        return
    for tool in ("valgrind", "callgrind_control", "callgrind_annotate"):
        if shutil.which(tool) is None:
            p.error(f"needs {tool} on the PATH")
    if not (args.t0_s > 0 and args.span_s > 0):
        p.error("--t0_s and --span_s must be > 0")
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "callgrind.out"
        command = ["valgrind", "--tool=callgrind", "--instr-atstart=no",
                   f"--callgrind-out-file={out}", sys.executable, __file__, "--inside",
                   "--run", args.run, "--t0_s", repr(args.t0_s), "--span_s", repr(args.span_s)]
        env = dict(os.environ, PYTHONPATH=os.pathsep.join(
            [str(Path(__file__).parent)] + os.environ.get("PYTHONPATH", "").split(os.pathsep)))
        done = subprocess.run(command, env=env, capture_output=True, text=True)
        dumps = sorted(Path(folder).glob("callgrind.out.*"), key=lambda d: int(d.suffix[1:]))
        if done.returncode != 0 or not dumps:
            raise RuntimeError(f"valgrind failed: {done.stderr.strip()[-2000:]}")
        names = []
        for dump in dumps:
            text = dump.read_text(errors="replace")
            match = re.search(r"^desc: Trigger: dump variant (\d+)", text, re.M)
            names.append(int(match.group(1)) if match else None)
        counted = {n: d for n, d in zip(names, dumps) if n is not None}
        labels = ["study run", "no per-step state log", "monitor once per span",
                  "gain writes x2", "no logged channels", "plant alone"]
        print(f"{args.run} from t = {args.t0_s:g} s over {args.span_s:g} s: instructions per "
              "step (callgrind)")
        per_step = {}
        for index, label in enumerate(labels):
            ir = totals(counted[index])
            per_step[label] = ir
        step_s = load_scene(resource("scenes/paper_study.yaml"), child=args.run).time_step_s
        steps = round(args.span_s / step_s)
        base = per_step["study run"] / steps
        for label, ir in per_step.items():
            print(f"  {label:26s} {ir / steps:12,.0f}  {ir / steps - base:+12,.0f}  "
                  f"({100 * (ir / steps / base - 1):+.1f} %)")
        study, alone = inclusive(counted[0]), inclusive(counted[5])
        print("  inclusive instructions per step         study run   plant alone")
        for label, pattern in FUNCTIONS:
            print(f"  {label:38s} {find(study, pattern) / steps:11,.0f} "
                  f"{find(alone, pattern) / steps:13,.0f}")


if __name__ == "__main__":
    main()
