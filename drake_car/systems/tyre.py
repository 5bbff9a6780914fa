"""Tyre forces on the four wheels as a LeafSystem: radial stiffness and damping at one contact
point per wheel, plus (optionally) the Magic Formula's horizontal forces and moments."""

import typing

from pydrake.common.value import AbstractValue, Value
from pydrake.math import RigidTransform
from pydrake.multibody.math import SpatialForce, SpatialVelocity
from pydrake.multibody.plant import ExternallyAppliedSpatialForce
from pydrake.systems.framework import BasicVector, LeafSystem, ValueProducer

from drake_car.law.magic_formula import linear_tyre, magic_formula
from drake_car.law.road import Flat
from drake_car.law.tyre_contact import RadialTyre, contact_point, radial_force
from drake_car.systems.failure import SimulationFailure
from drake_car.law.tyre_slip import (
    SlipOptions, contact_kinematics, low_speed_weight, relax, steady_slips, transient_slips)

WHEELS = ("fl", "fr", "rl", "rr")
# A tyre's Magic Formula holds up to a few times its nominal load; far beyond it the state has
# diverged (the formula's exponentials overflow near 3000 FNOMIN).
MAX_LOAD_RATIO = 50.0
DIAGNOSTIC_FIELDS = ("Fx_N", "Fy_N", "Fz_N", "Mz_Nm", "kappa", "alpha_rad", "gamma_rad",
                     "vx_mps", "deflection_m")


class _Contact(typing.NamedTuple):
    """One wheel's contact kinematics (cached per step)."""

    body_index: int
    p_body: list  # contact point in the wheel's frame
    point: tuple  # contact point in world
    deflection: float
    fz: float
    kinematics: object  # law.tyre_slip.ContactKinematics, or None (vertical only)


class _Solution(typing.NamedTuple):
    """One wheel's forces (cached per step)."""

    p_body: list
    deflection: float
    force: list  # in world
    torque: list
    diagnostics: list  # DIAGNOSTIC_FIELDS


