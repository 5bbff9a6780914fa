"""Where a step's time goes: Drake's C++ (SAP solve, multibody kinematics, the framework) against
the Python of each LeafSystem, for a study run at the default step. Also what that implies for
the paper's study (6 runs x 10 s) on one core.

Method: each run once plainly (wall per step) and once under cProfile. cProfile inflates Python
(per-call overhead), not C++: the self time of Simulator.AdvanceTo is the C++ share (with the
pybind calls into Python); the Python share is the plain wall minus it. The per-system split
comes from the profile's cumulative times, scaled to the plain Python share.

  python benchmarks/step_cost.py [--time_step_s 1e-3] [--out results/bench]
"""

import argparse
import cProfile
import pstats
from pathlib import Path

from drake_car.data import resource  # noqa: E402
from drake_car.scene.load import load_scene  # noqa: E402
from drake_car.sim.outputs import output_folder, provenance, write_json  # noqa: E402
from drake_car.sim.simulate import simulate  # noqa: E402

RUNS = {"a_3 (μs = 0.4)": "a_3", "a_1 (lubricated)": "a_1"}
# The callbacks Drake calls into each system (their cumulative times are disjoint; the cache
# calculations they trigger are inside them).
SYSTEMS = {
    "tyres (incl. Magic Formula)": ("systems/tyre.py", ("_calc_forces", "_update",
                                                        "_calc_diagnostics", "_calc_loads")),
    "strut friction": ("systems/strut_friction.py", ("_update", "_write_gains")),
    "driveshafts": ("systems/driveshaft.py", ("_calc",)),
    "divergence monitor": ("sim/monitor.py", ("check",)),
    "logged channels": ("model/channels.py", ("_calc_chassis", "_calc_steering",
                                              "_calc_struts", "_calc_energy")),
}


def measure(name, args):
    scene = load_scene(resource("scenes/paper_study.yaml"), child=name,
                       scene_text=f"plant: {{time_step: {args.time_step_s!r}}}")
    simulate(scene)  # the static equilibrium, cached: not part of the measured runs
    run = simulate(scene)
    wall = run.wall_s
    steps = round(float(run.history["t"][-1]) / args.time_step_s)
    profiler = cProfile.Profile()
    profiler.enable()
    simulate(scene)
    profiler.disable()
    stats = pstats.Stats(profiler).stats
    cpp = sum(v[2] for k, v in stats.items() if k[0] == "~" and "AdvanceTo" in k[2])
    profiled_total = sum(v[2] for v in stats.values())  # all self times
    python_profiled = profiled_total - cpp
    python_plain = max(wall - cpp, 0.0)
    per_system = {}
    for name, (path, functions) in SYSTEMS.items():
        cumulative = sum(v[3] for k, v in stats.items()
                         if k[0].endswith(path) and k[2] in functions)
        per_system[name] = 1e6 * cumulative / max(python_profiled, 1e-12) * python_plain / steps
    return {"wall_s": wall, "steps": steps, "wall_per_step_us": 1e6 * wall / steps,
            "cpp_per_step_us": 1e6 * cpp / steps,
            "python_per_step_us": 1e6 * python_plain / steps,
            "python_per_system_per_step_us": per_system}


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--time_step_s", type=float, default=1e-3)
    p.add_argument("--out", type=Path, default=None)
    args = p.parse_args()
    if not args.time_step_s > 0:
        p.error("--time_step_s must be > 0")
    results = {}
    for name, child in RUNS.items():
        results[name] = r = measure(child, args)
        print(f"{name}: {r['wall_s']:.2f} s for {r['steps']} steps = "
              f"{r['wall_per_step_us']:.0f} µs/step: C++ {r['cpp_per_step_us']:.0f}, "
              f"Python {r['python_per_step_us']:.0f}")
        for system, us in r["python_per_system_per_step_us"].items():
            print(f"    {system:30s} {us:6.1f} µs/step")
    a3 = results["a_3 (μs = 0.4)"]
    steps = 6 * 10.0 / args.time_step_s
    floor = steps * a3["cpp_per_step_us"] * 1e-6
    print(f"study (6 x 10 s) at dt = {args.time_step_s:g} s: {steps:.0f} steps; the C++ share "
          f"alone takes {floor:.1f} s, at a_3's full cost {steps * a3['wall_per_step_us'] * 1e-6:.1f} s")
    if args.out:
        with output_folder(args.out) as out:
            write_json(out / "step_cost.json", provenance(
                runs=results, study_steps=steps, study_cpp_floor_s=floor,
                time_step_s=args.time_step_s))


if __name__ == "__main__":
    main()
