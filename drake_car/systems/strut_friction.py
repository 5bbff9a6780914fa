"""The paper's FRD friction on a cylindrical (prismatic + revolute) pair, as a LeafSystem.

The law itself lives in ``drake_car.law.friction.frd`` (its per-step evaluation for all pairs,
compiled with numba, in ``drake_car.law.friction.compiled``); this system feeds it from the plant
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
    The law linearised about the state at the start of the step, solved implicitly inside
    Drake's SAP step (a linearly implicit Euler step). Each pair drives a SAP PD-controlled joint
    actuator whose implicit force is

        u = clamp(u_ff - Kp (q_{k+1} - q_d) - Kd (v_{k+1} - v_d), -e, e),

    and the system chooses, per step (x = |v_k|/Δv, S = N, or N r + M0/μs for rotation):

    * static phase (|v_k| ≤ Δv): u_ff = μ(v_k, Δ_k)·S, q_d = q_k, v_d = v_k, e = μs·S (the law
      never exceeds μs·S), and the law's own slopes:
      Kp = (1 - β)·μs·S·s'_Δ(|Δ_k|/Δmax)/Δmax, the creep term's tangent;
      Kd = max(s'_β(x)·b, b_slow)·S/Δv, the β term's tangent on the branch v_k is on
      (b = μs - μ1 when v moves with the creep, μs + μ1 against it), floored by that branch's
      secant over the band, b·S/Δv; below 0.1 Δv (``compiled.SLOW_FRACTION``) the floor blends
      linearly to the steeper branch's, b_slow = b + (μs + μ1 - b)(1 - x/0.1), because there the
      velocity may change sign within the step;
    * kinetic phase (|v_k| > Δv): u_ff = 0, v_d = 0, Kp = 0, Kd = s'_β,max·μs·S/Δv,
      e = μk(|v_k|)·S.
      The saturated damper gives exactly -μk·S·sgn(v_{k+1}) while |v_{k+1}| stays above
      e/Kd (≤ Δv), and catches a velocity reversal inside the step instead of overshooting it.

    Why these slopes (measured on the 1-DOF rig, 30 kg, N = 3 kN, 1 ms): the creep
    under a load held below μs·N is a first-order flow, v = Δv·β⁻¹((F/N - μ1)/(μs - μ1)), slow
    against 1 ms (Δmax/Δv = 50 ms). The previous choice, the slopes' upper bounds
    Kp = 1.5·μs·S/Δmax and Kd = 1.5·(μs + μ1)·S/Δv, is a W-method whose surplus Kd acts as an
    added inertia Kd·dt (~10⁴ kg at 1 ms against the block's 30 kg) where the law's slope is
    small (v near 0, μ1 near μs): the velocity lagged the law's and coasted past the
    equilibrium creep, to 7.4 µm (law 5.0 µm) at 0.999·μs·N, beyond Δmax. With the tangents and
    the branch's secant as floor the creep stays within 0.1 µm (2 % of Δmax) of the law at 1 ms
    for loads of 0.5..0.999 μs·N and below Δmax (tests/test_strut_friction.py). The secant
    floor keeps one step's velocity change within the band (a load jump of up to the branch's
    b·S moves v by at most Δv), so the stick survives a 1 ms step. What it does not cover: a
    load that drops by more than (μs - μ1)·S within one step while the pair moves with its
    creep faster than 0.1 Δv (e.g. a load held at μs·N(1 - 1e-7) and then removed at once) is
    taken as a break-away (one kinetic phase) where the law springs back. A linearly implicit
    step with any Jacobian is first-order consistent, so the scheme converges to the law as
    dt → 0 (the rig's tests and benchmarks/friction_convergence.py). μk in the Stribeck band
    Δv < |v| < 1.5Δv and the normal force N are lagged one step (N is lagged in both schemes:
    the reactions are the plant's sampled output).

    Event order within a step (Drake 1.51): the plant's SAP step is an unrestricted update and
    runs first; this system's discrete update then sees the new plant state x_{k+1} (and the
    reactions of that step), advances the creep memory to it and computes, in the same call,
    everything the next step needs: the feed-forward actuation, the PD targets, the gains and
    the diagnostics. They are discrete state, and the output ports are state output ports (no
    Python runs when the plant reads them). The same call writes the gains into the actuators;
    at the next step the plant reads the outputs. One Python call per step.

    Drake keeps PD gains and effort limits in the *model*, not in the context. This system owns
    them for its actuators: its update (and its initialization event) writes the values it has
    just computed into the actuators, the one side effect of an update here (a per-step publish
    event did it before, one more Python call per step; the same numbers bit for bit: the
    plant's step is an unrestricted update and has read the gains before this update runs,
    and it reads them next at the following step), and a forced publish writes them from a
    context (``sim.branch``, continuing a cloned context). A simulation depends only on its
    context; a stale value from a previous run is overwritten before the first step. Do not
    share the plant of a fast-scheme diagram between simulators running at the same time, and
    do not compute this system's update for a context the simulation does not continue (the
    actuators would hold that context's gains until its next step).

Normal force (eq. 4) comes from the reaction of the strut's ``normal_force_joint`` (Drake's
``reaction_forces`` output: force and moment on the joint's child at its frame Jc, in Jc). The
components perpendicular to the joint axis are used, the moment moved to the middle of the
overlap: M_mid = M_Jc + a(q)·(û × F) with a(q) = a0 + a1·q, and the overlap d(q) = d0 + d1·q
(``friction_pairs.Strut``). For rigs, ``constant_normal_force_N`` replaces the reaction. A
``mirrored`` strut (a car's right strut) has eq. (4) evaluated in its reference strut's
reflected frame: the paper's vector form is not invariant under a reflection, and a car whose
struts are evaluated in one frame is not mirror-symmetric (``law.friction.frd``).
"""

