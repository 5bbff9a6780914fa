"""The paper's FRD friction on a cylindrical (prismatic + revolute) pair, as a LeafSystem.

The law itself lives in ``drake_car.law.frd_friction``; this system feeds it from the plant
(joint velocities and displacements, the joint's reaction force and moment) and keeps the creep
as discrete state.

Two numerical schemes (``scheme``):

``reference``
    The law exactly as stated, applied explicitly: at each step the friction force is
    μ(v_k, Δ_k)·N_k from the state at the start of the step and goes in as a joint actuation.
    Explicit application of the stiff static-phase law (slopes μs·N/Δv ≈ 10⁷ N·s/m,
    μs·N/Δmax ≈ 10⁸ N/m) is stable only at tiny steps (dt ≲ 2·m/(μs·N/Δv), ~10 µs in the car);
    this is the scheme to converge to.

``fast``
    The law linearised about the state at the start of the step with a *fixed, over-estimated*
    Jacobian, solved implicitly inside Drake's SAP step (a linearly implicit "W-method" Euler
    step). Each pair drives a SAP PD-controlled joint actuator whose implicit force is

        u = clamp(u_ff - Kp (q_{k+1} - q_d) - Kd (v_{k+1} - v_d), -e, e),

    and the system chooses, per step,

    * static phase (|v_k| ≤ Δv): u_ff = μ(v_k, Δ_k)·N, q_d = q_k, v_d = v_k,
      Kp = s'_Δ·μs·N/Δmax, Kd = s'_β·(μs + μ1(Δ_k))·N/Δv (s' = the shape's largest slope:
      1.5 for the cubic STEP, 1 for linear; μs + μ1 because where v opposes the creep both
      terms of eq. 1 change with β), e = μs·N (the law never exceeds μs·N);
    * kinetic phase (|v_k| > Δv): u_ff = 0, v_d = 0, Kp = 0, Kd = s'_β·μs·N/Δv,
      e = μk(|v_k|)·N.
      The saturated damper gives exactly -μk·N·sgn(v_{k+1}) while |v_{k+1}| stays above
      e/Kd (≤ Δv), and catches a velocity reversal inside the step instead of overshooting it.

    Because Kp, Kd bound the law's slopes from above, the step is unconditionally stable for the
    stiff part; a W-method with any fixed Jacobian is first-order consistent, so the scheme
    converges to the law as dt → 0 (the friction rig's tests and benchmarks record the error
    against the reference at several steps). Where it departs from the law at finite dt: the
    static-phase force follows the law's tangent plane with the over-estimated slopes for one
    step: where the law's slope is below its bound (|v| near 0 or Δv on the cubic STEP, creep at
    Δmax) the term Kd·(v_{k+1} - v_k) acts as an added inertia Kd·dt, so the velocity inside the
    static band relaxes over several steps instead of at once. Measured consequence at 1 ms on
    the rig (30 kg, N = 3 kN): a load of 0.95·μs·N creeps the block 5.1 µm (law: 4.6 µm) and
    0.999·μs·N 10 µm (law: 4.9 µm) before it stops; both vanish as dt shrinks. μk in the
    Stribeck band Δv < |v| < 1.5Δv and the normal force N are lagged one step (N is lagged in
    both schemes: the reactions are the plant's sampled output).

    Event order within a step (Drake 1.51): the plant's SAP step is an unrestricted update and
    runs first; this system's discrete update then sees the new plant state x_{k+1} and stores
    the creep memory for it; the per-step publish and, at the next step, the plant read this
    system's outputs, computed from that memory and x_{k+1} (``advance_creep`` with zero
    displacement returns the memory unchanged, so the outputs, the gains and the memory agree).

    Drake keeps PD gains and effort limits in the *model*, not in the context. This system owns
    them for its actuators: a per-step publish event (and an initialization event) writes the
    values computed from the context into the actuators, so a simulation depends only on its
    context; a stale value from a previous run is overwritten before the first step. Do not
    share the plant of a fast-scheme diagram between simulators running at the same time.

Normal force (eq. 4) comes from the reaction of ``normal_force_joint`` (Drake's
``reaction_forces`` output: force and moment on the joint's child at its frame Jc, in Jc). The
components perpendicular to the joint axis are used, the moment moved to the middle of the
overlap: M_mid = M_Jc + a(q)·(û × F) with a(q) = a0 + a1·q, and the overlap d(q) = d0 + d1·q.
For rigs, ``constant_normal_force_N`` replaces the reaction.
"""

import dataclasses

import numpy as np
from pydrake.common.value import AbstractValue, Value
from pydrake.multibody.math import SpatialForce
from pydrake.multibody.tree import PdControllerGains, PrismaticJoint, RevoluteJoint
from pydrake.systems.framework import BasicVector, LeafSystem, ValueProducer

