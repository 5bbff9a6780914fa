"""What a step costs: the whole Diagram of a study run against its plant alone, and where the
difference goes (each LeafSystem's Python).

The plant alone: the same car, actuators, SAP pacer and plant configuration in a Diagram whose
inputs come from Drake's C++ constant sources, holding the values the whole Diagram fed it at
``--t0_s`` (a car accelerating, struts stuck or sliding), started from the whole Diagram's state
there. Both are advanced over the same simulated span, interleaved, ``--repeats`` times: the
whole Diagram as a study run advances it (in the divergence monitor's chunks, the checks
included), the plant alone in one call. The report gives medians of the wall time and of the
process's CPU time and their ratios, with the load average (compare ratios, not seconds: this
machine is shared; the CPU time is the steadier of the two under load). One more run of the whole
Diagram times each Python system's callbacks in place.

  python benchmarks/step_cost.py [--run a_3] [--time_step_s 1e-3] [--repeats 5] [--out DIR]
"""

import os
import statistics
import time

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.multibody.plant import AddMultibodyPlant
from pydrake.multibody.tree import ModelInstanceIndex
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import ConstantValueSource, ConstantVectorSource

from drake_car.commands import cli
from drake_car.data import resource
from drake_car.model.channels import CarChannels
from drake_car.model.car import add_car
from drake_car.model.drive import add_drive_actuators
from drake_car.model.struts import declare_strut_friction
from drake_car.scene.load import load_scene
from drake_car.model.steering import add_steering_column
from drake_car.scene.scene import HandsOff, PrescribedRotation
from drake_car.sim.monitor import Monitor
from drake_car.results.files import write_json
from drake_car.results.folder import output_folder
from drake_car.results.provenance import provenance
from drake_car.sim.build import build_diagram
from drake_car.sim.simulate import SceneRunner
from drake_car.systems.strut_friction import StrutFriction
from drake_car.systems.tyre import TyreSystem
from drake_car.systems.sap_pacer import add_sap_pacer, connect_sap_pacer

# The callbacks Drake calls into each Python system, by class (the cache and port calculations
# they trigger are inside them).
SYSTEMS = {
    "tyres and driveshafts": (TyreSystem, ("_update",)),
    "strut friction and its PD gains": (StrutFriction, ("_update",)),
    "divergence monitor": (Monitor, ("check",)),
    "logged channels": (CarChannels, ("_calc_chassis", "_calc_steering", "_calc_struts",
                                      "_calc_energy", "_calc_top_mounts")),
}


def _clocks():
    """(wall, this process's CPU) seconds: on a shared machine the CPU time is the steadier
    measure (other processes' load stretches the wall time, less the CPU time)."""
    return time.perf_counter(), time.process_time()


def _since(began):
    wall, cpu = _clocks()
    return wall - began[0], cpu - began[1]


def whole_diagram(scene, t0, span, *, column_form="reflected"):
    """(wall, CPU) seconds for ``span`` simulated seconds from ``t0``, and the runner. The
    span runs as a study run does: in the divergence monitor's chunks (``Runner.advance_to``).
    ``column_form``: a hands-off scene's steering column (``model.steering.COLUMN_FORMS``)."""
    runner = SceneRunner(scene, built=build_diagram(scene, column_form=column_form))
    runner.start()
    runner.advance_to(t0)
    began = _clocks()
    runner.advance_to(t0 + span)
    return _since(began), runner


def plant_alone(scene, runner, span):
    """(wall, CPU) seconds of ``plant_alone_simulator`` advanced ``span`` simulated seconds."""
    simulator = plant_alone_simulator(scene, runner)
    began = _clocks()
    simulator.AdvanceTo(simulator.get_context().get_time() + span)
    return _since(began)


def plant_alone_simulator(scene, runner):
    """The same plant (the hands-off column in the form ``runner`` built) with its inputs held
    by C++ constant sources at ``runner``'s values, every actuator's PD gains and effort limit
    as the whole Diagram last wrote them: an initialized Simulator at ``runner``'s time and
    state."""
    full, root = runner.built, runner.root
    pc = full.plant.GetMyContextFromRoot(root)
    builder = DiagramBuilder()
    plant, _ = AddMultibodyPlant(scene.plant, builder)
    car = add_car(plant, scene.car)
    if scene.manoeuvre.drives:
        add_drive_actuators(plant, car, pd=isinstance(scene.drive, PrescribedRotation))
    if scene.friction is not None:
        declare_strut_friction(plant, car, rotation=scene.friction.rotation,
                               scheme=scene.friction.scheme)
    if isinstance(scene.steering, HandsOff):
        form = ("coupler" if full.plant.HasModelInstanceNamed("steering_column")
                else "reflected")
        add_steering_column(plant, car, scene.steering, scheme="fast", form=form)
    pacer = add_sap_pacer(plant) if scene.simulator.sap_pacer else None
    plant.Finalize()
    if pacer is not None:
        connect_sap_pacer(builder, plant, pacer)
    sources = [(full.plant.get_applied_generalized_force_input_port(),
                plant.get_applied_generalized_force_input_port())]
    for i in range(full.plant.num_model_instances()):
        theirs = ModelInstanceIndex(i)
        if full.plant.num_actuated_dofs(theirs) == 0:
            continue
        mine = plant.GetModelInstanceByName(full.plant.GetModelInstanceName(theirs))
        sources += [(full.plant.get_desired_state_input_port(theirs),
                     plant.get_desired_state_input_port(mine)),
                    (full.plant.get_actuation_input_port(theirs),
                     plant.get_actuation_input_port(mine))]
    for source, target in sources:
        if source.HasValue(pc) and not builder.IsConnectedOrExported(target):
            held = builder.AddSystem(ConstantVectorSource(np.array(source.Eval(pc))))
            builder.Connect(held.get_output_port(0), target)
    forces = full.plant.get_applied_spatial_force_input_port().Eval(pc)
    held = builder.AddSystem(ConstantValueSource(AbstractValue.Make(list(forces))))
    builder.Connect(held.get_output_port(0), plant.get_applied_spatial_force_input_port())
    diagram = builder.Build()
    for index in full.plant.GetJointActuatorIndices():
        theirs = full.plant.get_joint_actuator(index)
        if theirs.has_controller():
            mine = plant.GetJointActuatorByName(theirs.name())
            mine.set_controller_gains(theirs.get_controller_gains())
            mine.set_effort_limit(theirs.effort_limit())
    simulator = Simulator(diagram)
    context = simulator.get_mutable_context()
    context.SetTime(root.get_time())
    plant.SetPositionsAndVelocities(plant.GetMyMutableContextFromRoot(context),
                                    full.plant.GetPositionsAndVelocities(pc))
    simulator.Initialize()
    return simulator


