"""The friction rig's closed-form cases (``study.rig.closed_forms``) on the two routes to a
converged answer: the **local** route (the run at its step, each slip of the
block resolved in a window at halved steps, ``sim.resolve`` through ``run_rig(resolve=...)``)
and the **global** route (the whole run at h, h/2, h/4, ... until every reading has
converged, ``sim.convergence.classify``, or the finest step), each reading with its error, and
whether they agree: |local - global| <= error_local + error_global.

Tolerances (the global route's, and the windows' ``position_tolerance_m``), from the law:
a position to Δmax (the law's pre-sliding range: a stuck block sits anywhere within its creep
of where it stuck, as its load sets it; a step error below that is below what the law itself
resolves), a belt's time to Δmax / V (the time the belt takes to carry a stuck block through
Δmax), a velocity to Δv (the law's static band), a count exactly.

The local route's errors, from its windows' (``Resolver.record``): a reading at time t
carries the position errors of every window that started before t (``position_error_at``: a
rest position carries every earlier window's error, and a reading inside a window its
window's, whose error is of the window's end). A reading before any window has no error of
the local route's (NaN: nothing slipped, the run is the plain run at its step; the incline at
8°): it is compared by its difference only. Mapped to each reading:

- belt (stuck, the block moves with the belt at V): a slip starts where the spring's force
  reaches μs N, at x_1 = q + V t (q where the block stuck, in the belt's frame): x_1 and the
  lag D carry the position error P(t); the start's time moves by (δx_1 + δq) / V <= 2 P / V,
  so a period (between two starts) carries 2 (P(t_k) + P(t_{k-1})) / V.
- oscillator: a turning point carries P(t); a decay per cycle (two turns apart) the sum of
  both turns' errors.
- incline: the final position carries P(end); sliding at a constant acceleration a from a
  break-away whose time the step shifts by δt, x moves by v δt and v by a δt: the final
  velocity carries (|a| / |v|) P(end); the number of break-aways (stick or slide) is exact.
"""

import dataclasses
import math
import time

import numpy as np

from drake_car.law.friction.coulomb import incline_acceleration_mps2
from drake_car.scene.scene import ResolveEvents
from drake_car.sim.convergence import classify
from drake_car.sim.rigs.friction import RigOptions, run_rig
from drake_car.study.rig.closed_forms import (
    BELT, BELT_DURATION_S, BELT_LAW, INCLINE_DURATION_S, INCLINE_LAW, OSCILLATOR,
    OSCILLATOR_DURATION_S, OSCILLATOR_LAW, incline_options, read_belt, read_incline,
    read_oscillator)

CASES = ("belt", "oscillator", "incline_8", "incline_14")
FINEST_STEP_S = 3.125e-5  # both routes' finest step (the car's ``ResolveEvents`` default)
BELT_SHAPE = {k: BELT[k] for k in ("mass_kg", "normal_force_N", "spring_Npm", "belt_speed_mps")}


@dataclasses.dataclass
class Case:
    law: object
    duration_s: float
    options: object  # time_step_s, scheme -> RigOptions


def case(name):
    """The closed-form case ``name`` (one of ``CASES``)."""
    if name == "belt":
        return Case(BELT_LAW, BELT_DURATION_S,
                    lambda dt, scheme: RigOptions(time_step_s=dt, scheme=scheme, **BELT))
    if name == "oscillator":
        return Case(OSCILLATOR_LAW, OSCILLATOR_DURATION_S,
                    lambda dt, scheme: RigOptions(time_step_s=dt, scheme=scheme, **OSCILLATOR))
    angle = float(name.split("_")[1])
    return Case(INCLINE_LAW, INCLINE_DURATION_S,
                lambda dt, scheme: incline_options(angle, dt, scheme))


def settings(law, finest_step_s=FINEST_STEP_S):
    """The local route's ``ResolveEvents``: rest positions to Δmax (see the module)."""
    return ResolveEvents(position_tolerance_m=law.dmax_translation_m, finest_step_s=finest_step_s,
                         solver_twin=False)  # the rig has no SAP ballast


def run(name, scheme, time_step_s, resolve=None):
    """The case at ``time_step_s`` (recorded every step), optionally resolved locally."""
    c = case(name)
    return run_rig(c.options(time_step_s, scheme), c.law, duration_s=c.duration_s,
                   record_period_s=time_step_s, resolve=resolve)


def readings(name, history):
    """{reading: (values, the times they are read at)} of a case's history."""
    t_end = float(history["t"][-1])
    if name == "belt":
        r = read_belt(history, BELT_LAW, **BELT_SHAPE)
        return {"period_s": (r.periods_s, r.slip_start_s),
                "slip_start_m": (r.slip_start_m, r.slip_start_s),
                "lag_m": (r.lag_m, r.slip_start_s)}
    if name == "oscillator":
        r = read_oscillator(history)
        return {"turn_m": (r.turns_m, r.turn_times_s),
                "decay_per_cycle_m": (r.decay_per_cycle_m, r.turn_times_s[1:])}  # unused times
    x, v, _ = read_incline(history, case(name).duration_s)
    moving = np.abs(history["v_mps"]) > INCLINE_LAW.dv_translation_mps
    starts = np.count_nonzero(moving[1:] & ~moving[:-1]) + int(moving[0])
    return {"final_x_m": (np.array([x]), np.array([t_end])),
            "final_v_mps": (np.array([v]), np.array([t_end])),
            "slides": (np.array([float(starts)]), np.array([t_end]))}


