"""Where a fresh process's start-up goes: the steps of ``drake-car-run`` timed one by
one in this process (run it in a fresh one; ``benchmarks/startup_cost.py`` times whole
processes). The static equilibrium comes from the disk cache (``sim.equilibrium_cache``) when
it is warm: run once to warm it.

  python benchmarks/startup_phases.py [--run a_3] [--time_step_s 2e-3]
"""

import time

_began = time.perf_counter()

import importlib  # noqa: E402
import os  # noqa: E402
import tempfile  # noqa: E402

from drake_car.commands import cli  # noqa: E402 (light: its heavy imports are lazy)


def main():
    p = cli.parser(__doc__, prog="benchmarks/startup_phases.py", out=False)
    p.add_argument("--run", default="a_3", help="an entry of scenes/paper_study.yaml")
    p.add_argument("--time_step_s", type=float, default=2e-3)
    args = p.parse_args()
    marks = [("start", _began)]

    def mark(what):
        marks.append((what, time.perf_counter()))

    for module in ("numpy", "pydrake.multibody.plant", "pydrake.systems.analysis"):
        importlib.import_module(module)
    mark("import pydrake and numpy")
    importlib.import_module("numba")
    mark("import numba")
    importlib.import_module("drake_car.commands.run")
    from drake_car.data import resource
    from drake_car.results.files import write_run
    from drake_car.scene.load import load_scene
    from drake_car.sim.simulate import SceneRunner
    mark("import the rest of drake_car.commands.run")
    scene = load_scene(resource("scenes/paper_study.yaml"), child=args.run,
                       scene_text=f"plant: {{time_step: {args.time_step_s!r}}}")
    mark("load the scene")
    runner = SceneRunner(scene)
    mark("build (numba's CPU target and cached functions loaded)")
    runner.start()
    mark("static equilibrium (disk cache) and Initialize")
    runner.advance_to(scene.end_time_s)
    mark(f"simulate {scene.end_time_s:g} s")
    run = runner.finish()
    with tempfile.TemporaryDirectory() as out:
        write_run(run, out)
    mark("finish and write the run's files")
    print(f"{args.run} at {args.time_step_s:g} s; load average {os.getloadavg()[0]:.2f}:")
    for (_, before), (what, after) in zip(marks, marks[1:]):
        print(f"  {what:56s} {after - before:6.3f} s")
    startup = sum(b - a for (_, a), (w, b) in zip(marks, marks[1:])
                  if not w.startswith(("import pydrake", "simulate", "finish")))
    print(f"  {'start-up beyond pydrake and numpy (no simulation, no files)':56s} "
          f"{startup:6.3f} s")


if __name__ == "__main__":
    main()