from drake_car.law.frd_friction import (
    STATIC, StrutFrictionParameters, advance_creep, friction_coefficient, mu_kinetic,
    normal_force, shape_max_slope)

SCHEMES = ("fast", "reference")
DIAGNOSTIC_FIELDS = ("v", "creep", "beta", "mu1", "mu", "phase", "N", "friction")
# Floor on PD gains: Drake removes a controller whose gains are both zero.
_MIN_GAIN = 1e-9


@dataclasses.dataclass
class FrictionPair:
    kind: str  # "translation" or "rotation"
    joint: object
    actuator: object


class StrutFriction(LeafSystem):
    """FRD friction on up to two pairs (translation on a prismatic joint, rotation on a revolute
    joint about the same axis).

    .. pydrake_system::

        name: StrutFriction
        input_ports:
        - plant_state
        - reaction_forces (absent with a constant normal force)
        output_ports:
        - friction_actuation
        - desired_state (fast scheme only)
        - diagnostics

    ``plant_state``: the plant's full state [q; v]. ``reaction_forces``: the plant's
    ``reaction_forces`` (list of SpatialForce, N and N·m). ``friction_actuation``: the
    feed-forward actuation of the pairs' actuators (N, N·m; in the reference scheme this is the
    whole friction force). ``desired_state``: [q_d..., v_d...] of the pairs' PD actuators.
    ``diagnostics``: per pair (translation first) the fields ``DIAGNOSTIC_FIELDS``: relative
    velocity v (m/s or rad/s), creep Δ (m or rad), β, μ1, signed μ, phase (0 static,
    1 kinetic), normal force N (N), friction from the law at the step's start (N or N·m),
    evaluated from the state at the start of the step.
    """

    def __init__(self, plant, pairs, params: StrutFrictionParameters, *, scheme="fast",
                 normal_force_joint=None, overlap_m=(0.1, 0.0), moment_arm_offset_m=(0.0, 0.0),
                 constant_normal_force_N=None, initial_normal_force_N=None,
                 name="strut_friction"):
        super().__init__()
        if scheme not in SCHEMES:
            raise ValueError(f"{name}: scheme {scheme!r} must be one of {SCHEMES}")
        if not pairs:
            raise ValueError(f"{name}: no friction pair given")
        self._name = name
        self._params = params
        self._scheme = scheme
        self._pairs = list(pairs)
        self._laws = []
        for pair in self._pairs:
            if pair.kind == "translation" and not isinstance(pair.joint, PrismaticJoint):
                raise TypeError(f"{name}: translation pair needs a PrismaticJoint, "
                                f"got {type(pair.joint).__name__} '{pair.joint.name()}'")
            if pair.kind == "rotation" and not isinstance(pair.joint, RevoluteJoint):
                raise TypeError(f"{name}: rotation pair needs a RevoluteJoint, "
                                f"got {type(pair.joint).__name__} '{pair.joint.name()}'")
            self._laws.append(params.translation() if pair.kind == "translation"
                              else params.rotation())
        nq = plant.num_positions()
        self._q_index = [p.joint.position_start() for p in self._pairs]
        self._v_index = [nq + p.joint.velocity_start() for p in self._pairs]
        self._overlap = tuple(float(x) for x in overlap_m)
        self._moment_offset = tuple(float(x) for x in moment_arm_offset_m)
        self._constant_normal = constant_normal_force_N
        # Drake's sampled reaction port reads zero before the first step; a run that starts
        # from a loaded, stuck state gives the normal force for that first step here.
        self._initial_normal = (None if initial_normal_force_N is None
                                else float(initial_normal_force_N))
        if constant_normal_force_N is None:
            joint = normal_force_joint or self._pairs[0].joint
            self._normal_joint_index = int(joint.index())
            self._normal_q_index = joint.position_start()
            axis = (joint.translation_axis() if isinstance(joint, PrismaticJoint)
                    else joint.revolute_axis())
            self._axis = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
        elif not constant_normal_force_N >= 0:
            raise ValueError(f"{name}: constant_normal_force_N = {constant_normal_force_N} "
                             "must be >= 0")
        n = len(self._pairs)

        self._state_port = self.DeclareVectorInputPort(
            "plant_state", plant.num_multibody_states())
        self._reaction_port = None
        if constant_normal_force_N is None:
            self._reaction_port = self.DeclareAbstractInputPort(
                "reaction_forces", Value[list[SpatialForce]]())
        # Discrete state per pair: creep, phase, joint position at the last update.
        self._state_index = self.DeclareDiscreteState(3 * n)
        self.DeclareInitializationDiscreteUpdateEvent(self._initialize)
        self.DeclarePeriodicDiscreteUpdateEvent(
            plant.time_step(), 0.0, self._update)
        self._step = self.DeclareCacheEntry(
            description="friction_step",
            value_producer=ValueProducer(allocate=lambda: AbstractValue.Make(()),
                                         calc=self._calc_step),
            prerequisites_of_calc={self.all_input_ports_ticket(),
                                   self.xd_ticket()})
        self._actuation_port = self.DeclareVectorOutputPort(
            "friction_actuation", n, self._calc_actuation,
            prerequisites_of_calc={self._step.ticket()})
        self._desired_port = None
        if scheme == "fast":
            self._desired_port = self.DeclareVectorOutputPort(
                "desired_state", 2 * n, self._calc_desired,
                prerequisites_of_calc={self._step.ticket()})
            self.DeclareInitializationPublishEvent(self._write_gains)
            self.DeclarePerStepPublishEvent(self._write_gains)
        self._diagnostics_port = self.DeclareVectorOutputPort(
            "diagnostics", BasicVector(len(DIAGNOSTIC_FIELDS) * n), self._calc_diagnostics,
            prerequisites_of_calc={self._step.ticket()})

    # -- wiring helpers ---------------------------------------------------------------------
    def connect(self, builder, plant):
        builder.Connect(plant.get_state_output_port(), self._state_port)
        if self._reaction_port is not None:
            builder.Connect(plant.get_reaction_forces_output_port(), self._reaction_port)

    def desired_state_output_port(self):
        return self._desired_port

    def actuation_output_port(self):
        return self._actuation_port

    def num_pairs(self):
        return len(self._pairs)

    def num_pd_pairs(self):
        return len(self._pairs) if self._scheme == "fast" else 0

    def pair_kinds(self):
        return [p.kind for p in self._pairs]

    def diagnostic_names(self):
        return [f"{p.kind}_{field}" for p in self._pairs for field in DIAGNOSTIC_FIELDS]

    @property
    def scheme(self):
        return self._scheme

    # -- the computation ----------------------------------------------------------------------
    def _normal_force(self, context, x):
        if self._constant_normal is not None:
            return float(self._constant_normal)
        if self._initial_normal is not None and context.get_time() <= 0.0:
            return self._initial_normal
        q = x[self._normal_q_index]
        overlap = self._overlap[0] + self._overlap[1] * q
        if not overlap > 0:
            raise RuntimeError(
                f"{self._name}: overlap d = {overlap:.4g} m <= 0 at t = {context.get_time():.4f} s"
                " (the rod has left the cylinder's guide)")
        reaction = self._reaction_port.Eval(context)[self._normal_joint_index]
        force = reaction.translational()
        moment = reaction.rotational()
        u = self._axis
        offset = self._moment_offset[0] + self._moment_offset[1] * q
        ux, uy, uz = u
        fx, fy, fz = force
        mx = moment[0] + offset * (uy * fz - uz * fy)
        my = moment[1] + offset * (uz * fx - ux * fz)
        mz = moment[2] + offset * (ux * fy - uy * fx)
        f_axial = fx * ux + fy * uy + fz * uz
        m_axial = mx * ux + my * uy + mz * uz
        return normal_force(
            (fx - f_axial * ux, fy - f_axial * uy, fz - f_axial * uz),
            (mx - m_axial * ux, my - m_axial * uy, mz - m_axial * uz),
            overlap, self._params.preload_force_N, self._params.mu_s,
            self._params.normal_force_form, axis=(ux, uy, uz))

    def _calc_step(self, context, abstract_value):
        x = self._state_port.Eval(context)
        memory = context.get_discrete_state(self._state_index).get_value()
        normal = self._normal_force(context, x)
        p = self._params
        results = []
        for i, (pair, law) in enumerate(zip(self._pairs, self._laws)):
            q = float(x[self._q_index[i]])
            v = float(x[self._v_index[i]])
            creep, phase = advance_creep(float(memory[3 * i]), float(memory[3 * i + 1]), v,
                                         q - float(memory[3 * i + 2]), law)
            mu, beta, mu1, _ = friction_coefficient(v, creep, law)
            if pair.kind == "translation":  # eq. (5); N includes F0/μs (eq. 4)
                scale = normal
            else:  # eq. (6)
                scale = normal * p.rod_radius_m + (
                    p.preload_moment_Nm / p.mu_s if p.preload_moment_Nm > 0 else 0.0)
            force = mu * scale
            gains = None
            if self._scheme == "fast":
                # |∂F/∂v| ≤ s'_β (μs + μ1) N / Δv in the static phase (v opposing the creep).
                kd = max(shape_max_slope(law.beta_shape) * (law.mu_s + mu1) * scale / law.dv,
                         _MIN_GAIN)
                if phase == STATIC:
                    kp = shape_max_slope(law.creep_shape) * law.mu_s * scale / law.dmax
                    gains = (kp, kd, law.mu_s * scale, q, v, force)
                else:
                    gains = (0.0, kd, mu_kinetic(v, law) * scale, q, 0.0, 0.0)
            results.append((q, v, creep, phase, beta, mu1, mu, normal, force, gains))
        abstract_value.set_value(tuple(results))

    def _initialize(self, context, discrete_state):
        x = self._state_port.Eval(context)
        values = np.zeros(3 * len(self._pairs))
        for i in range(len(self._pairs)):
            values[3 * i + 1] = STATIC
            values[3 * i + 2] = x[self._q_index[i]]
        discrete_state.set_value(self._state_index, values)

    def _update(self, context, discrete_state):
        # Only the creep memory; the forces are computed once per step, by the outputs.
        x = self._state_port.Eval(context)
        memory = context.get_discrete_state(self._state_index).get_value()
        values = np.empty(3 * len(self._pairs))
        for i, law in enumerate(self._laws):
            q = float(x[self._q_index[i]])
            creep, phase = advance_creep(float(memory[3 * i]), float(memory[3 * i + 1]),
                                         float(x[self._v_index[i]]),
                                         q - float(memory[3 * i + 2]), law)
            values[3 * i:3 * i + 3] = (creep, phase, q)
        discrete_state.set_value(self._state_index, values)

    def _calc_actuation(self, context, output):
        step = self._step.Eval(context)
        if self._scheme == "fast":
            output.SetFromVector([r[9][5] for r in step])
        else:
            output.SetFromVector([r[8] for r in step])

    def _calc_desired(self, context, output):
        step = self._step.Eval(context)
        output.SetFromVector([r[9][3] for r in step] + [r[9][4] for r in step])

    def _calc_diagnostics(self, context, output):
        values = []
        for q, v, creep, phase, beta, mu1, mu, normal, force, _ in self._step.Eval(context):
            values += [v, creep, beta, mu1, mu, phase, normal, force]
        output.SetFromVector(values)

    def _write_gains(self, context):
        for pair, r in zip(self._pairs, self._step.Eval(context)):
            kp, kd, limit, _, _, _ = r[9]
            pair.actuator.set_controller_gains(PdControllerGains(p=max(kp, _MIN_GAIN), d=kd))
            pair.actuator.set_effort_limit(max(limit, _MIN_GAIN))


