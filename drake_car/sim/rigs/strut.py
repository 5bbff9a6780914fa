"""The strut side-load friction rig: the car's own front strut, alone, on the industry's strut
friction test (the paper's ref. [16]: the strut clamped at its top, the knuckle loaded with a
constant side force, the rod stroked sinusoidally, the axial force read by a load cell).

The strut is the car's (``model.parameters.FrontSuspensionParameters``): the piston rod hangs
from the top mount, the guide ``guide_below_top_mount_m`` below it, the guide length (the
overlap at the design position) ``l``, the rod radius ``r``; the cylindrical pair is the car's
(rod -revolute- slider -prismatic- knuckle, both about the strut axis, joint frames at the
guide, q the rod's extension from the design position) and its friction is the car's
``StrutFriction`` with the normal force from the prismatic joint's reaction (eq. 4), exactly as
``model.struts.make_strut_friction`` wires it in the car. The rig's frame: z up along the strut
axis, the top mount at the origin. No gravity (the rig is tared).

Loads on the knuckle:

- the side force ``side_force_N`` along +x, constant in the rig's frame, at the point of the
  strut axis ``side_force_point_below_top_m`` below the top mount (default: the strut's lower
  mount, where a rig's lever clamps the knuckle; ``at_rest.StrutAtRest.rig_options`` loads
  it as the car's strut at rest: the car's transverse strut force at the top mount).
  ``corner_side_force_N`` is the closed form of a corner's tyre share (the car's b);
- the stroke actuator through the rig's compliance: a load cell and fixtures of stiffness
  ``rig_stiffness_Npm`` and damping ``rig_damping_Nspm`` between the knuckle and the actuator's
  position x_a(t) = A sin(2π f t); the load cell reads F = k (x_a - q) + c (ẋ_a - q̇), the
  axial force a rig measures (friction plus the knuckle's inertia);
- optionally the rod's rotation: a torsional actuator of stiffness ``rig_torsion_Nm_per_rad``
  driving the knuckle's rotation about the strut axis to θ_a(t) = A_θ sin(2π f_θ t)
  (zero amplitude: the knuckle held at 0 through the same torsion spring).

The compliance is what lets a rig show the break-away: at a reversal the knuckle sticks while
the actuator winds up the load cell until μs·N, then slips to μd·N.
"""

import dataclasses
import math

import numpy as np
from pydrake.common.value import Value
from pydrake.math import RigidTransform
from pydrake.multibody.math import SpatialForce
from pydrake.multibody.plant import (
    AddMultibodyPlant, ExternallyAppliedSpatialForce, MultibodyPlantConfig)
from pydrake.multibody.tree import PrismaticJoint, RevoluteJoint, SpatialInertia, UnitInertia
from pydrake.systems.framework import DiagramBuilder, LeafSystem
from pydrake.systems.primitives import LogVectorOutput

from drake_car.law.checks import ParameterError, finite, nonnegative, positive
from drake_car.law.friction.frd import StrutFrictionParameters, normal_force
from drake_car.model.parameters import CarParameters
from drake_car.model.struts import strut_geometry
from drake_car.sim.monitor import Monitor
from drake_car.sim.simulation import Runner, RunResult, state_columns
from drake_car.systems.friction_pairs import Strut, declare_pairs
from drake_car.systems.strut_friction import DIAGNOSTIC_FIELDS, StrutFriction

MAX_SIDE_FORCE_N = 2e4  # ~5 g on a front corner's load: beyond any strut rig
# [EST] beyond any strut's knuckle (the shipped car's lower mount is 0.47 m, its ball joint
# 0.59 m below the top mount along the axis: docs/findings/car_checks.md's points)
MAX_SIDE_FORCE_POINT_BELOW_TOP_M = 1.0
MAX_STROKE_AMPLITUDE_M = 0.05
MAX_DURATION_S = 600.0
MONITOR_PERIOD_S = 0.01  # the divergence monitor's check period on the rig (s)