def tolerance(name, reading):
    """A reading's tolerance, from the law (see the module)."""
    law = case(name).law
    if reading == "period_s":
        return law.dmax_translation_m / BELT["belt_speed_mps"]
    if reading.endswith("_mps"):
        return law.dv_translation_mps
    if reading == "slides":
        return 0.5
    return law.dmax_translation_m


def position_error_at(resolution, t):
    """The position error a reading at ``t`` carries on the local route: the sum of the
    windows' errors that started before it (see the module)."""
    return sum(sum(w["position_errors"].values()) for w in resolution["windows"]
               if w["start_s"] < t)


def local_errors(name, values, resolution):
    """{reading: errors} on the local route (see the module for each mapping)."""
    def p_at(times):  # NaN where no window started before: nothing slipped to resolve
        return np.array([position_error_at(resolution, t)
                         if any(w["start_s"] < t for w in resolution["windows"]) else math.nan
                         for t in times])
    errors = {}
    for reading, (value, times) in values.items():
        if reading == "period_s":  # between two slip starts, each moved by 2 P / V
            starts = np.concatenate([[times[0] - value[0]], times]) if len(times) else times
            moved = 2 * p_at(starts) / BELT["belt_speed_mps"]
            errors[reading] = moved[:-1] + moved[1:]
        elif reading == "decay_per_cycle_m":  # |x0| - |turn 2|, |turn 1| - |turn 3|, ...
            amplitude = np.concatenate([[0.0], p_at(values["turn_m"][1])])  # x0: exact
            errors[reading] = amplitude[:-2] + amplitude[2:]
        elif reading == "final_v_mps":
            c = case(name)
            theta = math.radians(c.options(1e-3, "fast").incline_deg)
            a = abs(incline_acceleration_mps2(incline_rad=theta, mu_d=c.law.mu_d))
            p = p_at(times)
            errors[reading] = a / np.maximum(np.abs(value), 1e-300) * p
        elif reading == "slides":
            errors[reading] = np.zeros_like(value)
        else:
            errors[reading] = p_at(times)
    return errors


def plain_route(name, scheme, time_step_s):
    """The case at its own step without resolution: {readings, cpu_s}."""
    began = time.process_time()
    values = readings(name, run(name, scheme, time_step_s).history)
    return {"readings": {k: v for k, (v, _) in values.items()},
            "cpu_s": time.process_time() - began}


def local_route(name, scheme, time_step_s, finest_step_s=FINEST_STEP_S):
    """The case on the local route: {readings, errors, cpu_s, resolution}."""
    began = time.process_time()
    result = run(name, scheme, time_step_s, settings(case(name).law, finest_step_s))
    values = readings(name, result.history)
    cpu = time.process_time() - began
    return {"readings": {k: v for k, (v, _) in values.items()},
            "errors": local_errors(name, values, result.resolution), "cpu_s": cpu,
            "resolution": result.resolution}


def global_route(name, scheme, time_step_s, finest_step_s=FINEST_STEP_S):
    """The case at h, h/2, ... until every reading has converged (``classify``, three steps,
    the tolerance from the law) or the finest step: {readings, errors, converged, steps_s,
    cpu_s}. A reading whose count differs between the last three steps has no error (inf)."""
    began = time.process_time()
    runs, dt = [], time_step_s
    while True:
        runs.append(readings(name, run(name, scheme, dt).history))
        found = _classified(name, runs) if len(runs) >= 3 else None
        if (found is not None and all(all(found[1][k]) for k in found[1])) or \
                dt / 2 < finest_step_s * (1 - 1e-9):
            break
        dt /= 2
    values, converged, errors = _classified(name, runs)
    return {"readings": values, "errors": errors, "converged": converged,
            "steps_s": [time_step_s / 2 ** k for k in range(len(runs))],
            "cpu_s": time.process_time() - began}


def _classified(name, runs):
    values, converged, errors = {}, {}, {}
    for reading in runs[-1]:
        series = [r[reading][0] for r in runs[-3:]]
        values[reading] = series[-1]
        if len({len(s) for s in series}) != 1:
            converged[reading] = [False] * len(series[-1])
            errors[reading] = np.full(len(series[-1]), math.inf)
            continue
        found = [classify([s[k] for s in series], tolerance(name, reading))
                 for k in range(len(series[-1]))]
        converged[reading] = [f["converged"] for f in found]
        errors[reading] = np.array([f["error"] for f in found])
    return values, converged, errors


def compare(local, reference):
    """Rows (reading, index, local, error_local, global, error_global, |diff|, agree) of the
    readings both routes have (the common leading cycles where their counts differ; agree
    None where the local route states no error)."""
    rows = []
    for reading, values in local["readings"].items():
        other = reference["readings"].get(reading)
        if other is None:
            continue
        for k in range(min(len(values), len(other))):
            a, b = float(values[k]), float(other[k])
            ea, eb = float(local["errors"][reading][k]), float(reference["errors"][reading][k])
            diff = abs(a - b)
            agree = None if math.isnan(ea + eb) else bool(diff <= (ea + eb) * (1 + 1e-9))
            rows.append((reading, k, a, ea, b, eb, diff, agree))
        if len(values) != len(other):
            rows.append((reading, "count", len(values), 0.0, len(other), 0.0,
                         abs(len(values) - len(other)), False))
    return rows
