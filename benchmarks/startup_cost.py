"""What a process spends before and around its simulation: ``drake-car-run`` on a
scene, against Python importing pydrake alone, with the static equilibrium from the disk cache
(``sim.equilibrium_cache``, warmed first) and without it (``DRAKE_CAR_CACHE_DIR=off``: settled
in the process, as before the cache). Wall and CPU (the child's user + system) per process,
medians of ``--repeats``, interleaved. ``--tree`` runs another checkout's code (PYTHONPATH) for
a before/after in one sitting. This machine is shared: compare in one sitting.

  python benchmarks/startup_cost.py [--run a_3] [--time_step_s 2e-3] [--repeats 3] [--tree DIR]
"""

import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from drake_car.commands import cli

ROOT = Path(__file__).resolve().parents[1]
IMPORT_ONLY = ("import pydrake.multibody.plant, pydrake.systems.analysis, "
               "pydrake.systems.primitives, numpy")


def _timed(command, env):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    began = time.perf_counter()
    subprocess.run(command, env=env, check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - began
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main():
    p = cli.parser(__doc__, prog="benchmarks/startup_cost.py", out=False)
    p.add_argument("--run", default="a_3", help="an entry of scenes/paper_study.yaml")
    p.add_argument("--time_step_s", type=float, default=2e-3)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--tree", type=Path, action="append", default=[],
                   help="another checkout to time too (repeatable)")
    args = p.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        run = [sys.executable, "-m", "drake_car.commands.run", "--scene",
               str(ROOT / "scenes" / "paper_study.yaml"), "--child", args.run,
               "--scene_text", f"plant: {{time_step: {args.time_step_s!r}}}", "--quiet"]
        cache = str(Path(tmp) / "cache")
        cases = {"import pydrake only": ([sys.executable, "-c", IMPORT_ONLY], ROOT, None)}
        for tree in [ROOT] + [t.resolve() for t in args.tree]:
            label = "this tree" if tree == ROOT else str(tree)
            cases[f"run, {label}, no disk cache"] = (run, tree, "off")
            cases[f"run, {label}, equilibrium cached"] = (run, tree, cache)
        times = {name: [] for name in cases}
        for k in range(args.repeats + 1):  # the first round warms the caches, not counted
            for name, (command, tree, cache_dir) in cases.items():
                env = dict(os.environ, PYTHONPATH=str(tree))
                if cache_dir is not None:
                    env["DRAKE_CAR_CACHE_DIR"] = cache_dir
                out = Path(tmp) / f"out_{k}_{abs(hash(name))}"
                command = command + (["--out", str(out)] if command is run else [])
                if k:
                    times[name].append(_timed(command, env))
                else:
                    _timed(command, env)
    print(f"{args.run} at {args.time_step_s:g} s; median of {args.repeats}; load average "
          f"{os.getloadavg()[0]:.2f} ({os.cpu_count()} cores, shared):")
    base = [statistics.median(x) for x in zip(*times["import pydrake only"])]
    for name, values in times.items():
        wall, cpu = (statistics.median(x) for x in zip(*values))
        print(f"  {name:48s} wall {wall:5.2f} s (+{wall - base[0]:5.2f}), CPU {cpu:5.2f} s "
              f"(+{cpu - base[1]:5.2f})")


if __name__ == "__main__":
    main()