import math

import numpy as np
from pydrake.common.value import Value
from pydrake.multibody.math import SpatialForce
from pydrake.multibody.tree import PdControllerGains, PrismaticJoint, RevoluteJoint
from pydrake.systems.framework import LeafSystem

from drake_car.law.friction.compiled import P, friction_step, pack_pair, pack_strut
from drake_car.law.friction.events import log_size, note_transitions
from drake_car.law.friction.frd import STATIC, StrutFrictionParameters
from drake_car.systems.failure import SimulationFailure
from drake_car.systems.friction_state import FrictionStateAccess
from drake_car.systems.friction_pairs import Strut

SCHEMES = ("fast", "reference")
DIAGNOSTIC_FIELDS = ("v", "creep", "beta", "mu1", "mu", "phase", "N", "friction")
_NONE = np.zeros(0)  # the reference scheme has no PD targets or gains
_NO_REACTION = np.zeros(6)  # a strut with a constant normal force


class _StrutData:
    """What the per-step computation needs of one strut, resolved once at construction."""

    def __init__(self, strut: Strut, name, params):
        self.label = strut.label
        self.params = strut.params if strut.params is not None else params
        self.overlap = tuple(float(x) for x in strut.overlap_m)
        self.offset = tuple(float(x) for x in strut.moment_arm_offset_m)
        self.rod_radius = float(strut.rod_radius_m)
        if not (math.isfinite(self.rod_radius) and self.rod_radius > 0):
            raise ValueError(f"{name}: strut '{strut.label}' rod_radius_m = "
                             f"{strut.rod_radius_m} must be > 0")
        self.constant = strut.constant_normal_force_N
        self.initial = (None if strut.initial_normal_force_N is None
                        else float(strut.initial_normal_force_N))
        self.joint_index = None
        if self.constant is not None:
            if not (math.isfinite(self.constant) and self.constant >= 0):
                raise ValueError(f"{name}: constant_normal_force_N = {self.constant} must be "
                                 "a finite number >= 0")
            self.row = pack_strut(self.params, constant=float(self.constant))
            return
        joint = strut.normal_force_joint or strut.pairs[0].joint
        self.joint_index = int(joint.index())
        self.q_index = joint.position_start()
        axis = (joint.translation_axis() if isinstance(joint, PrismaticJoint)
                else joint.revolute_axis())
        self.axis = tuple(float(a) for a in np.asarray(axis, dtype=float)
                          / np.linalg.norm(axis))
        self.row = pack_strut(self.params, initial=self.initial, q_index=self.q_index,
                              overlap=self.overlap, offset=self.offset, axis=self.axis,
                              mirrored=bool(strut.mirrored))


