"""Tyre forces on the four wheels as a LeafSystem: radial stiffness and damping at one contact
point per wheel, plus (optionally) the Magic Formula's horizontal forces and moments."""

import numpy as np
from pydrake.common.value import Value
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.multibody.math import SpatialVelocity
from pydrake.multibody.plant import Propeller, PropellerInfo
from pydrake.multibody.tree import BodyIndex
from pydrake.systems.framework import LeafSystem

from drake_car.law.road.profiles import Flat
from drake_car.law.tyre.compiled import tyre_step
from drake_car.law.tyre.packing import pack_coefficients, pack_config, pack_road
from drake_car.law.tyre.contact import RadialTyre
from drake_car.law.tyre.slip import SlipOptions
from drake_car.systems.body_kinematics import BodyKinematics
from drake_car.systems.failure import SimulationFailure

WHEELS = ("fl", "fr", "rl", "rr")
# A tyre's Magic Formula holds up to a few times its nominal load; far beyond it the state has
# diverged (the formula's exponentials overflow near 3000 FNOMIN).
MAX_LOAD_RATIO = 50.0
DIAGNOSTIC_FIELDS = ("Fx_N", "Fy_N", "Fz_N", "Mz_Nm", "kappa", "alpha_rad", "gamma_rad",
                     "vx_mps", "deflection_m")
_NONE = np.zeros(0)  # no drive torques, no relaxation state (never written)
# Frames P whose z axis is a body's x, y, z axis (exact permutations): a Propeller with P
# applies its command along (thrust) or about (moment) that axis.
_AXES = [RigidTransform(RotationMatrix(np.array(m, dtype=float)), np.zeros(3)) for m in (
    [[0, 0, 1], [1, 0, 0], [0, 1, 0]], [[0, 1, 0], [0, 0, 1], [1, 0, 0]], np.eye(3))]


