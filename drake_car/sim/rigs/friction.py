"""A one-degree-of-freedom friction rig: a block on a prismatic joint over a moving belt.

The strut friction system acts on the block-belt joint with a given normal force; the block is
loaded by an external force F(t) = F0 + Ḟ·t + A·sin(2πft) (switched off after ``force_off_s``),
a spring to a fixed anchor and, if the joint is inclined, gravity.

The belt moves at a constant speed V. The plant runs in the belt's frame, which is inertial:
the belt is welded there and the spring's anchor moves at -V, so the block's position from the
anchor is x = q + V t (q the joint's position, q̇ the velocity relative to the belt): a belt
driven at exactly V. (Before, the belt was a 100 kg body held at V by a stiff SAP
servo. SAP then solved block and belt as one problem, warm-started at the last step's
velocities, and stopped before iterating when the guess met its relative tolerance, 1e-6 of
the problem's momentum, the belt's included (``systems.sap_pacer``): a net force on the block
below about 1e-6 |p| √m / dt was dropped (0.7 N at 10 µs). On the belt of
``study.rig.closed_forms`` 28, 64, 79 and 89 % of the static phase's steps were so frozen at 40,
20, 10 and 5 µs, and the explicit scheme's period, converging at 40..10 µs, moved away at 5 µs
by +0.03 %.) The reference scheme gives SAP no constraint at all, so SAP returns the
unconstrained velocities exactly; the fast scheme's PD actuators do, so its rig has the car's
SAP pacer.
"""

import dataclasses
import math

import numpy as np
from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlantConfig
from pydrake.multibody.tree import PrismaticJoint, RevoluteJoint, SpatialInertia, UnitInertia
from pydrake.math import RigidTransform
from pydrake.systems.framework import DiagramBuilder, LeafSystem
from pydrake.systems.primitives import LogVectorOutput

from drake_car.law.checks import ParameterError, finite, nonnegative, positive
from drake_car.law.friction.frd import StrutFrictionParameters, explicit_time_step_limit_s
from drake_car.sim.monitor import Monitor
from drake_car.sim.simulation import RunResult, state_columns
from drake_car.sim.slips import SlipRunner
from drake_car.systems.friction_pairs import Strut, declare_pairs
from drake_car.systems.sap_pacer import add_sap_pacer, connect_sap_pacer
from drake_car.systems.strut_friction import DIAGNOSTIC_FIELDS, StrutFriction

GRAVITY_MPS2 = 9.81
MAX_NORMAL_FORCE_N = 1e6
# The divergence monitor's check period on the rig (s).
MONITOR_PERIOD_S = 0.01


