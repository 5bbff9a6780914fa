"""A one-degree-of-freedom friction rig: a block on a prismatic joint over a moving belt.

The strut friction system acts on the block-belt joint with a given normal force; the block is
loaded by an external force F(t) = F0 + Ḟ·t + A·sin(2πft) (switched off after ``force_off_s``),
a spring to a fixed anchor and, if the joint is inclined, gravity. The belt moves at constant
speed (a stiff SAP servo), or is welded to the world when its speed is zero.
"""

import dataclasses
import math

import numpy as np
from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlantConfig
from pydrake.multibody.tree import (
    PdControllerGains, PrismaticJoint, RevoluteJoint, SpatialInertia, UnitInertia)
from pydrake.math import RigidTransform
from pydrake.systems.framework import DiagramBuilder, LeafSystem
from pydrake.systems.primitives import LogVectorOutput

from drake_car.law.checks import ParameterError, finite, nonnegative, positive
from drake_car.law.friction.frd import StrutFrictionParameters, explicit_time_step_limit_s
from drake_car.sim.monitor import Monitor
from drake_car.sim.simulation import Runner, RunResult, state_columns
from drake_car.systems.friction_pairs import Strut, declare_pairs
from drake_car.systems.strut_friction import DIAGNOSTIC_FIELDS, StrutFriction

GRAVITY_MPS2 = 9.81
MAX_NORMAL_FORCE_N = 1e6
# The belt's speed servo (SAP PD, implicit, on the 100 kg belt): stiff enough that the belt's
# lag under a friction load F, F/p, and its speed dip under a load change ΔF, ~ΔF/d, are
# far below the friction's own scales (Δmax, Δv): 120 N gives 0.12 µm and 1e-6 m/s.
BELT_SERVO_P = 1e9
BELT_SERVO_D = 1e8
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

    def external_force(self, t):
        if t >= self.force_off_s:
            return 0.0
        return (self.force_N + self.force_rate_Nps * t
                + self.force_amp_N * math.sin(2 * math.pi * self.force_freq_hz * t))


class RigLoad(LeafSystem):
    """Generalized force on the block's joint: F(t) - k·x_world (+ nothing else).

    .. pydrake_system::

        name: RigLoad
        input_ports:
        - plant_state
        output_ports:
        - generalized_force
    """

    def __init__(self, plant, options: RigOptions, block_joint, belt_joint):
        super().__init__()
        self._options = options
        self._nv = plant.num_velocities()
        self._q_block = block_joint.position_start()
        self._v_block = block_joint.velocity_start()
        self._q_belt = None if belt_joint is None else belt_joint.position_start()
        self._state_port = self.DeclareVectorInputPort("plant_state", plant.num_multibody_states())
        self.DeclareVectorOutputPort("generalized_force", self._nv, self._calc)

    def _calc(self, context, output):
        x = self._state_port.Eval(context)
        position = x[self._q_block] + (0.0 if self._q_belt is None else x[self._q_belt])
        u = np.zeros(self._nv)
        u[self._v_block] = (self._options.external_force(context.get_time())
                            - self._options.spring_Npm * position)
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
    belt_joint: object
    options: RigOptions
    loggers: dict = dataclasses.field(default_factory=dict)
    log_columns: dict = dataclasses.field(default_factory=dict)
    name = "friction rig"
    monitor_period_s = MONITOR_PERIOD_S

    @property
    def time_step_s(self):
        return self.options.time_step_s

    def monitor(self):
        return Monitor(self.plant, self.diagram)

    def history(self, logged):
        """``RIG_COLUMNS``: x_m the block's position from the spring's anchor, v_mps its
        velocity relative to the belt, the friction pair's creep, μ and phase, friction_N
        the force the plant applied (the net actuation, PD included)."""
        n = len(logged["t"])
        x = logged[f"q_{self.block_joint.name()}"] + (
            0.0 if self.belt_joint is None else logged[f"q_{self.belt_joint.name()}"])
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
        if self.belt_joint is not None:
            v[self.belt_joint.velocity_start()] = self.options.belt_speed_mps
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
    belt_joint = None
    if options.belt_speed_mps != 0:
        belt_joint = plant.AddJoint(PrismaticJoint(
            "belt_slide", plant.world_frame(), belt.body_frame(), axis))
        servo = plant.AddJointActuator("belt_servo", belt_joint)
        servo.set_controller_gains(PdControllerGains(p=BELT_SERVO_P, d=BELT_SERVO_D))
    else:
        plant.WeldFrames(plant.world_frame(), belt.body_frame(), RigidTransform())
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
    plant.Finalize()

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
    load = builder.AddSystem(RigLoad(plant, options, block_joint, belt_joint))
    load.set_name("rig_load")
    builder.Connect(plant.get_state_output_port(), load.GetInputPort("plant_state"))
    builder.Connect(load.get_output_port(0), plant.get_applied_generalized_force_input_port())
    if belt_joint is not None:
        belt_command = builder.AddSystem(_BeltCommand(options.belt_speed_mps))
        builder.Connect(belt_command.get_output_port(0),
                        plant.get_desired_state_input_port(belt_instance))
    loggers, columns = _add_loggers(builder, plant, friction, block_instance,
                                    record_period_s or options.time_step_s)
    diagram = builder.Build()
    diagram.set_name("friction_rig")
    return Rig(diagram, plant, friction, block_joint, belt_joint, options, loggers, columns)


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


class _BeltCommand(LeafSystem):
    """Desired belt state [v·t, v]."""

    def __init__(self, speed):
        super().__init__()
        self._speed = speed
        self.DeclareVectorOutputPort("belt_desired_state", 2, self._calc)

    def _calc(self, context, output):
        t = context.get_time()
        output.SetFromVector([self._speed * t, self._speed])


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
            duration_s=1.0, record_period_s=None, progress=False) -> RunResult:
    """The rig on the one runner (``sim.simulation.Runner``): its history (``simulate_rig``)
    and how the run went (wall and CPU time, steps)."""
    if not (0 < duration_s <= 600):
        raise ParameterError("duration_s", duration_s, "must lie in (0, 600] s")
    rig = build_rig(options, params, record_period_s=record_period_s)
    period = record_period_s or options.time_step_s
    end = int(round(duration_s / period)) * period
    return Runner(rig, end_time_s=end, progress=progress).run().result()