@dataclasses.dataclass
class StrutFrictionSetup:
    """What a scene asks for on each front strut: law parameters, scheme, which pairs."""

    params: StrutFrictionParameters = dataclasses.field(default_factory=StrutFrictionParameters)
    scheme: str = "fast"
    rotation: bool = True

    # The explicit reference scheme is stable on the car only below ~1e-5 s (rod mass ~30 kg
    # through the strut, N up to ~5 kN): refuse steps far above that instead of chattering.
    reference_max_time_step_s: float = 2e-5

    def __post_init__(self):
        if self.scheme not in SCHEMES:
            raise ValueError(f"friction scheme {self.scheme!r} must be one of {SCHEMES}")

    def check_time_step(self, time_step_s):
        if self.scheme == "reference" and time_step_s > self.reference_max_time_step_s:
            raise ValueError(
                f"friction scheme 'reference' applies the law explicitly and is unstable on the "
                f"car at time_step_s = {time_step_s:g} s; use <= "
                f"{self.reference_max_time_step_s:g} s or the 'fast' scheme")

    def declare(self, plant, joints, side):
        """Adds the pairs' actuators (before Finalize). Returns the pairs."""
        return declare_pairs(plant, joints[0], joints[1] if self.rotation else None,
                             self.scheme, prefix=f"strut_friction_{side}")

    def make_system(self, plant, pairs, side, *, guide_length_l_m):
        # The prismatic joint's child is the cylinder, Jc at the guide; q is the extension s.
        # Overlap d = l - s; the overlap's middle lies d/2 beyond Jc along the joint axis.
        return StrutFriction(plant, pairs, self.params, scheme=self.scheme,
                             overlap_m=(guide_length_l_m, -1.0),
                             moment_arm_offset_m=(-0.5 * guide_length_l_m, 0.5),
                             name=f"strut_friction_{side}")


def declare_pairs(plant, prismatic=None, revolute=None, scheme="fast", prefix="friction"):
    """Adds one actuator per pair to ``plant`` (before Finalize); fast-scheme actuators get PD
    gains (overwritten every step by the system). Returns the list of FrictionPair."""
    pairs = []
    for kind, joint in (("translation", prismatic), ("rotation", revolute)):
        if joint is None:
            continue
        actuator = plant.AddJointActuator(f"{prefix}_{kind}", joint)
        if scheme == "fast":
            actuator.set_controller_gains(PdControllerGains(p=1.0, d=1.0))
        pairs.append(FrictionPair(kind, joint, actuator))
    return pairs