@dataclasses.dataclass
class StrutRigOptions:
    side_force_N: float = 1000.0
    side_force_point_below_top_m: float | None = None  # None: the strut's lower mount
    stroke_amplitude_m: float = 0.01
    stroke_frequency_hz: float = 0.5
    rotation_amplitude_rad: float = 0.0
    rotation_frequency_hz: float = 0.5
    # [EST] a servo-hydraulic strut rig's load path (load cell, fixtures, clamp): 2e6 N/m with
    # a damping ratio of ~0.3 on the 13 kg knuckle (c = 0.6 sqrt(k m) ≈ 3000 N s/m); it sets how
    # fast the force builds at a reversal, not the friction levels.
    rig_stiffness_Npm: float = 2e6
    rig_damping_Nspm: float = 3000.0
    # [EST] the torsional load path: 2e4 N m/rad, damping ratio ~0.3 on the knuckle's spin.
    rig_torsion_Nm_per_rad: float = 2e4
    rig_torsion_damping_Nms: float = 30.0
    time_step_s: float = 1e-3
    scheme: str = "fast"
    rotation: bool = True  # the rotation pair's friction (as the car's translation_rotation)

    def check(self, front):
        finite(self, "side_force_N", "stroke_amplitude_m", "rotation_amplitude_rad")
        positive(self, "stroke_frequency_hz", "rotation_frequency_hz", "rig_stiffness_Npm",
                 "rig_torsion_Nm_per_rad", "time_step_s")
        nonnegative(self, "rig_damping_Nspm", "rig_torsion_damping_Nms")
        if abs(self.side_force_N) > MAX_SIDE_FORCE_N:
            raise ParameterError("side_force_N", self.side_force_N,
                                 f"must lie in [-{MAX_SIDE_FORCE_N:g}, {MAX_SIDE_FORCE_N:g}] N")
        limit = stroke_limit_m(front)
        if abs(self.stroke_amplitude_m) > limit:
            raise ParameterError("stroke_amplitude_m", self.stroke_amplitude_m,
                                 f"must lie in [-{limit:g}, {limit:g}] m (the rod leaves its "
                                 f"guide of l = {front.guide_length_l_m} m)")
        if abs(self.rotation_amplitude_rad) > math.pi / 2:
            raise ParameterError("rotation_amplitude_rad", self.rotation_amplitude_rad,
                                 "must lie in [-π/2, π/2] rad")
        if self.time_step_s > 2e-3:
            raise ParameterError("time_step_s", self.time_step_s,
                                 "must be <= 2 ms (the rig's 390 rad/s load path is explicit)")
        if self.scheme not in ("fast", "reference"):
            raise ParameterError("scheme", self.scheme, "must be fast or reference")
        point = self.side_force_point(front)
        if not 0 <= point <= MAX_SIDE_FORCE_POINT_BELOW_TOP_M:
            raise ParameterError("side_force_point_below_top_m", point,
                                 f"must lie in [0, {MAX_SIDE_FORCE_POINT_BELOW_TOP_M:g}] m")
        return self

    def side_force_point(self, front):
        if self.side_force_point_below_top_m is None:
            return front.strut_lower_mount_below_top_m
        return self.side_force_point_below_top_m

    def stroke(self, t):
        """The actuator's position and velocity (m, m/s)."""
        w = 2 * math.pi * self.stroke_frequency_hz
        return (self.stroke_amplitude_m * math.sin(w * t),
                self.stroke_amplitude_m * w * math.cos(w * t))

    def twist(self, t):
        w = 2 * math.pi * self.rotation_frequency_hz
        return (self.rotation_amplitude_rad * math.sin(w * t),
                self.rotation_amplitude_rad * w * math.cos(w * t))


def stroke_limit_m(front):
    """The largest stroke the rig runs the strut at: the rod stays in its guide (the overlap
    d = l - q above a quarter of l), and at most MAX_STROKE_AMPLITUDE_M."""
    return min(MAX_STROKE_AMPLITUDE_M, 0.75 * front.guide_length_l_m)


def corner_side_force_N(front, vertical_load_N, lateral_load_N=0.0):
    """The side force at the top mount (``side_force_point_below_top_m = 0``) that loads the
    strut as a corner's wheel loads do: the knuckle's moment balance about the ball joint,
    F = (Fz b + Fy h_bj) / (h_top - h_bj), Fz the vertical road reaction at the lateral offset b
    (the paper's Fig. 4), Fy the lateral tyre force at the ground (outward +), h_bj and h_top the
    ball joint's and the top mount's heights. The spring is taken on a line through the ball
    joint, the lower arm as carrying no moment. It is the tyre's share alone: the car's own
    strut load at rest (``at_rest.strut_at_rest``, measured in the settled car) adds the
    spring's line (+155 N on the shipped car, whose spring runs along the strut axis, not
    through the ball joint), the tie rod and the unsprung weights: 642.5 N against 520.7 N."""
    lever = front.top_mount_height_m - front.ball_joint_height_m
    return (vertical_load_N * front.ball_joint_offset_b_m
            + lateral_load_N * front.ball_joint_height_m) / lever