class TyreSystem(LeafSystem):
    """Tyre forces at one contact point per wheel.

    .. pydrake_system::

        name: TyreSystem
        input_ports:
        - plant_state (kinematics "state", the default)
        - body_poses (kinematics "ports")
        - body_spatial_velocities (kinematics "ports")
        - net_actuation (with driveshafts only)
        output_ports:
        - tyre_wrenches
        - tyre_loads
        - tyre_diagnostics

    The wheels' motion: with ``kinematics="state"`` from the plant's state [q; v] through
    ``systems.body_kinematics`` (compiled, checked against the plant when made); with
    ``"ports"`` from the plant's ``body_poses`` and ``body_spatial_velocities`` (lists of every
    body's, dearer to read every step). ``connect(builder, plant)`` wires the inputs.
    ``tyre_wrenches``: per wheel (fl, fr, rl, rr) the tyre's force (N) and its moment about
    the wheel's origin (N m), both in the wheel's frame; with ``driveshafts``
    (``systems.driveshaft.Driveshafts``) followed by the drive torques on the knuckles and the
    moment reacting them on the body, in its frame (``net_actuation``: the plant's output of
    that name for the driven instance). ``make_applier()`` gives the Drake system (C++) that
    applies them to the plant. ``tyre_loads``: Fz (N) of fl, fr, rl, rr, then their radial
    deflections (m). ``tyre_diagnostics``: per wheel the fields ``DIAGNOSTIC_FIELDS`` in the
    contact frame (x along the wheel heading, y to its left; ISO slip conventions).

    With ``linear`` the horizontal forces come from ``law.tyre.magic_formula.linear_tyre`` (the
    same tyre linearised about zero slip) instead.

    Vertical: deflection δ = max(0, h(x_c, y_c) - z_c) at the lowest point c of the wheel's
    circle, Fz = max(0, k δ + c δ̇) with δ̇ = -v_z of the wheel centre. Horizontal (when a Magic
    Formula tyre is given): Fx, Fy, Mz, My of ``drake_car.law.tyre.magic_formula`` at the slips of
    ``drake_car.law.tyre.slip`` (transient with relaxation lengths, kept as discrete state, or
    steady), effective rolling radius R_e = R0 - δ/3, plus a viscous contact damping faded in
    below a low speed. Without relaxation the slips divide by max(|V_x|, v_floor): such a tyre is
    stiff at low speed and meant for runs that start rolling.

    One step, one call (as ``StrutFriction``): the plant's step runs first; this system's
    periodic discrete update (period ``time_step_s``, the plant's step) then sees the plant's
    new state, advances the relaxation to it and computes from it the forces of the next step,
    the loads and the diagnostics, all discrete state (an initialization event computes them from
    the initial state). The plant reads the forces at its next step: they are the forces of the
    state it steps from, as a direct-feedthrough calculation would give, computed once. All
    outputs are state output ports and the forces reach the plant through Drake's C++: no Python
    runs when they are read. The maths is ``law.tyre.compiled`` (numba), the pure-Python law is
    its reference. ``road_height`` is one of ``law.road.profiles``'s profiles (default ``Flat``).
    """

    def __init__(self, wheel_bodies: dict, tyre: RadialTyre, road_height=None, *,
                 magic_formula_tyre=None, slip: SlipOptions | None = None, combined=True,
                 linear=False, time_step_s=None, mirror_right=True, mirror_left=("fl", "rl"),
                 driveshafts=None, kinematics="state"):
        super().__init__()
        missing = [w for w in WHEELS if w not in wheel_bodies]
        if missing:
            raise ValueError(f"TyreSystem: wheel bodies missing for {missing}")
        if not (time_step_s and time_step_s > 0):
            raise ValueError("TyreSystem: give the plant's time_step_s > 0 (the forces are "
                             "computed once per step)")
        if linear and magic_formula_tyre is None:
            raise ValueError("TyreSystem: the linear tyre is the Magic Formula tyre linearised; "
                             "give magic_formula_tyre")
        if kinematics not in ("state", "ports"):
            raise ValueError(f"TyreSystem: kinematics {kinematics!r} must be 'state' or 'ports'")
        self._tyre = tyre
        self._mf = magic_formula_tyre
        self._slip = slip = slip or SlipOptions()
        self._dt = time_step_s
        self._relaxed = magic_formula_tyre is not None and slip.relaxation
        self._int_indices = [int(wheel_bodies[w].index()) for w in WHEELS]
        # The right-hand tyres are the left-hand ones mirrored (as Adams' and MF-Tyre's tyre-side
        # option does), so the car is symmetric: the data's ply-steer and conicity offsets
        # would otherwise push all four tyres the same way.
        mirror = ([1.0 if w in mirror_left else -1.0 for w in WHEELS] if mirror_right
                  else [1.0] * len(WHEELS))
        magic = magic_formula_tyre is not None
        self._config = pack_config(
            tyre, slip, magic=magic, linear=linear, combined=combined, relaxed=self._relaxed,
            max_load=MAX_LOAD_RATIO * magic_formula_tyre.FNOMIN if magic else np.inf,
            time_step=time_step_s, mirror=mirror)
        self._coefficients = (pack_coefficients(magic_formula_tyre) if magic
                              else np.zeros(1))
        self._road = pack_road(Flat() if road_height is None else road_height)
        # What the wrenches' entries act on (make_applier): each wheel's force and moment
        # along its own axes; with driveshafts, the drive torques on the knuckles and their
        # reaction on the body along its axes.
        self._appliers = [  # per wheel: F_x, F_y, F_z, M_x, M_y, M_z
            PropellerInfo(BodyIndex(index), axis, thrust_ratio=thrust, moment_ratio=1.0 - thrust)
            for index in self._int_indices for thrust in (1.0, 0.0) for axis in _AXES]
        self._driven = np.zeros(0, dtype=np.int64)
        self._drive_indices = None
        if driveshafts is not None:
            self._driven = np.array([self._int_indices.index(w) for w in driveshafts.wheels],
                                    dtype=np.int64)
            self._drive_indices = np.array(driveshafts.actuation_indices, dtype=np.int64)
            self._appliers += [
                PropellerInfo(BodyIndex(knuckle), frame, thrust_ratio=0.0, moment_ratio=1.0)
                for knuckle, frame in zip(driveshafts.knuckles, driveshafts.knuckle_frames)]
            self._appliers += [PropellerInfo(BodyIndex(driveshafts.body), axis,
                                             thrust_ratio=0.0, moment_ratio=1.0)
                               for axis in _AXES]
        # Where the wheels' (and the reacting body's) poses and velocities come from: the plant's
        # state through the compiled kinematics (one vector read), or the plant's lists of
        # every body's (two list reads).
        bodies = [wheel_bodies[w] for w in WHEELS]
        plant = bodies[0].GetParentPlant()
        if driveshafts is not None:
            bodies.append(plant.get_body(BodyIndex(driveshafts.body)))
        self._kinematics = self._state_port = self._poses_port = self._velocities_port = None
        if kinematics == "state":
            self._kinematics = BodyKinematics(plant, bodies)
            self._rows = self._kinematics.rows
            self._state_port = self.DeclareVectorInputPort("plant_state",
                                                           plant.num_multibody_states())
        else:
            self._bodies = [int(b.index()) for b in bodies]
            self._rows = np.arange(len(bodies), dtype=np.int64)
            self._poses_port = self.DeclareAbstractInputPort(
                "body_poses", Value[list[RigidTransform]]())
            self._velocities_port = self.DeclareAbstractInputPort(
                "body_spatial_velocities", Value[list[SpatialVelocity]]())
        self._wheel_rows = self._rows[:len(WHEELS)]
        self._body_row = int(self._rows[-1]) if driveshafts is not None else -1
        self._instance = driveshafts.instance if driveshafts is not None else None
        self._actuation_port = None
        if driveshafts is not None:
            self._actuation_port = self.DeclareVectorInputPort("net_actuation",
                                                               driveshafts.actuation_size)
        self._relaxation = (self.DeclareDiscreteState(2 * len(WHEELS)) if self._relaxed
                            else None)
        self._wrenches = self.DeclareDiscreteState(len(self._appliers))
        self._loads = self.DeclareDiscreteState(2 * len(WHEELS))
        self._diagnostics = self.DeclareDiscreteState(len(DIAGNOSTIC_FIELDS) * len(WHEELS))
        self.DeclareInitializationDiscreteUpdateEvent(self._initialize)
        self.DeclarePeriodicDiscreteUpdateEvent(time_step_s, 0.0, self._update)
        self.DeclareStateOutputPort("tyre_wrenches", self._wrenches)
        self.DeclareStateOutputPort("tyre_loads", self._loads)
        self.DeclareStateOutputPort("tyre_diagnostics", self._diagnostics)

    def diagnostic_names(self):
        """Per wheel, the fields with the wheel's name before the unit: "Fx_fl_N", "kappa_fl"."""
        names = []
        for w in WHEELS:
            for field in DIAGNOSTIC_FIELDS:
                quantity, _, unit = field.partition("_")
                names.append(f"{quantity}_{w}_{unit}" if unit else f"{quantity}_{w}")
        return names

    def _initialize(self, context, discrete_state):
        self._step(context, discrete_state, advance=False, t=context.get_time())

    def _update(self, context, discrete_state):
        # The plant has stepped: its outputs are those of x_{k+1}, at time t + dt.
        self._step(context, discrete_state, advance=True, t=context.get_time() + self._dt)

    def make_applier(self):
        """Drake's ``Propeller`` system (C++) that applies ``tyre_wrenches`` to the bodies: each
        entry is a "propeller" along or about a body-fixed axis, its command the entry (no
        Python runs when the plant reads the forces). Connect the plant's ``body_poses`` to its
        ``body_poses`` input, ``tyre_wrenches`` to its ``command`` input, its
        ``spatial_forces`` output to the plant's applied spatial forces."""
        return Propeller(self._appliers)

    @property
    def radial_tyre(self):
        """The radial spring and damper the system runs with (``law.tyre.contact.RadialTyre``)."""
        return self._tyre

    @property
    def slip(self):
        """The slip options the system runs with (``law.tyre.slip.SlipOptions``)."""
        return self._slip

    def connect(self, builder, plant):
        """Connects this system's inputs to ``plant``'s outputs."""
        if self._state_port is not None:
            builder.Connect(plant.get_state_output_port(), self._state_port)
        else:
            builder.Connect(plant.get_body_poses_output_port(), self._poses_port)
            builder.Connect(plant.get_body_spatial_velocities_output_port(),
                            self._velocities_port)
        if self._actuation_port is not None:
            builder.Connect(plant.get_net_actuation_output_port(self._instance),
                            self._actuation_port)

    def _step(self, context, discrete_state, advance, t):
        if self._kinematics is not None:
            frames, twists = self._kinematics(self._state_port.Eval(context))
        else:
            poses = self._poses_port.Eval(context)
            velocities = self._velocities_port.Eval(context)
            frames = np.array([poses[i].GetAsMatrix34() for i in self._bodies])
            twists = np.array([velocities[i].get_coeffs() for i in self._bodies])
        torques = (self._actuation_port.Eval(context)[self._drive_indices]
                   if self._actuation_port is not None else _NONE)
        value = discrete_state.get_mutable_value
        relaxation = value(self._relaxation) if self._relaxed else _NONE
        loads = value(self._loads)
        wheel = tyre_step(frames, twists, self._wheel_rows, relaxation, advance, self._config,
                          self._coefficients, self._road, torques, self._driven,
                          self._body_row, value(self._wrenches), loads,
                          value(self._diagnostics))
        if wheel >= 0:
            raise SimulationFailure(
                f"diverged at t = {t:.6f} s: tyre {WHEELS[wheel]} vertical load "
                f"{loads[wheel]:.4g} N beyond {MAX_LOAD_RATIO:g} × FNOMIN, where the Magic "
                "Formula ends (a smaller plant.time_step or gentler inputs may help)")
