"""The divergence monitor and the frozen-step count of every run.

Divergence: the runner advances in chunks of ``simulator.monitor_period_s`` and checks the
plant's state after each: a non-finite entry, or a generalized speed beyond
``MAX_GENERALIZED_SPEED``, stops the run with a ``DivergenceError`` that names the time, the
quantity (the joint and its value) and the first system whose outputs are not finite.

A run that stays finite can still have gone wrong (an explicitly applied tyre spring too stiff
for the step pumps energy into the wheels until the car is thrown off the road, and the exact
path an unstable run takes depends on the machine's floating point). Two more checks, with the
car's tyres (``Road`` below), stop such a run:

- Off the road: all four tyre loads zero, the car over the flat part of its road
  (``flat_up_to_m``), for longer than ``simulator.airborne_limit_s``. On a flat road a car whose
  wheels all stay off it for T has been thrown at least g T² / 8 up (a ballistic hop); the
  default, 0.2 s, is a 5 cm hop, which no drive on a flat road makes.
- Energy not given: the car's mechanical energy E (kinetic, gravity, coil springs, the tyres'
  radial springs ½ k δ²) exceeds its value at the start plus the work every actuator could
  have done (the drive's and the steering's: ∫ Σ |u_i v_i| dt over the actuated joints,
  trapezoidal between checks) plus the work the tyres' rolling radius can give, by more than
  ``ENERGY_SLACK_J``. The tyres' slip is taken at the effective rolling radius R_e = R0 - δ/3
  (``law.tyre.slip``) while their force acts at the contact point, R_l = R0 - δ from the wheel's
  centre: a longitudinal force Fx on a wheel spinning at Ω does Fx Ω (R_e - R_l) more work on
  the car than its slip accounts for (a model's approximation, bounded, not an instability):
  ∫ Σ |Fx_i Ω_i| (2/3) δ_i dt is counted with the actuators'. Rolling resistance (QSY*)
  usually dissipates more; a file without it (Chrono's Sedan_Pac02Tire.tir) gained 2.0 kJ
  over a 0-60 km/h launch in 6 s (1.2 % of the car's kinetic energy; this term 6.6 kJ, its
  slip losses 4.5 kJ), three times the slack.

Frozen steps: steps in which the car's generalized velocities did not change at all (bitwise):
SAP returned its initial guess, dropping the step's impulses (``systems.sap_pacer``). The car's
state is logged every step by a VectorLogSink (C++), counted and cleared after each chunk.
"""

import dataclasses
import math

import numpy as np

from drake_car.systems.failure import SimulationFailure

# Limits a car on a road never reaches (generalized speeds in m/s or rad/s: a wheel at 250 km/h
# spins at ~220 rad/s).
MAX_GENERALIZED_SPEED = 500.0
# The energy a run may gain beyond the work of its actuators before the monitor stops it: the
# car's weight lifted by 5 cm (~640 J for the 1300 kg car) per tonne, i.e. g x 0.05 m per kg.
# The explicit tyre spring's energy error in a sane run is a fraction of a wheel's hop energy
# (½ k δ², δ ~ 1 cm: ~10 J at k = 2e5 N/m), the actuator work's trapezoid error second order
# in the period; an unstable tyre spring gains this much in a few of its periods.
ENERGY_SLACK_M = 0.05


class DivergenceError(SimulationFailure):
    """The simulation diverged; the message names the time, the quantity and the system."""


@dataclasses.dataclass
class Road:
    """What the off-the-road and energy checks need of a car on tyres: the TyreSystem
    (``tyre_loads``: four loads, four radial deflections; ``tyre_diagnostics``: Fx first of
    each wheel's fields), its radial stiffness, the road's ``flat_up_to_m``, the car's chassis
    body (its origin at the front axle, ahead of every wheel), the airborne limit (s), the
    wheel bodies (their spin for the tyres' rolling-radius work)."""

    tyre: object
    radial_stiffness_Npm: float
    flat_up_to_m: float
    chassis: object
    airborne_limit_s: float
    wheels: tuple = ()  # the wheel bodies in the tyre system's order (fl, fr, rl, rr)


@dataclasses.dataclass
class MonitorStats:
    frozen_steps: int = 0
    first_frozen_time_s: float | None = None
    steps: int = 0
    energy_gain_J: float = -math.inf  # the largest gain beyond the actuators' work seen