def eq4_normal_force_N(front, options: StrutRigOptions, stroke_m=0.0):
    """Eq. (4)'s vector form for the rig, quasi-static: the reaction is -F (transverse) and the
    moment about the overlap's middle F·a, a the side force's lever to that middle, d = l - q;
    F ⊥ M, so N = |M/d + F| = |F| sqrt(1 + (a/d)²) (the magnitude sum would be |F| (1 + a/d))."""
    d = front.guide_length_l_m - stroke_m
    middle = front.guide_below_top_mount_m + stroke_m + 0.5 * d  # below the top mount
    lever = options.side_force_point(front) + stroke_m - middle
    return abs(options.side_force_N) * math.sqrt(1.0 + (lever / d) ** 2)


def rest_normal_force_N(front, options: StrutRigOptions, law: StrutFrictionParameters):
    """The strut's normal force at rest at the design position, as the friction computes it
    (eq. 4 in the law's form, its preload): the reaction on the knuckle is -F along x and the
    moment F·a about the overlap's middle (``eq4_normal_force_N``), the joint's axis -z. The
    friction starts with it: before the plant's first step there is no reaction to read, and
    the side force acts from t = 0 (with N = 0 the first step slipped, friction-free)."""
    d = front.guide_length_l_m
    lever = options.side_force_point(front) - (front.guide_below_top_mount_m + 0.5 * d)
    force = options.side_force_N
    return normal_force((-force, 0.0, 0.0), (0.0, force * lever, 0.0), d,
                        law.preload_force_N, law.mu_s, law.normal_force_form,
                        axis=(0.0, 0.0, -1.0))


class RigLoads(LeafSystem):
    """The actuators through the load path and the side force.

    .. pydrake_system::

        name: RigLoads
        input_ports:
        - plant_state
        output_ports:
        - generalized_force
        - side_force
    """

    def __init__(self, plant, options, prismatic, revolute, knuckle, point_below_guide_m):
        super().__init__()
        self._options = options
        self._nv = plant.num_velocities()
        self._nq = plant.num_positions()
        self._qp, self._vp = prismatic.position_start(), prismatic.velocity_start()
        self._qr, self._vr = revolute.position_start(), revolute.velocity_start()
        self._state_port = self.DeclareVectorInputPort("plant_state", plant.num_multibody_states())
        self.DeclareVectorOutputPort("generalized_force", self._nv, self._calc_force)
        force = ExternallyAppliedSpatialForce()
        force.body_index = knuckle.index()
        force.p_BoBq_B = [0.0, 0.0, -point_below_guide_m]  # the knuckle's frame is at the guide
        force.F_Bq_W = SpatialForce([0.0, 0.0, 0.0], [options.side_force_N, 0.0, 0.0])
        self._side = [force]
        self.DeclareAbstractOutputPort(
            "side_force", lambda: Value[list[ExternallyAppliedSpatialForce]](),
            self._calc_side)

    def load_cell(self, t, x):
        """(axial force N, torsional moment N·m) the actuators apply to the knuckle."""
        o = self._options
        xa, va = o.stroke(t)
        ta, wa = o.twist(t)
        q, v = x[self._qp], x[self._nq + self._vp]
        th, w = x[self._qr], x[self._nq + self._vr]
        return (o.rig_stiffness_Npm * (xa - q) + o.rig_damping_Nspm * (va - v),
                o.rig_torsion_Nm_per_rad * (ta - th) + o.rig_torsion_damping_Nms * (wa - w))

    def _calc_force(self, context, output):
        axial, moment = self.load_cell(context.get_time(), self._state_port.Eval(context))
        u = np.zeros(self._nv)
        u[self._vp] = axial
        u[self._vr] = moment
        output.SetFromVector(u)

    def _calc_side(self, context, output):
        output.set_value(self._side)