def callback_split(scene, t0, span, steps):
    """µs per step spent inside each system's callbacks (``SYSTEMS``), timed in a run of the
    whole Diagram by wrapping them (a timer call on either side: ~0.1 µs each)."""
    spent = {name: 0 for name in SYSTEMS}
    originals = []
    for name, (cls, methods) in SYSTEMS.items():
        for method in methods:
            if not hasattr(cls, method):
                continue
            original = getattr(cls, method)
            originals.append((cls, method, original))

            def timed(*args, _original=original, _name=name, **kwargs):
                began = time.perf_counter_ns()
                try:
                    return _original(*args, **kwargs)
                finally:
                    spent[_name] += time.perf_counter_ns() - began
            setattr(cls, method, timed)
    try:
        runner = SceneRunner(scene)
        runner.start()
        runner.advance_to(t0)
        for name in spent:
            spent[name] = 0
        runner.advance_to(t0 + span)
    finally:
        for cls, method, original in originals:
            setattr(cls, method, original)
    return {name: ns * 1e-3 / steps for name, ns in spent.items()}


def main():
    p = cli.parser(__doc__, prog="benchmarks/step_cost.py", out="optional")
    p.add_argument("--run", default="a_3", help="an entry of scenes/paper_study.yaml")
    p.add_argument("--time_step_s", type=float, default=1e-3)
    p.add_argument("--t0_s", type=float, default=4.0, help="where the measured span starts")
    p.add_argument("--span_s", type=float, default=2.0, help="simulated seconds measured")
    p.add_argument("--repeats", type=int, default=5)
    args = p.parse_args()
    if not (args.time_step_s > 0 and args.repeats >= 1 and args.span_s > 0):
        p.error("--time_step_s, --span_s must be > 0 and --repeats >= 1")
    scene = load_scene(resource("scenes/paper_study.yaml"), child=args.run,
                       scene_text=f"plant: {{time_step: {args.time_step_s!r}}}")
    steps = round(args.span_s / args.time_step_s)
    load_before = os.getloadavg()
    clocks = ("wall", "cpu")
    whole, alone = {c: [] for c in clocks}, {c: [] for c in clocks}
    for _ in range(args.repeats):  # interleaved: drift hits both alike
        times, runner = whole_diagram(scene, args.t0_s, args.span_s)
        for clock, seconds in zip(clocks, times):
            whole[clock].append(1e6 * seconds / steps)
        for clock, seconds in zip(clocks, plant_alone(scene, runner, args.span_s)):
            alone[clock].append(1e6 * seconds / steps)
    load_after = os.getloadavg()
    w = {c: statistics.median(whole[c]) for c in clocks}
    a = {c: statistics.median(alone[c]) for c in clocks}
    ratio = {c: w[c] / a[c] for c in clocks}
    split = callback_split(scene, args.t0_s, args.span_s, steps)
    print(f"{args.run} at {args.time_step_s:g} s, median of {args.repeats}, load average "
          f"{load_before[0]:.2f} before, {load_after[0]:.2f} after (this machine: "
          f"{os.cpu_count()} cores):")
    for clock in clocks:
        print(f"  {clock:4s}: whole Diagram {w[clock]:4.0f} µs/step, plant alone "
              f"{a[clock]:4.0f} µs/step, ratio {ratio[clock]:.2f}  (ratios of the repeats: "
              + " ".join(f"{x / y:.2f}" for x, y in zip(whole[clock], alone[clock])) + ")")
    print(f"  beyond the plant (CPU): {w['cpu'] - a['cpu']:.0f} µs/step, of which inside the "
          "Python systems' callbacks (wall, timed in one more run):")
    for system, us in split.items():
        print(f"    {system:30s} {us:6.1f} µs/step")
    print(f"    {'the rest':30s} {w['cpu'] - a['cpu'] - sum(split.values()):6.1f} µs/step "
          "(Drake's framework and C++ systems; the plant's step itself costs more in the whole "
          "Diagram than alone)")
    if args.out:
        with output_folder(args.out) as out:
            write_json(out / "step_cost.json", provenance(
                scene=args.run, time_step_s=args.time_step_s, load_average=[
                    load_before[0], load_after[0]], whole_us=whole, alone_us=alone,
                median_whole_us=w, median_alone_us=a, ratio=ratio, callbacks_us=split))

if __name__ == "__main__":
    main()