@dataclasses.dataclass
class RigOptions:
    mass_kg: float = 30.0
    normal_force_N: float = 3000.0
    force_N: float = 0.0
    force_rate_Nps: float = 0.0
    force_amp_N: float = 0.0
    force_freq_hz: float = 0.0
    force_off_s: float = math.inf
    spring_Npm: float = 0.0
    belt_speed_mps: float = 0.0
    x0_m: float = 0.0
    v0_mps: float = 0.0
    incline_deg: float = 0.0  # joint axis raised by this angle; gravity then loads the joint
    rotational: bool = False  # a revolute joint (rotation pair) instead of a prismatic one
    rod_radius_m: float = 0.011
    time_step_s: float = 1e-3
    scheme: str = "fast"
    friction: bool = True
    # Take N from the joint's reaction (eq. 4) instead of normal_force_N; for the first step,
    # before the plant has reported a reaction, use initial_normal_force_N if given.
    normal_from_reaction: bool = False
    initial_normal_force_N: float | None = None

    def check(self, params: StrutFrictionParameters | None = None):
        """Raises ParameterError naming an option out of range; with ``params``, also a step
        above the explicit (reference) scheme's stability limit on this rig."""
        positive(self, "mass_kg", "time_step_s", "rod_radius_m")
        nonnegative(self, "normal_force_N", "spring_Npm", "force_freq_hz")
        finite(self, "force_N", "force_rate_Nps", "force_amp_N", "belt_speed_mps", "x0_m",
               "v0_mps", "incline_deg")
        if not (self.force_off_s >= 0):  # inf allowed: never switched off
            raise ParameterError("force_off_s", self.force_off_s, "must be >= 0")
        if not -90 < self.incline_deg < 90:
            raise ParameterError("incline_deg", self.incline_deg, "must lie in (-90, 90)")
        if self.normal_force_N > MAX_NORMAL_FORCE_N:
            raise ParameterError("normal_force_N", self.normal_force_N,
                                 f"must be <= {MAX_NORMAL_FORCE_N:g} N (a strut's normal force "
                                 "is a few kN)")
        if self.time_step_s > 0.01:
            raise ParameterError("time_step_s", self.time_step_s, "must be <= 0.01 s")
        if self.rotational and self.belt_speed_mps != 0:
            raise ParameterError("belt_speed_mps", self.belt_speed_mps,
                                 "must be 0 for a rotational rig")
        if params is not None and self.friction and self.scheme == "reference":
            if self.rotational:  # the block's inertia: 0.1 m radius of gyration
                limit = explicit_time_step_limit_s(0.01 * self.mass_kg,
                                                   self.normal_force_N * self.rod_radius_m,
                                                   params.rotation())
            else:
                limit = explicit_time_step_limit_s(self.mass_kg, self.normal_force_N,
                                                   params.translation())
            if self.time_step_s > limit:
                raise ParameterError(
                    "time_step_s", self.time_step_s,
                    f"is above the explicit (reference) scheme's stability limit {limit:.3g} s "
                    f"on this rig (2 m Δv / (1.5 μs N), m = {self.mass_kg:g} kg, N = "
                    f"{self.normal_force_N:g} N); use a smaller step or the fast scheme")
        return self

    def anchor_distance_m(self, q, t):
        """The block's position from the spring's anchor: q + V t (the plant runs in the belt's
        frame, the belt at q = 0)."""
        return q + self.belt_speed_mps * t

    def external_force(self, t):
        if t >= self.force_off_s:
            return 0.0
        return (self.force_N + self.force_rate_Nps * t
                + self.force_amp_N * math.sin(2 * math.pi * self.force_freq_hz * t))


class RigLoad(LeafSystem):
    """Generalized force on the block's joint: F(t) - k·x, x = q + V t the block's position from
    the spring's anchor (V the belt's speed; the plant runs in the belt's frame).

    .. pydrake_system::

        name: RigLoad
        input_ports:
        - plant_state
        output_ports:
        - generalized_force
    """

    def __init__(self, plant, options: RigOptions, block_joint):
        super().__init__()
        self._options = options
        self._nv = plant.num_velocities()
        self._q_block = block_joint.position_start()
        self._v_block = block_joint.velocity_start()
        self._state_port = self.DeclareVectorInputPort("plant_state", plant.num_multibody_states())
        self.DeclareVectorOutputPort("generalized_force", self._nv, self._calc)

    def _calc(self, context, output):
        x = self._state_port.Eval(context)
        t = context.get_time()
        u = np.zeros(self._nv)
        u[self._v_block] = (self._options.external_force(t) - self._options.spring_Npm
                            * self._options.anchor_distance_m(x[self._q_block], t))
        output.SetFromVector(u)


@dataclasses.dataclass
class Rig:
    """The rig's Diagram and what the runner needs of it (``sim.simulation.Simulation``): its
    loggers (the plant's state, the friction's diagnostics, the block's net actuation), the
    monitor's checks a rig can have (a finite state, speeds below the monitor's limit), its
    initial state and its history's columns ``RIG_COLUMNS``."""

    diagram: object
    plant: object
    friction: object  # StrutFriction or None
    block_joint: object
    options: RigOptions
    loggers: dict = dataclasses.field(default_factory=dict)
    log_columns: dict = dataclasses.field(default_factory=dict)
    name = "friction rig"
    monitor_period_s = MONITOR_PERIOD_S

    @property
    def time_step_s(self):
        return self.options.time_step_s

    def monitor(self):
        # No state logger: the steps are counted by time (a window's levels', sim.resolve).
        return Monitor(self.plant, self.diagram, time_step_s=self.time_step_s)

    def history(self, logged):
        """``RIG_COLUMNS``: x_m the block's position from the spring's anchor, v_mps its
        velocity relative to the belt, the friction pair's creep, μ and phase, friction_N
        the force the plant applied (the net actuation, PD included)."""
        n = len(logged["t"])
        x = self.options.anchor_distance_m(logged[f"q_{self.block_joint.name()}"], logged["t"])
        out = {"t": logged["t"], "x_m": x, "v_mps": logged[f"v_{self.block_joint.name()}"]}
        for column, field in (("creep_m", "creep"), ("mu", "mu"), ("phase", "phase"),
                              ("friction_N", "actuation")):
            out[column] = logged[field] if self.friction is not None else np.zeros(n)
        return {c: out[c] for c in RIG_COLUMNS}

    def set_initial_state(self, root_context):
        pc = self.plant.GetMyMutableContextFromRoot(root_context)
        q = self.plant.GetPositions(pc)
        v = self.plant.GetVelocities(pc)
        q[self.block_joint.position_start()] = self.options.x0_m
        v[self.block_joint.velocity_start()] = self.options.v0_mps
        self.plant.SetPositions(pc, q)
        self.plant.SetVelocities(pc, v)