@dataclasses.dataclass
class StrutRig:
    """The rig's Diagram and what the runner needs of it (``sim.simulation.Simulation``): its
    loggers (the plant's state every step; with dry friction the translation pair's
    diagnostics and the pairs' net actuation), the monitor's checks a rig can have (a finite
    state, speeds below the monitor's limit) and its history's columns ``RIG_COLUMNS``. It
    starts at the design position, at rest."""

    diagram: object
    plant: object
    friction: object
    loads: RigLoads
    prismatic: object
    revolute: object
    options: StrutRigOptions = None
    loggers: dict = dataclasses.field(default_factory=dict)
    log_columns: dict = dataclasses.field(default_factory=dict)
    name = "strut rig"
    monitor_period_s = MONITOR_PERIOD_S

    @property
    def time_step_s(self):
        return self.options.time_step_s

    def monitor(self):
        return Monitor(self.plant, self.diagram)

    def set_initial_state(self, root_context):
        pass  # the design position, at rest: the plant's default

    def history(self, logged):
        """``RIG_COLUMNS`` (``simulate_strut_rig``) from the logged state, diagnostics and
        actuation."""
        t = logged["t"]
        n = len(t)
        names = self.log_columns["state"]
        x = np.array([logged[name] for name in names])  # [q; v] per sample
        nq = self.plant.num_positions()
        qp, vp = self.prismatic.position_start(), self.prismatic.velocity_start()
        out = {c: np.zeros(n) for c in RIG_COLUMNS}
        out["t"] = t
        for k in range(n):
            # The force the actuators applied over the step that ended at t_k: from the
            # state at its start, the sample before (the first sample: its own).
            out["load_cell_N"][k], out["torsion_Nm"][k] = self.loads.load_cell(
                t[max(k - 1, 0)], x[:, max(k - 1, 0)])
            out["actuator_m"][k] = self.options.stroke(t[k])[0]
        out["stroke_m"] = x[qp].copy()
        out["velocity_mps"] = x[nq + vp].copy()
        out["angle_rad"] = x[self.revolute.position_start()].copy()
        if self.friction is None:
            out["friction_N"] = -self.prismatic.default_damping() * x[nq + vp]
            return out
        # The actuators are in the friction pairs' order: translation, then rotation.
        out["friction_N"] = logged["actuation_0"]
        if "actuation_1" in logged:
            out["friction_moment_Nm"] = logged["actuation_1"]
        for column, field in (("normal_N", "N"), ("mu", "mu"), ("phase", "phase")):
            out[column] = logged[field]  # the translation pair's (the first)
        return out


def build_strut_rig(car: CarParameters, options: StrutRigOptions,
                    law: StrutFrictionParameters | None) -> StrutRig:
    """The rig's Diagram; ``law`` None: the lubricated strut (the car's viscous damping in the
    prismatic joint, no dry friction)."""
    front, mass = car.front, car.mass
    options.check(front)
    builder = DiagramBuilder()
    plant, _ = AddMultibodyPlant(
        MultibodyPlantConfig(time_step=options.time_step_s, discrete_contact_approximation="sap"),
        builder)
    plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, 0.0])
    instance = plant.AddModelInstance("strut")
    guide = RigidTransform([0.0, 0.0, -front.guide_below_top_mount_m])
    rod = plant.AddRigidBody("piston_rod", instance, SpatialInertia(
        mass.piston_rod_kg, np.zeros(3), UnitInertia(0.01, 0.01, 1e-4)))
    plant.WeldFrames(plant.world_frame(), rod.body_frame(), RigidTransform())
    slider = plant.AddRigidBody("strut_slider", instance, SpatialInertia(
        mass.strut_slider_kg, np.zeros(3), UnitInertia(1e-4, 1e-4, 1e-4)))
    # [EST] the knuckle's spin inertia about the strut axis: 0.3 kg m² (13 kg at ~0.15 m).
    knuckle = plant.AddRigidBody("knuckle", instance, SpatialInertia(
        mass.front_knuckle_kg, np.zeros(3), UnitInertia(0.03, 0.03, 0.3 / 13.0)))
    rod_guide = plant.AddFrame(_fixed("rod_guide", rod, guide))
    revolute = plant.AddJoint(RevoluteJoint("strut_revolute", rod_guide, slider.body_frame(),
                                            [0.0, 0.0, 1.0]))
    damping = front.strut_damping_Nspm if law is None or law.mu_s == 0 else 0.0
    prismatic = plant.AddJoint(PrismaticJoint("strut_prismatic", slider.body_frame(),
                                              knuckle.body_frame(), [0.0, 0.0, -1.0],
                                              damping=damping))
    dry = law is not None and law.mu_s > 0
    pairs = []
    if dry:
        pairs = declare_pairs(plant, prismatic, revolute if options.rotation else None,
                              options.scheme, prefix="strut_friction")
    plant.Finalize()
    friction = None
    if dry:
        strut = Strut(pairs, **strut_geometry(front),
                      initial_normal_force_N=rest_normal_force_N(front, options, law))
        friction = builder.AddSystem(StrutFriction(plant, [strut], law, scheme=options.scheme,
                                                   name="strut_friction"))
        friction.connect(builder, plant)
        builder.Connect(friction.actuation_output_port(), plant.get_actuation_input_port(instance))
        if friction.desired_state_output_port() is not None:
            builder.Connect(friction.desired_state_output_port(),
                            plant.get_desired_state_input_port(instance))
    below_guide = options.side_force_point(front) - front.guide_below_top_mount_m
    loads = builder.AddSystem(RigLoads(plant, options, prismatic, revolute, knuckle, below_guide))
    loads.set_name("rig_loads")
    builder.Connect(plant.get_state_output_port(), loads.GetInputPort("plant_state"))
    builder.Connect(loads.GetOutputPort("generalized_force"),
                    plant.get_applied_generalized_force_input_port())
    builder.Connect(loads.GetOutputPort("side_force"),
                    plant.get_applied_spatial_force_input_port())
    loggers, columns = _add_loggers(builder, plant, friction, instance, options.time_step_s)
    diagram = builder.Build()
    diagram.set_name("strut_rig")
    return StrutRig(diagram, plant, friction, loads, prismatic, revolute, options, loggers,
                    columns)


