"""The one-DOF friction rig's closed-form cases (``law.friction.coulomb``), run and read: a block
stick-slipping on a belt (its period, where its slips start, how far it lags the belt), a free
oscillator with friction (its amplitude's decay per cycle) and an incline (stick below tan⁻¹ μs,
slide above). Used by benchmarks/friction_convergence.py and tests/test_reference_convergence.py.

Event times are interpolated between the samples (linearly, in the relative velocity; the
samples need not be evenly spaced: ``study.rig.routes`` reads locally resolved runs), so a
period is read to a fraction of a step, not to the step: a period read from the steps at
which the phase flag flips carries an error of up to one step that does not shrink with the
scheme's own error.
"""

import dataclasses
import math

import numpy as np

from drake_car.law.friction.coulomb import (
    belt_exit_speed_mps, belt_law_period_s, belt_shift, oscillator_decay_per_cycle_m,
    oscillator_turn_bound_m)
from drake_car.law.friction.frd import StrutFrictionParameters
from drake_car.sim.rigs.friction import RigOptions, simulate_rig

# The belt of the accuracy study: 30 kg on 6 kN/m over a belt at 0.1 m/s, N = 300 N,
# μs = 0.4, μd = 0.3: a stick of x_s - x_d = 5 mm each way (10 mm) and a cycle of 0.46 s. Δv = 1 % of the belt's
# speed, Δmax = 1 % of the stick's 10 mm.
BELT = dict(mass_kg=30.0, normal_force_N=300.0, spring_Npm=6000.0, belt_speed_mps=0.1)
BELT_LAW = StrutFrictionParameters(mu_s=0.4, mu_d=0.3, dv_translation_mps=1e-3,
                                   dmax_translation_m=1e-4)
BELT_DURATION_S = 1.6  # the first stick (from rest) and three whole cycles
# A free oscillator: 30 kg on 20 kN/m released at 50 mm, N = 500 N, the paper's law
# (μs = 0.2, μd = 0.15, Δv = 1e-4 m/s, Δmax = 5 µm): 15 mm of decay per cycle.
OSCILLATOR = dict(mass_kg=30.0, normal_force_N=500.0, spring_Npm=2.0e4, x0_m=0.05)
OSCILLATOR_LAW = StrutFrictionParameters(mu_s=0.2, mu_d=0.15)
# Five half cycles of 0.12 s: turns at 42.5 ... 12.5 mm, the last at k|x| = 2.5 μs N.
OSCILLATOR_DURATION_S = 0.68
# An incline: 30 kg at 8° (sticks, tan θ = 0.14 < μs) and 14° (slides, tan θ = 0.25).
INCLINE_LAW = StrutFrictionParameters(mu_s=0.2, mu_d=0.15)
INCLINE_DURATION_S = 0.3


def crossings(t, v, level, direction):
    """Times where ``v`` crosses ``level`` (direction -1: downward, +1: upward), interpolated
    linearly between the samples, with the sample index before each."""
    above = v > level
    if direction < 0:
        index = np.flatnonzero(above[:-1] & ~above[1:])
    else:
        index = np.flatnonzero(~above[:-1] & above[1:])
    fraction = (level - v[index]) / (v[index + 1] - v[index])
    return t[index] + fraction * (t[index + 1] - t[index]), index, fraction


@dataclasses.dataclass
class BeltReading:
    """What one belt run shows, cycle by cycle after the first (which starts from rest):
    ``periods_s`` between successive slip starts; ``slip_start_m`` x_1 where each cycle's
    closing slip starts (u falls below -1.5 Δv); ``lag_m`` D, how far the block lagged the belt
    between the previous slip's end (u back above -1.5 Δv) and that start; ``law_period_s`` the
    period these give by ``coulomb.belt_law_period_s`` (the law's identity, item 1 there: a
    check that the slip between the band's edges is Coulomb's arc)."""

    periods_s: np.ndarray
    slip_start_m: np.ndarray
    lag_m: np.ndarray
    law_period_s: np.ndarray
    slip_start_s: np.ndarray = None  # when each of those slips starts


def read_belt(history, law, *, mass_kg, normal_force_N, spring_Npm, belt_speed_mps):
    """A ``BeltReading`` of a rig history (``sim.rigs.friction.simulate_rig``), its samples at
    any times (a locally resolved run's windows are sampled at their own steps)."""
    pair = law.translation()
    edge = belt_exit_speed_mps(pair, belt_speed_mps) - belt_speed_mps  # -1.5 Δv
    t, x, u = history["t"], history["x_m"], history["v_mps"]
    starts, i0, f0 = crossings(t, u, edge, -1)
    ends, i1, f1 = crossings(t, u, edge, +1)
    x_start = x[i0] + f0 * (x[i0 + 1] - x[i0])
    x_end = x[i1] + f1 * (x[i1 + 1] - x[i1])
    lags, identity = [], []
    for k in range(1, len(starts)):  # each cycle: slip k - 1's start to slip k's
        before = np.flatnonzero((ends < starts[k]) & (ends > starts[k - 1]))
        if before.size != 1:
            raise ValueError(f"slip {k}: expected one re-entry before it, found {before.size}")
        j = before[0]
        lag = belt_speed_mps * (starts[k] - ends[j]) - (x_start[k] - x_end[j])
        lags.append(lag)
        # The arc from this cycle's slip start, the stick to the next one's (which a limit
        # cycle starts at the same place).
        identity.append(belt_law_period_s(
            mass_kg=mass_kg, spring_Npm=spring_Npm, normal_N=normal_force_N, law=pair,
            belt_speed_mps=belt_speed_mps, slip_start_m=x_start[k - 1], lag_m=lag)
            + (x_start[k] - x_start[k - 1]) / belt_speed_mps)
    return BeltReading(np.diff(starts), x_start[1:], np.array(lags), np.array(identity),
                       starts[1:])