class Monitor:
    """Checks ``plant``'s state in ``diagram``; counts frozen steps from ``state_logger`` (a
    VectorLogSink of one model instance's state [q; v], sampled every step), when given."""

    def __init__(self, plant, diagram, *, state_logger=None, instance=None, road=None,
                 time_step_s=None):
        """``time_step_s``: without ``state_logger``, count the steps by the time checked (a
        plant of that step updates at its multiples: the rig's, from t = 0), as
        ``sim.resolve`` counts a window's level's steps."""
        self._plant, self._diagram = plant, diagram
        self._step_s = time_step_s
        self._checked_s = 0.0  # the time of the last check (the steps counted by time)
        self._road = road
        self._airborne_since = None
        self._energy = None  # [E at the start, actuator work so far, last power, last time]
        self._ballast = None  # (velocity index, mass) of the SAP ballast, if the plant has one
        if road is not None:
            self._actuation = plant.MakeActuationMatrix()
            mass = plant.CalcTotalMass(plant.CreateDefaultContext())
            if plant.HasModelInstanceNamed("sap_ballast"):
                # Not the car's energy: a decoupled body its actuator drives (its work and its
                # kinetic energy both left out; ``systems.sap_ballast``).
                index = plant.GetJointByName("sap_ballast").velocity_start()
                ballast_kg = plant.GetBodyByName("sap_ballast").default_mass()
                self._ballast = (index, ballast_kg)
                self._actuation[index, :] = 0.0
                mass -= ballast_kg
            self._slack_J = ENERGY_SLACK_M * 9.81 * mass
        self._logger = state_logger
        self._nq = plant.num_positions()
        self._nq_instance = plant.num_positions(instance) if instance is not None else 0
        self._names = _coordinate_names(plant)
        self.stats = MonitorStats()
        self._last_v = None

    @property
    def counts_steps(self):
        """Whether the monitor counts the steps (and the frozen ones): with a state logger."""
        return self._logger is not None

    @property
    def counts_by_time(self):
        """Whether the monitor counts the steps by the time checked (``time_step_s``)."""
        return self._logger is None and self._step_s is not None

    @property
    def last_velocities(self):
        """The last logged step's velocities (to resume a count in a branch)."""
        return None if self._last_v is None else self._last_v.copy()

    def resume(self, stats, last_velocities):
        """Continue a count made by another monitor (a branched run's prefix)."""
        self.stats = dataclasses.replace(stats)
        self._last_v = last_velocities

    def snapshot(self):
        """What the monitor carries from one check to the next (energy account, airborne
        time, the last step's velocities): ``sim.resolve`` runs a window from a saved state
        and hands the state back."""
        return (None if self._energy is None else list(self._energy), self._airborne_since,
                self.last_velocities, self._checked_s)

    def restore(self, snapshot):
        energy, airborne, last_v, self._checked_s = snapshot
        self._energy = None if energy is None else list(energy)
        self._airborne_since = airborne
        self._last_v = None if last_v is None else last_v.copy()

    def check(self, root_context):
        """Counts the frozen steps since the last check, then checks the state."""
        if self._logger is not None:
            self._count_frozen(root_context)
        elif self._step_s is not None:
            t, h = root_context.get_time(), self._step_s
            # The updates at k h in [last check, t): AdvanceTo(t) leaves the one due at t.
            self.stats.steps += (math.ceil(t / h - 1e-6) - math.ceil(self._checked_s / h - 1e-6))
            self._checked_s = t
        plant = self._plant
        x = plant.GetPositionsAndVelocities(plant.GetMyContextFromRoot(root_context))
        v = x[self._nq:]
        if math.isfinite(x.dot(x)) and v.dot(v) < MAX_GENERALIZED_SPEED ** 2:
            if self._road is not None:
                self._check_road_and_energy(root_context, x)
            return
        t = root_context.get_time()
        bad = np.flatnonzero(~np.isfinite(x))
        if bad.size:
            what = f"{self._names[bad[0]]} is {x[bad[0]]}"
        else:
            i = int(np.argmax(np.abs(v)))
            if abs(v[i]) < MAX_GENERALIZED_SPEED:
                return
            what = (f"{self._names[self._nq + i]} = {v[i]:.4g} beyond ±"
                    f"{MAX_GENERALIZED_SPEED:g} (m/s or rad/s)")
        culprit = _first_non_finite(self._diagram, root_context)
        raise DivergenceError(
            f"diverged at t = {t:.6f} s: {what}"
            + (f"; first system with non-finite outputs: {culprit}" if culprit else "")
            + "; a smaller plant.time_step or gentler inputs may help")

    def _check_road_and_energy(self, root_context, x):
        road, plant = self._road, self._plant
        t = root_context.get_time()
        loads = road.tyre.GetOutputPort("tyre_loads").Eval(
            road.tyre.GetMyContextFromRoot(root_context))
        pc = plant.GetMyContextFromRoot(root_context)
        if (np.all(loads[:4] <= 0.0)
                and road.chassis.EvalPoseInWorld(pc).translation()[0] <= road.flat_up_to_m):
            if self._airborne_since is None:
                self._airborne_since = t
            elif t - self._airborne_since > road.airborne_limit_s:
                raise DivergenceError(
                    f"diverged at t = {t:.6f} s: left the road: all four tyre loads zero "
                    f"since t = "
                    f"{self._airborne_since:.6f} s on a flat road, beyond "
                    f"simulator.airborne_limit_s = {road.airborne_limit_s:g} s; a smaller "
                    "plant.time_step or a softer tyre may help")
        else:
            self._airborne_since = None
        deflection = loads[4:8]
        energy = (plant.EvalKineticEnergy(pc) + plant.EvalPotentialEnergy(pc)
                  + 0.5 * road.radial_stiffness_Npm * float(deflection.dot(deflection)))
        if self._ballast is not None:
            index, ballast_kg = self._ballast
            energy -= 0.5 * ballast_kg * x[self._nq + index] ** 2
        u = plant.get_net_actuation_output_port().Eval(pc)
        power = float(np.abs(x[self._nq:] * (self._actuation @ u)).sum())
        if road.wheels:
            diagnostics = road.tyre.GetOutputPort("tyre_diagnostics").Eval(
                road.tyre.GetMyContextFromRoot(root_context))
            per_wheel = len(diagnostics) // len(road.wheels)
            for k, wheel in enumerate(road.wheels):
                spin = np.linalg.norm(wheel.EvalSpatialVelocityInWorld(pc).rotational())
                power += abs(diagnostics[per_wheel * k]) * spin * (2.0 / 3.0) * deflection[k]
        if self._energy is None:
            self._energy = [energy, 0.0, power, t, t]
            return
        start, work, last_power, last_t, start_t = self._energy
        work += 0.5 * (power + last_power) * (t - last_t)
        self._energy = [start, work, power, t, start_t]
        self.stats.energy_gain_J = max(self.stats.energy_gain_J, energy - start - work)
        gain = energy - start - work
        if gain > self._slack_J:
            raise DivergenceError(
                f"diverged at t = {t:.6f} s: gained energy: the car's mechanical energy is "
                f"{energy:.6g} J, "
                f"{gain:.4g} J above its {start:.6g} J at t = {start_t:.6f} s plus the "
                f"{work:.4g} J its actuators could have given (allowed: {self._slack_J:.3g} J); "
                "a smaller plant.time_step or a softer tyre may help")

    def _count_frozen(self, root_context):
        log = self._logger.FindMutableLog(root_context)
        data = log.data()
        if data.shape[1] == 0:
            return
        v = data[self._nq_instance:, :]
        times = log.sample_times()
        if self._last_v is not None:
            v = np.hstack([self._last_v[:, None], v])
            times = np.concatenate([[np.nan], times])
        frozen = np.all(v[:, 1:] == v[:, :-1], axis=0)
        self.stats.steps += int(frozen.size)
        count = int(np.count_nonzero(frozen))
        if count:
            self.stats.frozen_steps += count
            if self.stats.first_frozen_time_s is None:
                self.stats.first_frozen_time_s = float(times[1:][frozen][0])
        self._last_v = v[:, -1].copy()
        log.Clear()


def _coordinate_names(plant):
    """'position of joint X' / 'velocity of joint X' for every state entry."""
    names = [""] * plant.num_multibody_states()
    nq = plant.num_positions()
    for index in plant.GetJointIndices():
        joint = plant.get_joint(index)
        for k in range(joint.num_positions()):
            names[joint.position_start() + k] = f"position of joint '{joint.name()}'"
        for k in range(joint.num_velocities()):
            names[nq + joint.velocity_start() + k] = f"velocity of joint '{joint.name()}'"
    return names


def _first_non_finite(diagram, root_context):
    for system in diagram.GetSystems():
        context = system.GetMyContextFromRoot(root_context)
        for i in range(system.num_output_ports()):
            port = system.get_output_port(i)
            try:
                value = port.Eval(context)
            except Exception:  # abstract ports that cannot be read as vectors
                continue
            if isinstance(value, np.ndarray) and not np.all(np.isfinite(value)):
                return f"{system.get_name()} (port {port.get_name()})"
    return None
