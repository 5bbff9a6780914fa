"""A run's state carried between two Diagrams of one scene built at different steps
(``sim.resolve``: a window resolved at a finer step and back).

A Context does not copy between Diagrams (the plant's sampled-port memory and SceneGraph's state
carry their own Diagram's identifiers), values do: ``state_values`` takes every system's
discrete state (the plant's positions and velocities, the strut friction's creep, phases,
targets, gains and event log, the tyres' relaxation state and forces of the next step) and the
time; ``set_state`` writes them into the other Diagram by system name and group, writes the
model values the friction and the hands-off schedule keep in the plant (PD gains, effort
limits: a forced publish, as ``sim.branch`` does) and re-initializes its simulator without the
initialization events. Into a Diagram of the same step this is exact: the continued run equals
the run that never left, bit for bit (``tests/test_resolve.py``). The plant's sampled outputs
need no copy: every system that reads them (the friction's reactions, the driveshafts' torque)
does so in its update, after the plant's step has refreshed them.

What does not carry over as a value is the constraints' violation. SAP holds a ball constraint
(the ball joints and tie rods closing the car's loops) as a near-rigid spring whose stiffness
scales with m/dt², so under a steady load its violation scales with dt² (measured on the car: 2.8
µm at 1 ms). The same positions fed to a step four times finer carry sixteen times the force in
its first step: a kick that raised a strut's normal force by 10 % and spun the rods to 500 Δv
(a break-away no run has). ``set_state`` therefore sets each constraint's violation to
(dt_to / dt_from)² times its value, by the smallest change of the positions in the mass metric
(Newton on the constraints' Jacobian, two iterations), and shifts the friction's record of the
pairs' positions by their part of that change (it is no motion of the pairs: no creep, no PD
error). With it the finer run continues the coarser one without a kick (the rods' velocities
change by < 0.01 Δv over the first steps).
"""

import dataclasses

import numpy as np
from pydrake.multibody.tree import JacobianWrtVariable
from pydrake.systems.analysis import InitializeParams

from drake_car.model.car import loop_closure_frames
from drake_car.systems.gain_schedule import GainSchedule
from drake_car.systems.strut_friction import StrutFriction

NEWTON_ITERATIONS = 2


@dataclasses.dataclass
class StateValues:
    """A Diagram's state as values: the time (s), system name -> its discrete state groups,
    the step (s) of the Diagram they were taken from, and its plant's state names (positions,
    then velocities: a Diagram whose plant has a body more, the SAP ballast, takes them by
    name)."""

    time_s: float
    groups: dict
    step_s: float
    plant_names: tuple = ()
    sap_factor: float = 1.0  # the Diagram's SAP tolerance factor (``systems.sap_ballast``)


def state_values(built, root) -> StateValues:
    """Every system's discrete state of ``built``'s Diagram in ``root`` (copies)."""
    groups = {}
    for system in built.diagram.GetSystems():
        context = system.GetMyContextFromRoot(root)
        count = context.num_discrete_state_groups()
        if count:
            groups[system.get_name()] = [context.get_discrete_state(i).get_value().copy()
                                         for i in range(count)]
    plant = built.plant
    return StateValues(root.get_time(), groups, built.time_step_s,
                       tuple(plant.GetPositionNames()) + tuple(plant.GetVelocityNames()),
                       _sap_factor(built))


def set_state(built, simulator, values: StateValues):
    """``values`` into ``built``'s Diagram (its simulator's root context), the constraints'
    violation set to this Diagram's step, the model values written, the simulator initialized
    without initialization events. ``built``: a ``sim.simulation.Simulation`` (the car's
    Diagram, the friction rig's); a plant without constraints (the rig's) has no violation to
    set."""
    root = simulator.get_mutable_context()
    root.SetTime(values.time_s)
    for system in built.diagram.GetSystems():
        groups = values.groups.get(system.get_name())
        if groups is None:
            continue
        context = system.GetMyMutableContextFromRoot(root)
        if system is built.plant:
            groups = _plant_groups(built.plant, context, groups, values.plant_names)
        if context.num_discrete_state_groups() != len(groups):
            raise ValueError(f"set_state: system {system.get_name()} has "
                             f"{context.num_discrete_state_groups()} discrete state groups, "
                             f"the values {len(groups)}")
        for i, value in enumerate(groups):
            context.SetDiscreteState(i, value)
    ratio = built.time_step_s / values.step_s
    if ratio != 1.0 and built.plant.num_constraints():  # the car's loop closures
        scale_constraint_violation(built, root, ratio ** 2)
    if _sap_factor(built) != values.sap_factor:  # into another tolerance: the solver twin
        _follow_ballast(built, root)
    for system in built.diagram.GetSystems():
        if isinstance(system, (GainSchedule, StrutFriction)):
            system.ForcedPublish(system.GetMyContextFromRoot(root))
    simulator.Initialize(InitializeParams(suppress_initialization_events=True))


