"""A divergence monitor: stops a simulation with an error naming the time and the system,
instead of letting NaNs run into the results."""

import dataclasses
import math

import numpy as np
from pydrake.systems.framework import EventStatus

# Limits a car on a road never reaches (generalized speeds in m/s or rad/s: a wheel at 250 km/h
# spins at ~220 rad/s).
MAX_GENERALIZED_SPEED = 500.0


class DivergenceError(RuntimeError):
    """The simulation diverged; the message names the time and the system."""


@dataclasses.dataclass
class MonitorStats:
    """Steps in which the car's generalized velocities did not change at all (bitwise): SAP
    returned its initial guess, dropping the step's impulses (see systems/sap_pacer.py)."""

    frozen_steps: int = 0
    first_frozen_time_s: float | None = None
    steps: int = 0


def attach_monitor(simulator, built, *, max_speed=MAX_GENERALIZED_SPEED):
    """Checks the plant's state after every step; on a non-finite or runaway state, finds the
    first system whose outputs are not finite and stops the simulation naming it. Counts the
    car's frozen steps into the returned MonitorStats."""
    plant = built.plant
    diagram = built.diagram
    nq = plant.num_positions()
    max_speed_squared = max_speed * max_speed
    instance = built.car.instance
    stats = MonitorStats()
    last = {"updates": None, "v": None}

    def monitor(root_context):
        pc = plant.GetMyContextFromRoot(root_context)
        x = plant.GetPositionsAndVelocities(pc)
        v = x[nq:]
        # A step that ran the plant's discrete update (AdvanceTo and the loggers' publish
        # times also end short steps that do not) and left the car's velocities unchanged.
        updates = simulator.get_num_discrete_updates()
        v_car = plant.GetVelocities(pc, instance)
        if last["updates"] is None or updates > last["updates"]:
            if last["updates"] is not None:
                stats.steps += 1
                if np.array_equal(v_car, last["v"]):
                    stats.frozen_steps += 1
                    if stats.first_frozen_time_s is None:
                        stats.first_frozen_time_s = root_context.get_time()
            last["updates"], last["v"] = updates, v_car
        if v.dot(v) < max_speed_squared and math.isfinite(x.dot(x)):
            return EventStatus.Succeeded()
        if np.all(np.isfinite(x)) and np.max(np.abs(v), initial=0.0) < max_speed:
            return EventStatus.Succeeded()
        t = root_context.get_time()
        culprit = _first_non_finite(diagram, root_context) or plant.get_name()
        what = ("non-finite state" if not np.all(np.isfinite(x))
                else f"generalized speed {np.max(np.abs(v)):.3g} beyond {max_speed:g}")
        return EventStatus.Failed(diagram, f"diverged at t = {t:.6f} s: {what}; first system "
                                           f"with non-finite outputs: {culprit}")

    simulator.set_monitor(monitor)
    return stats


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


def run_checked(simulator, end_time_s):
    """AdvanceTo that turns a monitor failure into a DivergenceError."""
    try:
        simulator.AdvanceTo(end_time_s)
    except RuntimeError as e:
        if "diverged at t =" in str(e):
            raise DivergenceError(str(e)) from e
        raise