class TyreSystem(LeafSystem):
    """Tyre forces at one contact point per wheel.

    .. pydrake_system::

        name: TyreSystem
        input_ports:
        - body_poses
        - body_spatial_velocities
        output_ports:
        - tyre_forces
        - tyre_loads
        - tyre_diagnostics

    ``body_poses`` and ``body_spatial_velocities`` are the plant's outputs of the same names.
    ``tyre_forces``: list of ExternallyAppliedSpatialForce, one per wheel, applied at the
    contact point, in world. ``tyre_loads``: Fz (N) of fl, fr, rl, rr, then their radial
    deflections (m). ``tyre_diagnostics``: per wheel the fields ``DIAGNOSTIC_FIELDS`` in the
    contact frame (x along the wheel heading, y to its left; ISO slip conventions).

    With ``linear`` the horizontal forces come from ``law.magic_formula.linear_tyre`` (the
    same tyre linearised about zero slip) instead.

    Vertical: deflection δ = max(0, h(x_c, y_c) - z_c) at the lowest point c of the wheel's
    circle, Fz = max(0, k δ + c δ̇) with δ̇ = -v_z of the wheel centre. Horizontal (when a Magic
    Formula tyre is given): Fx, Fy, Mz, My of ``drake_car.law.magic_formula`` at the slips of
    ``drake_car.law.tyre_slip`` (transient with relaxation lengths, kept as discrete state, or
    steady), effective rolling radius R_e = R0 - δ/3, plus a viscous contact damping faded in
    below a low speed. Without relaxation the slips divide by max(|V_x|, v_floor): such a tyre is
    stiff at low speed and meant for runs that start rolling.
    """

    def __init__(self, wheel_bodies: dict, tyre: RadialTyre, road_height=None, *,
                 magic_formula_tyre=None, slip: SlipOptions | None = None, combined=True,
                 linear=False, time_step_s=None, mirror_right=True, mirror_left=("fl", "rl")):
        super().__init__()
        missing = [w for w in WHEELS if w not in wheel_bodies]
        if missing:
            raise ValueError(f"TyreSystem: wheel bodies missing for {missing}")
        self._tyre = tyre
        self._road = Flat() if road_height is None else road_height
        self._flat = isinstance(self._road, Flat)
        self._mf = magic_formula_tyre
        self._max_load = (MAX_LOAD_RATIO * magic_formula_tyre.FNOMIN
                          if magic_formula_tyre is not None else float("inf"))
        self._slip = slip = slip or SlipOptions()
        self._combined = combined
        self._linear = linear
        if linear and magic_formula_tyre is None:
            raise ValueError("TyreSystem: the linear tyre is the Magic Formula tyre linearised; "
                             "give magic_formula_tyre")
        self._body_indices = [wheel_bodies[w].index() for w in WHEELS]
        # The right-hand tyres are the left-hand ones mirrored (as Adams' and MF-Tyre's tyre-side
        # option does), so the car is symmetric: the data's ply-steer and conicity offsets
        # would otherwise push all four tyres the same way.
        self._mirror = [1.0 if w in mirror_left else -1.0 for w in WHEELS] if mirror_right \
            else [1.0] * len(WHEELS)
        self._int_indices = [int(i) for i in self._body_indices]
        self._applied = []  # one force object per wheel, refilled every step
        for index in self._body_indices:
            applied = ExternallyAppliedSpatialForce()
            applied.body_index = index
            self._applied.append(applied)
        self._poses_port = self.DeclareAbstractInputPort(
            "body_poses", Value[list[RigidTransform]]())
        self._velocities_port = self.DeclareAbstractInputPort(
            "body_spatial_velocities", Value[list[SpatialVelocity]]())
        self._relaxed = self._mf is not None and slip.relaxation
        if self._relaxed:
            if not (time_step_s and time_step_s > 0):
                raise ValueError("TyreSystem: relaxation needs the plant's time_step_s > 0")
            self._dt = time_step_s
            self._deflections = self.DeclareDiscreteState(2 * len(WHEELS))
            self.DeclarePeriodicDiscreteUpdateEvent(time_step_s, 0.0, self._update)
        # Two caches: the contact kinematics depend on the plant's outputs only, the forces also
        # on the deflection states; the discrete update reads the first, so a step evaluates
        # each once.
        self._kinematics = self.DeclareCacheEntry(
            description="contact_kinematics",
            value_producer=ValueProducer(
                allocate=lambda: AbstractValue.Make(()), calc=self._calc_kinematics),
            prerequisites_of_calc={self.all_input_ports_ticket()})
        self._solution = self.DeclareCacheEntry(
            description="contact_solution",
            value_producer=ValueProducer(
                allocate=lambda: AbstractValue.Make(()), calc=self._calc_solution),
            prerequisites_of_calc={self._kinematics.ticket(), self.xd_ticket()})
        self.DeclareAbstractOutputPort(
            "tyre_forces", lambda: Value[list[ExternallyAppliedSpatialForce]](),
            self._calc_forces, prerequisites_of_calc={self._solution.ticket()})
        self.DeclareVectorOutputPort("tyre_loads", BasicVector(2 * len(WHEELS)),
                                     self._calc_loads,
                                     prerequisites_of_calc={self._solution.ticket()})
        self.DeclareVectorOutputPort(
            "tyre_diagnostics", BasicVector(len(DIAGNOSTIC_FIELDS) * len(WHEELS)),
            self._calc_diagnostics, prerequisites_of_calc={self._solution.ticket()})

    def _deflection_rate(self, point, v):
        """dδ/dt = (rate at which the road rises under the moving wheel) - v_z."""
        if self._flat:
            return -float(v[2])
        eps = 1e-3
        x, y = point[0], point[1]
        dh_dx = (self._road(x + eps, y) - self._road(x - eps, y)) / (2 * eps)
        dh_dy = (self._road(x, y + eps) - self._road(x, y - eps)) / (2 * eps)
        return dh_dx * float(v[0]) + dh_dy * float(v[1]) - float(v[2])

    def check_time_step(self, time_step_s, spin_inertia_kgm2):
        """The horizontal forces act on the wheels' spin explicitly: the low-speed damping c
        and the contact patch's longitudinal spring K_x/σκ need dt < 2 I/(c R²) and
        dt < 2/ω, ω = R sqrt(K_x/(σκ I)). Raises ValueError past either limit."""
        if self._mf is None:
            return
        radius = self._tyre.unloaded_radius_m
        limits = []
        if self._slip.low_speed_damping_Nspm > 0:
            limits.append(2 * spin_inertia_kgm2
                          / (self._slip.low_speed_damping_Nspm * radius ** 2))
        if self._relaxed:
            kx = magic_formula(self._mf, self._mf.FNOMIN, 0.0, 0.0, 0.0, 0.0).slip_stiffness
            omega = radius * (kx / (self._slip.relaxation_length_long_m
                                    * spin_inertia_kgm2)) ** 0.5
            limits.append(2.0 / omega)
        if limits and time_step_s > min(limits):
            raise ValueError(
                f"time_step_s = {time_step_s:g} s is above the tyres' explicit stability limit "
                f"{min(limits):.2g} s (wheel spin inertia {spin_inertia_kgm2:g} kg m²); use a "
                "smaller step")

    def diagnostic_names(self):
        """Per wheel, the fields with the wheel's name before the unit: "Fx_fl_N", "kappa_fl"."""
        names = []
        for w in WHEELS:
            for field in DIAGNOSTIC_FIELDS:
                quantity, _, unit = field.partition("_")
                names.append(f"{quantity}_{w}_{unit}" if unit else f"{quantity}_{w}")
        return names

    def _calc_kinematics(self, context, abstract_value):
        # Scalars throughout (tuples, not numpy): this runs every step for four wheels.
        poses = self._poses_port.Eval(context)
        velocities = self._velocities_port.Eval(context)
        radius = self._tyre.unloaded_radius_m
        result = []
        for index in self._int_indices:
            (r00, r01, r02, px), (r10, r11, r12, py), (r20, r21, r22, pz) = \
                poses[index].GetAsMatrix34().tolist()
            axis = (r01, r11, r21)  # the wheel's spin axis is its body y
            centre = (px, py, pz)
            wx, wy, wz, vx, vy, vz = velocities[index].get_coeffs().tolist()
            point, deflection, _ = contact_point(centre, axis, radius, self._road)
            fz = radial_force(self._tyre, deflection,
                              self._deflection_rate(point, (vx, vy, vz)))
            kin = None
            if self._mf is not None:
                kin = contact_kinematics(axis, centre, (vx, vy, vz), (wx, wy, wz), point,
                                         radius - deflection / 3.0)
            # The contact point in the wheel's frame: R^T (p - centre).
            rx, ry, rz = point[0] - px, point[1] - py, point[2] - pz
            p_body = [r00 * rx + r10 * ry + r20 * rz, r01 * rx + r11 * ry + r21 * rz,
                      r02 * rx + r12 * ry + r22 * rz]
            result.append(_Contact(index, p_body, point, deflection, fz, kin))
        abstract_value.set_value(tuple(result))

    def _calc_solution(self, context, abstract_value):
        deflections = (context.get_discrete_state(self._deflections).get_value().tolist()
                       if self._relaxed else None)
        result = []
        for k, (index, p_body, point, deflection, fz, kin) in enumerate(
                self._kinematics.Eval(context)):
            force = [0.0, 0.0, fz]
            torque = [0.0, 0.0, 0.0]
            diagnostics = [0.0, 0.0, fz, 0.0, 0.0, 0.0, 0.0, 0.0, deflection]
            if kin is not None:
                if fz > self._max_load:
                    raise SimulationFailure(
                        f"diverged at t = {context.get_time():.6f} s: tyre {WHEELS[k]} vertical "
                        f"load {fz:.4g} N beyond {MAX_LOAD_RATIO:g} × FNOMIN, where the Magic "
                        "Formula ends (a smaller plant.time_step or gentler inputs may help)")
                if self._relaxed:
                    kappa, alpha = transient_slips(deflections[2 * k], deflections[2 * k + 1],
                                                   self._slip)
                else:
                    kappa, alpha = steady_slips(kin, self._slip)
                mirror = self._mirror[k]
                if self._linear:
                    f = linear_tyre(self._mf, fz, kappa, mirror * alpha, mirror * kin.gamma,
                                    kin.v_cx)
                else:
                    f = magic_formula(self._mf, fz, kappa, mirror * alpha, mirror * kin.gamma,
                                      kin.v_cx, self._combined)
                if mirror < 0:  # right-hand tyre: the data's lateral offsets mirrored
                    f.fy, f.mz = -f.fy, -f.mz
                damping = (self._slip.low_speed_damping_Nspm
                           * low_speed_weight(kin.v_cx, self._slip)) if fz > 0 else 0.0
                fx = f.fx - damping * kin.v_sx
                fy = f.fy - damping * kin.v_sy
                # e_x = (c, s, 0), e_y = (-s, c, 0): F = fx e_x + fy e_y + fz n,
                # M = Mz n + My e_y.
                c, s = kin.e_x[0], kin.e_x[1]
                force = [fx * c - fy * s, fx * s + fy * c, fz]
                torque = [-f.my * s, f.my * c, f.mz]
                diagnostics = [fx, fy, fz, f.mz, kappa, alpha, kin.gamma, kin.v_cx, deflection]
            result.append(_Solution(p_body, deflection, force, torque, diagnostics))
        abstract_value.set_value(tuple(result))

    def _update(self, context, discrete_state):
        values = context.get_discrete_state(self._deflections).get_value().tolist()
        options = self._slip
        for k, contact in enumerate(self._kinematics.Eval(context)):
            kin = contact.kinematics
            if contact.fz <= 0.0:  # wheel off the road: the contact patch relaxes to zero
                values[2 * k] = values[2 * k + 1] = 0.0
                continue
            values[2 * k] = relax(values[2 * k], -kin.v_sx, kin.v_cx,
                                  options.relaxation_length_long_m, self._dt)
            values[2 * k + 1] = relax(values[2 * k + 1], kin.v_sy, kin.v_cx,
                                      options.relaxation_length_lat_m, self._dt)
        discrete_state.set_value(self._deflections, values)

    def _calc_forces(self, context, output):
        forces = self._applied
        for applied, solution in zip(forces, self._solution.Eval(context)):
            applied.p_BoBq_B = solution.p_body
            applied.F_Bq_W = SpatialForce(solution.torque, solution.force)
        output.set_value(forces)  # copied into the port's value

    def _calc_loads(self, context, output):
        solution = self._solution.Eval(context)
        output.SetFromVector([s.force[2] for s in solution] + [s.deflection for s in solution])

    def _calc_diagnostics(self, context, output):
        values = []
        for s in self._solution.Eval(context):
            values += s.diagnostics
        output.SetFromVector(values)
