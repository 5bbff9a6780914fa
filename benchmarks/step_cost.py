"""What a step costs: the whole Diagram of a study run against its plant alone, and where the
difference goes (each LeafSystem's Python).

The plant alone: the same car, actuators, SAP pacer and plant configuration in a Diagram whose
inputs come from Drake's C++ constant sources, holding the values the whole Diagram fed it at
``--t0_s`` (a car accelerating, struts stuck or sliding), started from the whole Diagram's state
there. Both are advanced over the same simulated span, interleaved, ``--repeats`` times; the
report gives medians and their ratio (compare ratios, not seconds: this machine is shared).
A cProfile of the whole Diagram splits its Python by system (cumulative times scaled to the
plain run's Python share).

  python benchmarks/step_cost.py [--scene a_3] [--time_step_s 1e-3] [--repeats 5] [--out DIR]
"""

import argparse
import cProfile
import pstats
import statistics
import time
from pathlib import Path

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.multibody.plant import AddMultibodyPlant
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import ConstantValueSource, ConstantVectorSource

from drake_car.data import resource
from drake_car.model.car import add_car
from drake_car.model.drive import add_drive_actuators
from drake_car.model.struts import declare_strut_friction
from drake_car.scene.load import load_scene
from drake_car.scene.scene import PrescribedRotation
from drake_car.sim.outputs import output_folder, provenance, write_json
from drake_car.sim.simulate import Runner
from drake_car.systems.sap_pacer import add_sap_pacer, connect_sap_pacer

# The callbacks Drake calls into each Python system (cumulative times are disjoint; the cache
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


def whole_diagram(scene, t0, span):
    """Seconds of wall time for ``span`` simulated seconds from ``t0``, and the Runner."""
    runner = Runner(scene)
    runner.start()
    runner.advance_to(t0)
    began = time.perf_counter()
    runner.simulator.AdvanceTo(t0 + span)
    return time.perf_counter() - began, runner


def plant_alone(scene, runner, span):
    """The same plant with its inputs held by C++ constant sources at ``runner``'s values."""
    full, root = runner.built, runner.root
    pc = full.plant.GetMyContextFromRoot(root)
    car_instance = full.car.instance
    builder = DiagramBuilder()
    plant, _ = AddMultibodyPlant(scene.plant, builder)
    car = add_car(plant, scene.car)
    if scene.manoeuvre.drives:
        add_drive_actuators(plant, car, pd=isinstance(scene.drive, PrescribedRotation))
    if scene.friction is not None:
        declare_strut_friction(plant, car, rotation=scene.friction.rotation,
                               scheme=scene.friction.scheme)
    pacer = add_sap_pacer(plant) if scene.simulator.sap_pacer else None
    plant.Finalize()
    if pacer is not None:
        connect_sap_pacer(builder, plant, pacer)
    sources = [
        (full.plant.get_desired_state_input_port(car_instance),
         plant.get_desired_state_input_port(car.instance)),
        (full.plant.get_actuation_input_port(car_instance),
         plant.get_actuation_input_port(car.instance)),
        (full.plant.get_applied_generalized_force_input_port(),
         plant.get_applied_generalized_force_input_port()),
    ]
    for source, target in sources:
        if source.HasValue(pc):
            held = builder.AddSystem(ConstantVectorSource(np.array(source.Eval(pc))))
            builder.Connect(held.get_output_port(0), target)
    forces = full.plant.get_applied_spatial_force_input_port().Eval(pc)
    held = builder.AddSystem(ConstantValueSource(AbstractValue.Make(list(forces))))
    builder.Connect(held.get_output_port(0), plant.get_applied_spatial_force_input_port())
    diagram = builder.Build()
    # The friction's gains as the whole Diagram last wrote them.
    if scene.friction is not None:
        for side, pairs in (("left", 0), ("right", 1)):
            for kind in ("translation", "rotation"):
                name = f"strut_friction_{side}_{kind}"
                if full.plant.HasJointActuatorNamed(name):
                    mine = plant.GetJointActuatorByName(name)
                    theirs = full.plant.GetJointActuatorByName(name)
                    mine.set_controller_gains(theirs.get_controller_gains())
                    mine.set_effort_limit(theirs.effort_limit())
    simulator = Simulator(diagram)
    context = simulator.get_mutable_context()
    context.SetTime(root.get_time())
    plant.SetPositionsAndVelocities(plant.GetMyMutableContextFromRoot(context),
                                    full.plant.GetPositionsAndVelocities(pc))
    simulator.Initialize()
    began = time.perf_counter()
    simulator.AdvanceTo(root.get_time() + span)
    return time.perf_counter() - began


def profile_split(scene, t0, span, python_wall, steps):
    profiler = cProfile.Profile()
    runner = Runner(scene)
    runner.start()
    runner.advance_to(t0)
    profiler.enable()
    runner.advance_to(t0 + span)
    profiler.disable()
    stats = pstats.Stats(profiler).stats
    python_profiled = sum(v[2] for k, v in stats.items()
                          if not (k[0] == "~" and "AdvanceTo" in k[2]))
    split = {}
    for name, (path, functions) in SYSTEMS.items():
        cumulative = sum(v[3] for k, v in stats.items()
                         if k[0].endswith(path) and k[2] in functions)
        split[name] = 1e6 * cumulative / max(python_profiled, 1e-12) * python_wall / steps
    return split


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--scene", default="a_3", help="an entry of scenes/paper_study.yaml")
    p.add_argument("--time_step_s", type=float, default=1e-3)
    p.add_argument("--t0_s", type=float, default=4.0, help="where the measured span starts")
    p.add_argument("--span_s", type=float, default=2.0, help="simulated seconds measured")
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--out", type=Path, default=None)
    args = p.parse_args()
    if not (args.time_step_s > 0 and args.repeats >= 1 and args.span_s > 0):
        p.error("--time_step_s, --span_s must be > 0 and --repeats >= 1")
    scene = load_scene(resource("scenes/paper_study.yaml"), child=args.scene,
                       scene_text=f"plant: {{time_step: {args.time_step_s!r}}}")
    steps = round(args.span_s / args.time_step_s)
    whole, alone = [], []
    for _ in range(args.repeats):  # interleaved: drift hits both alike
        wall, runner = whole_diagram(scene, args.t0_s, args.span_s)
        whole.append(1e6 * wall / steps)
        alone.append(1e6 * plant_alone(scene, runner, args.span_s) / steps)
    w, a = statistics.median(whole), statistics.median(alone)
    split = profile_split(scene, args.t0_s, args.span_s, (w - a) * steps * 1e-6, steps)
    print(f"{args.scene} at {args.time_step_s:g} s, median of {args.repeats}: whole Diagram "
          f"{w:.0f} µs/step, plant alone {a:.0f} µs/step, ratio {w / a:.2f}")
    print(f"  beyond the plant: {w - a:.0f} µs/step, of which (profile split):")
    for system, us in split.items():
        print(f"    {system:30s} {us:6.1f} µs/step")
    if args.out:
        with output_folder(args.out) as out:
            write_json(out / "step_cost.json", provenance(
                scene=args.scene, time_step_s=args.time_step_s, whole_us=whole, alone_us=alone,
                median_whole_us=w, median_alone_us=a, ratio=w / a, python_split_us=split))


if __name__ == "__main__":
    main()