def _add_loggers(builder, plant, friction, instance, period):
    """The plant's state; with dry friction the pairs' diagnostics (the translation pair's
    fields first) and the strut's net actuation (the pairs' actuators)."""
    loggers = {"state": LogVectorOutput(plant.get_state_output_port(), builder, period)}
    columns = {"state": state_columns(plant)}
    if friction is not None:
        loggers["friction"] = LogVectorOutput(friction.GetOutputPort("diagnostics"), builder,
                                              period)
        columns["friction"] = [f"{name}_{k}" if k else name for k in range(friction.num_pairs())
                               for name in DIAGNOSTIC_FIELDS]
        loggers["actuation"] = LogVectorOutput(plant.get_net_actuation_output_port(instance),
                                               builder, period)
        columns["actuation"] = [f"actuation_{k}" for k in range(plant.num_actuators(instance))]
    for group, logger in loggers.items():
        logger.set_name(f"log_{group}")
    return loggers, columns


def _fixed(name, body, pose):
    from pydrake.multibody.tree import FixedOffsetFrame
    return FixedOffsetFrame(name, body.body_frame(), pose)


RIG_COLUMNS = ("t", "actuator_m", "stroke_m", "velocity_mps", "load_cell_N", "friction_N",
               "normal_N", "mu", "phase", "angle_rad", "torsion_Nm", "friction_moment_Nm")


def simulate_strut_rig(car: CarParameters, options: StrutRigOptions,
                       law: StrutFrictionParameters | None, *, cycles=2.0, progress=False):
    """Runs ``cycles`` stroke periods; returns ``RIG_COLUMNS`` sampled every step.
    ``load_cell_N``: the axial force the actuator applied over the step that ended at t (from
    the state at its start: what the knuckle felt, as ``friction_N`` is; the peak at a
    break-away is then the load that broke the strut free, at most one step's load increase
    above μs·N); ``friction_N``: the friction force on the knuckle from the
    system (the actuators' net actuation; the lubricated strut's -c q̇); ``normal_N``, ``mu``,
    ``phase``: the translation pair's diagnostics; ``torsion_Nm`` and ``friction_moment_Nm``
    the same about the axis. ``run_strut_rig`` returns how the run went too."""
    return run_strut_rig(car, options, law, cycles=cycles, progress=progress).history


def run_strut_rig(car: CarParameters, options: StrutRigOptions,
                  law: StrutFrictionParameters | None, *, cycles=2.0,
                  progress=False) -> RunResult:
    """The rig on the one runner (``sim.simulation.Runner``): its history
    (``simulate_strut_rig``) and how the run went (wall and CPU time, steps)."""
    duration = cycles / options.stroke_frequency_hz
    if not (0 < duration <= MAX_DURATION_S):
        raise ParameterError("cycles", cycles,
                             f"make a run of {duration:g} s; it must lie in (0, "
                             f"{MAX_DURATION_S:g}] s")
    rig = build_strut_rig(car, options, law)
    end = int(round(duration / options.time_step_s)) * options.time_step_s
    return Runner(rig, end_time_s=end, progress=progress).run().result()