def build_rig(options: RigOptions, params: StrutFrictionParameters | None = None, *,
              record_period_s=None) -> Rig:
    """The rig's Diagram; its loggers record every ``record_period_s`` (default: every
    step)."""
    params = params or StrutFrictionParameters()
    options.check(params)
    builder = DiagramBuilder()
    plant, _ = AddMultibodyPlant(
        MultibodyPlantConfig(time_step=options.time_step_s, discrete_contact_approximation="sap"),
        builder)
    theta = math.radians(options.incline_deg)
    axis = np.array([math.cos(theta), 0.0, math.sin(theta)])
    belt_instance = plant.AddModelInstance("belt")
    block_instance = plant.AddModelInstance("block")
    belt = plant.AddRigidBody("belt", belt_instance,
                              SpatialInertia(100.0, np.zeros(3), UnitInertia(1.0, 1.0, 1.0)))
    plant.WeldFrames(plant.world_frame(), belt.body_frame(), RigidTransform())  # its own frame
    if options.rotational:
        inertia = SpatialInertia(options.mass_kg, np.zeros(3),
                                 UnitInertia(0.01, 0.01, 0.01))  # 0.1 m radius of gyration
        block = plant.AddRigidBody("block", block_instance, inertia)
        block_joint = plant.AddJoint(RevoluteJoint(
            "block_joint", belt.body_frame(), block.body_frame(), axis))
    else:
        block = plant.AddRigidBody("block", block_instance, SpatialInertia(
            options.mass_kg, np.zeros(3), UnitInertia(0.01, 0.01, 0.01)))
        block_joint = plant.AddJoint(PrismaticJoint(
            "block_joint", belt.body_frame(), block.body_frame(), axis))
    pairs = []
    if options.friction:
        pairs = declare_pairs(plant, None if options.rotational else block_joint,
                              block_joint if options.rotational else None, options.scheme,
                              prefix="rig_friction")
    # The fast scheme's PD actuators make the block a SAP constraint problem: the pacer makes
    # SAP iterate every step, as in the car (systems.sap_pacer: no frozen steps). The reference
    # scheme gives SAP no constraint at all: it returns the unconstrained velocities exactly.
    pacer = add_sap_pacer(plant) if options.friction and options.scheme == "fast" else None
    plant.Finalize()
    if pacer is not None:
        connect_sap_pacer(builder, plant, pacer)

    friction = None
    if options.friction:
        strut = Strut(pairs, rod_radius_m=options.rod_radius_m,
                      constant_normal_force_N=(None if options.normal_from_reaction
                                               else options.normal_force_N),
                      initial_normal_force_N=options.initial_normal_force_N)
        friction = builder.AddSystem(StrutFriction(plant, [strut], params,
                                                   scheme=options.scheme, name="rig_friction"))
        friction.set_name("rig_friction")
        friction.connect(builder, plant)
        builder.Connect(friction.actuation_output_port(),
                        plant.get_actuation_input_port(block_instance))
        if friction.desired_state_output_port() is not None:
            builder.Connect(friction.desired_state_output_port(),
                            plant.get_desired_state_input_port(block_instance))
    load = builder.AddSystem(RigLoad(plant, options, block_joint))
    load.set_name("rig_load")
    builder.Connect(plant.get_state_output_port(), load.GetInputPort("plant_state"))
    builder.Connect(load.get_output_port(0), plant.get_applied_generalized_force_input_port())
    loggers, columns = _add_loggers(builder, plant, friction, block_instance,
                                    record_period_s or options.time_step_s)
    diagram = builder.Build()
    diagram.set_name("friction_rig")
    return Rig(diagram, plant, friction, block_joint, options, loggers, columns)


