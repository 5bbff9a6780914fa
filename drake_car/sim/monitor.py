"""The divergence monitor and the frozen-step count of every run.

Divergence: the runner advances in chunks of ``simulator.monitor_period_s`` and checks the
plant's state after each: a non-finite entry, or a generalized speed beyond
``MAX_GENERALIZED_SPEED``, stops the run with a ``DivergenceError`` that names the time, the
quantity (the joint and its value) and the first system whose outputs are not finite.

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


class DivergenceError(SimulationFailure):
    """The simulation diverged; the message names the time, the quantity and the system."""


@dataclasses.dataclass
class MonitorStats:
    frozen_steps: int = 0
    first_frozen_time_s: float | None = None
    steps: int = 0


class Monitor:
    """Checks ``plant``'s state in ``diagram``; counts frozen steps from ``state_logger`` (a
    VectorLogSink of one model instance's state [q; v], sampled every step), when given."""

    def __init__(self, plant, diagram, *, state_logger=None, instance=None):
        self._plant, self._diagram = plant, diagram
        self._logger = state_logger
        self._nq = plant.num_positions()
        self._nq_instance = plant.num_positions(instance) if instance is not None else 0
        self._names = _coordinate_names(plant)
        self.stats = MonitorStats()
        self._last_v = None

    @property
    def last_velocities(self):
        """The last logged step's velocities (to resume a count in a branch)."""
        return None if self._last_v is None else self._last_v.copy()

    def resume(self, stats, last_velocities):
        """Continue a count made by another monitor (a branched run's prefix)."""
        self.stats = dataclasses.replace(stats)
        self._last_v = last_velocities

    def check(self, root_context):
        """Counts the frozen steps since the last check, then checks the state."""
        if self._logger is not None:
            self._count_frozen(root_context)
        plant = self._plant
        x = plant.GetPositionsAndVelocities(plant.GetMyContextFromRoot(root_context))
        v = x[self._nq:]
        if math.isfinite(x.dot(x)) and v.dot(v) < MAX_GENERALIZED_SPEED ** 2:
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