def run_belt(scheme, time_step_s, *, law=BELT_LAW, case=None, duration_s=BELT_DURATION_S):
    """The belt case run with ``scheme`` at ``time_step_s``, recorded every step, read."""
    case = dict(BELT if case is None else case)
    history = simulate_rig(RigOptions(time_step_s=time_step_s, scheme=scheme, **case), law,
                           duration_s=duration_s, record_period_s=time_step_s)
    return read_belt(history, law, mass_kg=case["mass_kg"],
                     normal_force_N=case["normal_force_N"], spring_Npm=case["spring_Npm"],
                     belt_speed_mps=case["belt_speed_mps"])


def belt_bracket(law=BELT_LAW, case=None):
    """``coulomb.belt_shift`` for the belt case."""
    case = dict(BELT if case is None else case)
    return belt_shift(mass_kg=case["mass_kg"], spring_Npm=case["spring_Npm"],
                      normal_N=case["normal_force_N"], law=law.translation(),
                      belt_speed_mps=case["belt_speed_mps"])


@dataclasses.dataclass
class OscillatorReading:
    """Turning points (interpolated where the velocity crosses 0 outside the first 1 ms) and
    the decay per cycle between turning points two apart; ``bound_m`` the law's bound on each
    turn's shift (``coulomb.oscillator_turn_bound_m``) at the last turn used."""

    turns_m: np.ndarray
    decay_per_cycle_m: np.ndarray
    coulomb_m: float
    bound_m: float
    turn_times_s: np.ndarray = None


def run_oscillator(scheme, time_step_s, *, law=OSCILLATOR_LAW, case=None,
                   duration_s=OSCILLATOR_DURATION_S):
    case = dict(OSCILLATOR if case is None else case)
    history = simulate_rig(RigOptions(time_step_s=time_step_s, scheme=scheme, **case), law,
                           duration_s=duration_s, record_period_s=time_step_s)
    return read_oscillator(history, law, case)


def read_oscillator(history, law=OSCILLATOR_LAW, case=None):
    """An ``OscillatorReading`` of a rig history (samples at any times: a locally resolved
    run's windows are sampled at their own steps)."""
    case = dict(OSCILLATOR if case is None else case)
    t, x, v = history["t"], history["x_m"], history["v_mps"]
    turns = []
    for direction in (-1, +1):
        _, index, fraction = crossings(t, v, 0.0, direction)
        for i, f in zip(index, fraction):
            if t[i] > 1e-3:
                turns.append((t[i] + f * (t[i + 1] - t[i]), x[i] + f * (x[i + 1] - x[i])))
    turns.sort()
    # The turning points alternate in sign; a cycle spans two of them.
    positions = np.array([p for _, p in turns] if turns else [])
    amplitude = np.abs(np.concatenate([[case["x0_m"]], positions]))
    decay = amplitude[:-2] - amplitude[2:]
    pair = law.translation()
    last = amplitude[-1] if amplitude.size else case["x0_m"]
    bound = oscillator_turn_bound_m(mass_kg=case["mass_kg"], spring_Npm=case["spring_Npm"],
                                    normal_N=case["normal_force_N"], law=pair,
                                    spring_force_N=case["spring_Npm"] * last)
    return OscillatorReading(positions, decay, oscillator_decay_per_cycle_m(
        spring_Npm=case["spring_Npm"], normal_N=case["normal_force_N"], mu_d=pair.mu_d), bound,
        np.array([time for time, _ in turns]))


def incline_options(angle_deg, time_step_s, scheme, mass_kg=30.0):
    """The incline case's rig: N = m g cos θ."""
    theta = math.radians(angle_deg)
    return RigOptions(mass_kg=mass_kg, normal_force_N=mass_kg * 9.81 * math.cos(theta),
                      incline_deg=angle_deg, time_step_s=time_step_s, scheme=scheme)


def run_incline(scheme, time_step_s, angle_deg, *, law=INCLINE_LAW, mass_kg=30.0,
                duration_s=INCLINE_DURATION_S):
    """(final position, final velocity, the velocity's slope over the last half) of the block
    on an incline of ``angle_deg``; N = m g cos θ."""
    h = simulate_rig(incline_options(angle_deg, time_step_s, scheme, mass_kg), law,
                     duration_s=duration_s, record_period_s=time_step_s)
    return read_incline(h, duration_s)


def read_incline(h, duration_s=INCLINE_DURATION_S):
    """``run_incline``'s reading of a rig history."""
    half = h["t"] >= 0.5 * duration_s
    t, v = h["t"][half], h["v_mps"][half]
    return float(h["x_m"][-1]), float(h["v_mps"][-1]), float((v[-1] - v[0]) / (t[-1] - t[0]))