def _add_loggers(builder, plant, friction, block_instance, period):
    """The plant's state; with friction, the pair's diagnostics (``DIAGNOSTIC_FIELDS``) and the
    block's net actuation (one actuator: the pair's)."""
    loggers = {"state": LogVectorOutput(plant.get_state_output_port(), builder, period)}
    columns = {"state": state_columns(plant)}
    if friction is not None:
        loggers["friction"] = LogVectorOutput(friction.GetOutputPort("diagnostics"), builder,
                                              period)
        columns["friction"] = list(DIAGNOSTIC_FIELDS)
        loggers["actuation"] = LogVectorOutput(
            plant.get_net_actuation_output_port(block_instance), builder, period)
        columns["actuation"] = ["actuation"]
    for group, logger in loggers.items():
        logger.set_name(f"log_{group}")
    return loggers, columns


RIG_COLUMNS = ("t", "x_m", "v_mps", "creep_m", "mu", "phase", "friction_N")


def simulate_rig(options: RigOptions, params: StrutFrictionParameters | None = None, *,
                 duration_s=1.0, record_period_s=None, progress=False):
    """Runs the rig; returns columns ``RIG_COLUMNS`` sampled every ``record_period_s``
    (default: every step). ``friction_N`` is the force the plant applied (the net actuation,
    PD included); x_m the block's position from the spring anchor; v_mps relative to the belt.
    ``run_rig`` returns how the run went too."""
    return run_rig(options, params, duration_s=duration_s, record_period_s=record_period_s,
                   progress=progress).history


def run_rig(options: RigOptions, params: StrutFrictionParameters | None = None, *,
            duration_s=1.0, record_period_s=None, progress=False, resolve=None) -> RunResult:
    """The rig on the one runner (``sim.simulation.Runner``): its history (``simulate_rig``),
    how the run went (wall and CPU time, steps) and its friction's stick-slip events.
    ``resolve``: a ``scene.simulator.ResolveEvents``: the rig's slips resolved locally, as a car's
    (``sim.resolve``: each slip of the block's pair, ``pairs: all`` for a rotational rig's, run
    in a window at halved steps, the history spliced; the windows' samples at their own steps
    where the run records every step), the result's ``resolution`` saying what it did."""
    if not (0 < duration_s <= 600):
        raise ParameterError("duration_s", duration_s, "must lie in (0, 600] s")
    if resolve is not None:
        resolve.check()
        if resolve.solver_twin:
            raise ParameterError("solver_twin", True,
                                 "must be false on the friction rig (it has no SAP ballast to "
                                 "loosen its solver's tolerance with)")
        if resolve.finest_step_s > options.time_step_s / 2:
            raise ParameterError("finest_step_s", resolve.finest_step_s,
                                 f"must be <= half the rig's step {options.time_step_s:g} s")
    rig = build_rig(options, params, record_period_s=record_period_s)
    period = record_period_s or options.time_step_s
    end = int(round(duration_s / period)) * period
    every_step = record_period_s is None or record_period_s == options.time_step_s

    def level(step_s):  # a window's level: the rig at another step, without resolution
        return RigRunner(build_rig(dataclasses.replace(options, time_step_s=step_s), params,
                                   record_period_s=None if every_step else period),
                         end_time_s=end)
    runner = RigRunner(rig, end_time_s=end, progress=progress, resolve=resolve,
                       make_level=level).run()
    return dataclasses.replace(runner.result(), events=runner.event_table(),
                               resolution=runner.resolution())


class RigRunner(SlipRunner):
    """The one runner on the rig, its friction's events kept and, with ``resolve``, its slips
    resolved locally (``sim.slips``); every pair of the rig is selected (``resolve.pairs``
    still picks translation only, or all)."""