class StrutFriction(FrictionStateAccess, LeafSystem):
    """FRD friction on the pairs of one or more struts (translation on a prismatic joint,
    rotation on a revolute joint about the same axis). One system serves all struts of a car:
    the plant's state and reactions are read once per step for all of them.

    .. pydrake_system::

        name: StrutFriction
        input_ports:
        - plant_state
        - reaction_forces (absent when every strut has a constant normal force)
        output_ports:
        - friction_actuation
        - desired_state (fast scheme only)
        - diagnostics

    ``plant_state``: the plant's full state [q; v]. ``reaction_forces``: the plant's
    ``reaction_forces`` (list of SpatialForce, N and N·m). ``friction_actuation``: the
    feed-forward actuation of the pairs' actuators, strut by strut (N, N·m; in the reference
    scheme this is the whole friction force). ``desired_state``: [q_d..., v_d...] of the pairs'
    PD actuators. ``diagnostics``: per pair the fields ``DIAGNOSTIC_FIELDS`` (names from
    ``diagnostic_names()``): relative velocity v (m/s or rad/s), creep Δ (m or rad), β, μ1,
    signed μ, phase (0 static, 1 kinetic), normal force N (N), friction from the law at the
    step's start (N or N·m), evaluated from the state at the start of the step.

    ``struts``: a list of ``friction_pairs.Strut``.

    State: the creep, phase and position memory of every pair, the step's PD targets and the
    event log, as discrete groups (``systems.friction_state``: the layout; ``creeps()``,
    ``phases()``, ``events()`` read them). An initialization event sets them from the plant's
    state (no creep, static): a new ``Simulator`` on a saved context resets them unless it is
    initialized with ``InitializeParams(suppress_initialization_events=True)`` (``sim.branch``).
    """

    def __init__(self, plant, struts, params: StrutFrictionParameters, *, scheme="fast",
                 name="strut_friction"):
        super().__init__()
        if scheme not in SCHEMES:
            raise ValueError(f"{name}: scheme {scheme!r} must be one of {SCHEMES}")
        if not struts or not all(isinstance(s, Strut) for s in struts):
            raise TypeError(f"{name}: give a non-empty list of friction_pairs.Strut")
        labels = [s.label for s in struts]
        if len(set(labels)) != len(labels):
            raise ValueError(f"{name}: strut labels {labels} must be distinct")
        self.set_name(name)
        self._name = name
        self._params = params
        self._scheme = scheme
        self._struts = [_StrutData(s, name, params) for s in struts]
        nq = plant.num_positions()
        # Flattened over the struts' pairs, in actuation order.
        self._pairs, self._laws, self._strut_of, self._strut_params = [], [], [], []
        for k, strut in enumerate(struts):
            if not strut.pairs:
                raise ValueError(f"{name}: strut '{strut.label}' has no friction pair")
            law = strut.params if strut.params is not None else params
            for pair in strut.pairs:
                expected = PrismaticJoint if pair.kind == "translation" else RevoluteJoint
                if not isinstance(pair.joint, expected):
                    raise TypeError(f"{name}: {pair.kind} pair needs a {expected.__name__}, "
                                    f"got {type(pair.joint).__name__} '{pair.joint.name()}'")
                self._pairs.append(pair)
                self._laws.append(law.translation() if pair.kind == "translation"
                                  else law.rotation())
                self._strut_params.append(law)
                self._strut_of.append(k)
        self._labels = [struts[k].label for k in self._strut_of]
        self._q_index = [p.joint.position_start() for p in self._pairs]
        self._actuators = [p.actuator for p in self._pairs]
        # The per-step computation is law.friction.compiled's: the pairs and struts as arrays.
        self._pair_rows = np.array([
            pack_pair(law, self._strut_params[i], rotation=pair.kind == "rotation",
                      strut=self._strut_of[i], q_index=self._q_index[i],
                      v_index=nq + pair.joint.velocity_start(),
                      rod_radius=self._struts[self._strut_of[i]].rod_radius)
            for i, (pair, law) in enumerate(zip(self._pairs, self._laws))])
        self._strut_rows = np.array([s.row for s in self._struts])
        self._no_reactions = np.zeros((len(self._struts), 6))
        n = len(self._pairs)
        # What the event log needs of each pair (law.friction.events): its velocity's and
        # position's entries in [q; v], Δv, and (μs, arm, preload) of its static capacity.
        rows = self._pair_rows
        self._v_index = rows[:, P.V_INDEX].astype(np.int64)
        self._q_index_array = rows[:, P.Q_INDEX].astype(np.int64)
        self._dv = rows[:, P.DV].copy()
        self._dmax = rows[:, P.DMAX].copy()
        rotation = rows[:, P.ROTATION] != 0.0
        self._capacity_scale = np.column_stack([
            rows[:, P.MU_S], np.where(rotation, rows[:, P.ROD_RADIUS], 1.0),
            np.where(rotation & (rows[:, P.PRELOAD_MOMENT] > 0),
                     rows[:, P.PRELOAD_MOMENT] / np.where(rows[:, P.STRUT_MU_S] > 0,
                                                          rows[:, P.STRUT_MU_S], 1.0), 0.0)])
        self._dt = plant.time_step()

        self._state_port = self.DeclareVectorInputPort(
            "plant_state", plant.num_multibody_states())
        self._reaction_port = None
        if any(s.constant is None for s in self._struts):
            self._reaction_port = self.DeclareAbstractInputPort(
                "reaction_forces", Value[list[SpatialForce]]())
        # Discrete state groups, each computed by the one update per step (per pair):
        # the memory [creep..., phase..., the joint position at the last update...]; the
        # feed-forward (fast) or whole friction (reference) actuation; the diagnostics
        # (DIAGNOSTIC_FIELDS per pair); the fast scheme's PD targets [q_d..., v_d...] and gains
        # [Kp..., Kd..., effort limit...].
        self._memory = self.DeclareDiscreteState(3 * n)
        self._actuation = self.DeclareDiscreteState(n)
        self._diagnostics = self.DeclareDiscreteState(len(DIAGNOSTIC_FIELDS) * n)
        # The stick-slip event log (law.friction.events: a bounded ring, read by the runner).
        self._events = self.DeclareDiscreteState(log_size(n))
        self._desired = self._gain_values = None
        if scheme == "fast":
            self._desired = self.DeclareDiscreteState(2 * n)
            self._gain_values = self.DeclareDiscreteState(3 * n)
        self.DeclareInitializationDiscreteUpdateEvent(self._initialize)
        self.DeclarePeriodicDiscreteUpdateEvent(self._dt, 0.0, self._update)
        self._actuation_port = self.DeclareStateOutputPort("friction_actuation",
                                                           self._actuation)
        self._desired_port = None
        if scheme == "fast":
            self._desired_port = self.DeclareStateOutputPort("desired_state", self._desired)
            self._gains = PdControllerGains(p=1.0, d=1.0)  # reused for every write
            self.DeclareForcedPublishEvent(self._write_gains)
        self._diagnostics_port = self.DeclareStateOutputPort("diagnostics", self._diagnostics)

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

    def pair_kinds(self):
        return [p.kind for p in self._pairs]

    def diagnostic_names(self):
        return [f"{label}_{p.kind}_{field}" if label else f"{p.kind}_{field}"
                for label, p in zip(self._labels, self._pairs) for field in DIAGNOSTIC_FIELDS]

    @property
    def scheme(self):
        return self._scheme

    # -- the computation ----------------------------------------------------------------------
    def _initialize(self, context, discrete_state):
        # Memory: no creep, static, at the initial positions; then the step's values from it.
        x = self._state_port.Eval(context)
        n = len(self._pairs)
        memory = discrete_state.get_mutable_value(self._memory)
        memory[:n] = 0.0
        memory[n:2 * n] = STATIC
        memory[2 * n:] = x[self._q_index]
        log = discrete_state.get_mutable_value(self._events)
        log[:] = 0.0
        log[1 + n:1 + 2 * n] = -1.0  # no reserve at full creep yet
        self._compute(context, discrete_state, x, context.get_time(), initial=True)

    def _update(self, context, discrete_state):
        # The plant has stepped: x is x_{k+1}, at time t + dt. Its transitions are noted
        # first, from the values the step used (still in discrete_state).
        x = self._state_port.Eval(context)
        t = context.get_time() + self._dt
        value = discrete_state.get_mutable_value
        fast = self._scheme == "fast"
        note_transitions(t, x, self._v_index, self._q_index_array, self._dv, self._dmax,
                         self._capacity_scale, value(self._memory), value(self._diagnostics),
                         fast, value(self._actuation),
                         value(self._desired) if fast else _NONE,
                         value(self._gain_values) if fast else _NONE, value(self._events))
        self._compute(context, discrete_state, x, t, initial=False)

    def _compute(self, context, discrete_state, x, t, initial):
        """Advances the creep memory (in ``discrete_state``) to the plant state ``x`` and
        computes the friction, the fast scheme's PD targets and gains, and the diagnostics,
        into ``discrete_state`` (``law.friction.compiled.friction_step``); writes the gains
        into the actuators (the plant's next step reads them there)."""
        reactions = self._no_reactions
        if self._reaction_port is not None:
            forces = self._reaction_port.Eval(context)
            reactions = np.array([forces[s.joint_index].get_coeffs()
                                  if s.joint_index is not None else _NO_REACTION
                                  for s in self._struts])
        value = discrete_state.get_mutable_value
        fast = self._scheme == "fast"
        failed = friction_step(x, reactions, initial, fast, self._pair_rows, self._strut_rows,
                               value(self._memory), value(self._actuation),
                               value(self._diagnostics),
                               value(self._desired) if fast else _NONE,
                               value(self._gain_values) if fast else _NONE)
        if failed >= 0:
            strut = self._struts[failed]
            overlap = strut.overlap[0] + strut.overlap[1] * x[strut.q_index]
            raise SimulationFailure(
                f"{self._name}: overlap d = {overlap:.4g} m <= 0 at t = {t:.4f} s"
                f"{' on strut ' + strut.label if strut.label else ''}"
                " (the rod has left the cylinder's guide)")
        if fast:
            self._set_gains(value(self._gain_values))

    def _write_gains(self, context):
        """The forced publish: the gains of ``context`` into the actuators."""
        self._set_gains(context.get_discrete_state(self._gain_values).get_value())

    def _set_gains(self, gain_values):
        """[Kp..., Kd..., effort limit...] into the pairs' actuators."""
        values = gain_values.tolist()
        n = len(self._actuators)
        gains = self._gains
        for i, actuator in enumerate(self._actuators):
            gains.p, gains.d = values[i], values[n + i]
            actuator.set_controller_gains(gains)
            actuator.set_effort_limit(values[2 * n + i])