def _plant_groups(plant, context, groups, names):
    """The plant's state ``groups`` (from a plant with state ``names``) as this plant takes
    them: as they are where the names agree; else by name, this plant's other entries (the
    SAP ballast's joint: ``systems.sap_ballast``) zero (its velocity is then set to its
    target: ``_follow_ballast``)."""
    mine = tuple(plant.GetPositionNames()) + tuple(plant.GetVelocityNames())
    if not names or names == mine:
        return groups
    missing = sorted(set(names) - set(mine))
    if missing:
        raise ValueError(f"set_state: the plant has no state entries {missing[:3]}; a state "
                         "moves only between Diagrams of one car")
    if len(groups) != 1:
        raise ValueError(f"set_state: the plant's state comes in {len(groups)} groups; by name "
                         "only one is moved")
    value = np.zeros(context.get_discrete_state(0).size())
    where = {name: k for k, name in enumerate(mine)}
    for k, name in enumerate(names):
        value[where[name]] = groups[0][k]
    return [value]


def _sap_factor(built):
    """The SAP tolerance factor ``built``'s Diagram was built with (1: no ballast)."""
    scene = getattr(built, "scene", None)
    return scene.simulator.sap_tolerance_factor if scene is not None else 1.0


def _follow_ballast(built, root):
    """The SAP ballast's velocity (if the Diagram has one) set to its target from the car's
    state: its PD actuator holds it there (``systems.sap_ballast``), so the run continues as
    if it had always been loosened, without a first step spent catching up."""
    diagram = built.diagram
    if not diagram.HasSubsystemNamed("sap_ballast_target"):
        return
    target = diagram.GetSubsystemByName("sap_ballast_target")
    velocity = target.get_output_port().Eval(target.GetMyContextFromRoot(root))[1]
    plant = built.plant
    context = plant.GetMyMutableContextFromRoot(root)
    joint = plant.GetJointByName("sap_ballast")
    v = plant.GetVelocities(context)
    v[joint.velocity_start()] = velocity
    plant.SetVelocities(context, v)


def constraint_violation(built, plant_context):
    """The loop closures' violations p_B - p_A, stacked (m)."""
    plant = built.plant
    world = plant.world_frame()
    return np.concatenate([
        plant.CalcPointsPositions(plant_context, b, np.zeros(3), world)[:, 0]
        - plant.CalcPointsPositions(plant_context, a, np.zeros(3), world)[:, 0]
        for a, b in loop_closure_frames(built.car)])


def scale_constraint_violation(built, root, scale):
    """Sets the loop closures' violation to ``scale`` times its value in ``root`` (see the
    module), the friction's record of its pairs' positions shifted with them."""
    plant = built.plant
    frames = loop_closure_frames(built.car)
    if plant.num_constraints() != len(frames):
        raise ValueError(f"set_state: the plant has {plant.num_constraints()} constraints, of "
                         f"which {len(frames)} are the car's loop closures; a state moves "
                         "between steps only with those")
    context = plant.GetMyMutableContextFromRoot(root)
    world = plant.world_frame()
    origin = np.zeros(3)
    target = scale * constraint_violation(built, context)
    q0 = plant.GetPositions(context)
    for _ in range(NEWTON_ITERATIONS):
        residual = target - constraint_violation(built, context)
        jacobian = np.vstack([
            plant.CalcJacobianTranslationalVelocity(context, JacobianWrtVariable.kV, b, origin,
                                                    world, world)
            - plant.CalcJacobianTranslationalVelocity(context, JacobianWrtVariable.kV, a,
                                                      origin, world, world)
            for a, b in frames])
        # The smallest change in the mass metric: dv = M⁻¹Jᵀ (J M⁻¹ Jᵀ)⁻¹ r.
        m_inv_jt = np.linalg.solve(plant.CalcMassMatrix(context), jacobian.T)
        dv = m_inv_jt @ np.linalg.solve(jacobian @ m_inv_jt, residual)
        plant.SetPositions(context, plant.GetPositions(context)
                           + plant.MapVelocityToQDot(context, dv))
    moved = plant.GetPositions(context) - q0
    for system in built.diagram.GetSystems():
        if isinstance(system, StrutFriction):
            system.shift_positions(system.GetMyMutableContextFromRoot(root),
                                   moved[system.position_indices()])
