"""A measured strut loop checked against the rig it claims to come from, before it is fitted
(``study.rig.fit``), and the fit's residual against the loop's own noise after.

A loop is a CSV of samples: ``stroke_m`` (the rod's extension from its design position, m),
``force_N`` (the load cell's force on the knuckle, N, + along + stroke) and optionally
``t_s`` (s). Refused (``LoopError``, naming the column or the option and what is allowed):

- units by magnitude: a stroke beyond the strut's travel on the rig (``sim.rigs.strut``'s limit:
  the rod keeps a quarter of its guide l, and at most 0.05 m), a stroke in mm is a thousand
  times that; a force beyond what μ <= 2 allows at the side load (eq. 4's N(q) on the rig,
  times ``OVERSHOOT`` for the rig's peak after a break-away, plus the knuckle's inertia
  m A ω² and ``NOISE_SIGMAS`` of the loop's noise); a sliding force of the opposite sign to
  the motion (the force column's convention reversed);
- the test against the options: the side load must be given (it scales N, which the loop
  alone cannot tell), and where it acts on the strut axis (its lever to the guide sets N too:
  the same force gives 0.80 of N at the shipped strut's lower mount as at its top mount); by
  default where the rig's own loops apply it, the top mount (``sim.rigs.at_rest``); the
  stroke's amplitude and frequency are taken from the loop (its reversals: half their span,
  their spacing) and checked against --amplitude_m and --frequency_hz when those are given,
  within ``TEST_TOLERANCE``; the time base is the ``t_s`` column (uniform) or
  --sample_period_s, and one is checked against the other.
  The actuator's amplitude is the knuckle's plus the load path's give at the reversal (the
  sliding force over the rig's stiffness: the knuckle stops that far short of the actuator).

After the fit (``residual_check``): the loop's noise is the force's scatter between
neighbouring samples while sliding (the second difference's robust spread / √6: a white noise
σ gives σ√6), floored by what the law leaves out there (the knuckle's inertia m ω² A / 2); a
residual above ``RESIDUAL_RATIO`` times that is flagged: the law (Coulomb friction μd·N while
sliding) does not describe the loop, and μs, μd are not confident values.
"""

import csv
import dataclasses
import io
import math

import numpy as np

from drake_car.law.checks import read_input_file
from drake_car.sim.rigs.at_rest import SIDE_FORCE_POINT_BELOW_TOP_M
from drake_car.sim.rigs.strut import (
    MAX_STROKE_AMPLITUDE_M, StrutRigOptions, eq4_normal_force_N, stroke_limit_m)
from drake_car.study.rig.analysis import LoopError, reversals

MU_MAX = 2.0  # the friction law's limit (law.friction.frd)
# [EST] the rig's break-away peak over μs·N: tests/test_strut_rig.py's bound is 1.17-1.18 μs
# for this rig; 1.25 leaves room for another rig's load path.
OVERSHOOT = 1.25
NOISE_SIGMAS = 5.0
# [EST] how far a loop's amplitude and frequency may be from the options': a rig's actuator
# control and its LVDT's calibration agree within a few per cent.
TEST_TOLERANCE = 0.05
# [EST] a residual more than this many times the loop's noise is not noise: the law does not
# describe the loop (a white noise gives a ratio of 1; the synthetic loop gives 1.0).
RESIDUAL_RATIO = 3.0
# [EST] a measured loop's size limit: 100 s sampled at 10 kHz, ~40 bytes a row, is 40 MB.
MAX_LOOP_BYTES = 64_000_000


@dataclasses.dataclass
class Loop:
    stroke_m: np.ndarray
    force_N: np.ndarray
    t_s: np.ndarray | None = None


def read_loop(path):
    """The loop of CSV ``path`` (columns stroke_m, force_N, optionally t_s); LoopError."""
    data = read_input_file(path, "measured loop", limit=MAX_LOOP_BYTES, error=LoopError,
                           is_text="a CSV file", where="")
    try:
        rows = list(csv.DictReader(io.StringIO(data.decode("utf-8"), newline="")))
        columns = {name: np.array([float(r[name]) for r in rows])
                   for name in ("stroke_m", "force_N", "t_s") if rows and name in rows[0]}
        stroke, force = columns["stroke_m"], columns["force_N"]
    except UnicodeDecodeError as e:
        raise LoopError(f"not a text file (byte {e.start} is not UTF-8); a measured loop is a "
                        "CSV file") from None
    except (KeyError, ValueError, TypeError) as e:
        raise LoopError(f"must be a CSV with columns stroke_m, force_N and optionally t_s, "
                        f"numbers ({type(e).__name__}: {e})") from None
    if not (np.isfinite(stroke).all() and np.isfinite(force).all()):
        raise LoopError("the loop has a value that is not a finite number")
    return Loop(stroke, force, columns.get("t_s"))


def noise_N(force_N, mask=None):
    """The force's noise: the robust spread of its second difference / √6 (over ``mask``'s
    samples where given, a second difference counted where all three are in it)."""
    f = np.asarray(force_N, dtype=float)
    d2 = f[2:] - 2 * f[1:-1] + f[:-2]
    if mask is not None:
        d2 = d2[mask[2:] & mask[1:-1] & mask[:-2]]
    if len(d2) == 0:
        return 0.0
    return float(1.4826 * np.median(np.abs(d2 - np.median(d2))) / math.sqrt(6.0))


def _middles(stroke, turns):
    """Per half-cycle (between reversals): (its samples' mask of the middle half of its travel,
    its direction)."""
    out = []
    for a, b in zip(turns, turns[1:]):
        direction = math.copysign(1.0, stroke[b] - stroke[a])
        travel = (stroke - stroke[a]) * direction
        span = abs(stroke[b] - stroke[a])
        mask = np.zeros(len(stroke), dtype=bool)
        mask[a:b] = (travel[a:b] > 0.25 * span) & (travel[a:b] < 0.75 * span)
        out.append((mask, direction))
    return out


def side_force_where(front, options):
    """Where ``options``' side force acts, in words: at the top mount, at the strut's lower
    mount, or a distance below the top mount."""
    point = options.side_force_point(front)
    if point == 0:
        return "at the top mount"
    if point == front.strut_lower_mount_below_top_m:
        return f"at the strut's lower mount, {point:g} m below the top mount"
    return f"{point:g} m below the top mount"


def rig_of_loop(car, loop, *, side_force_N=None,
                side_force_point_below_top_m=SIDE_FORCE_POINT_BELOW_TOP_M, amplitude_m=None,
                frequency_hz=None, sample_period_s=None):
    """(StrutRigOptions of the test the loop came from, its sample period, notes of what was
    taken from the loop): the loop checked by magnitude and against the options given (see
    the module); ``side_force_point_below_top_m``: where the side force acts on the strut axis
    (default: the top mount, as the rig's own loops); LoopError naming what is wrong."""
    front = car.front
    stroke, force = loop.stroke_m, loop.force_N
    limit = stroke_limit_m(front)
    reach = float(np.max(np.abs(stroke)))
    if reach > limit:
        hint = (f" In mm it would reach {reach / 1000:.4g} m: is it in mm? stroke_m is in "
                "metres." if reach / 1000 <= limit else "")
        raise LoopError(f"the stroke reaches {reach:.4g} m, beyond the strut's travel on the rig "
                        f"(±{limit:g} m: the rod keeps a quarter of its guide l = "
                        f"{front.guide_length_l_m:g} m, and at most "
                        f"{MAX_STROKE_AMPLITUDE_M:g} m).{hint}")
    if side_force_N is None:
        raise LoopError("--side_force_N: must be given with --measured: the side load the loop "
                        "was measured at (N); the loop cannot tell it, and μ scales with it")
    turns = reversals(stroke)
    if len(turns) < 3:
        raise LoopError(f"the stroke has {len(turns)} reversals; at least 3 are needed")
    notes = []
    measured_amplitude = float(np.mean(np.abs(np.diff(stroke[turns]))) / 2)
    middles = _middles(stroke, turns)
    sliding = np.concatenate([force[m] * d for m, d in middles])
    options = StrutRigOptions(side_force_N=side_force_N,
                              side_force_point_below_top_m=side_force_point_below_top_m)
    give = float(np.median(np.abs(sliding))) / options.rig_stiffness_Npm
    amplitude = measured_amplitude + give
    if amplitude_m is None:
        notes.append(f"stroke amplitude {amplitude:.4g} m at the actuator (the loop's "
                     f"{measured_amplitude:.4g} m plus the load path's give {give:.2g} m)")
    elif abs(amplitude - amplitude_m) > TEST_TOLERANCE * amplitude_m:
        raise LoopError(f"its stroke amplitude is {measured_amplitude:.4g} m ({amplitude:.4g} m "
                        f"at the actuator, the load path's give added), not --amplitude_m "
                        f"{amplitude_m:g} (within {TEST_TOLERANCE:.0%}); leave --amplitude_m "
                        "out to take it from the loop")
    else:
        amplitude = amplitude_m
    period = _sample_period(loop, sample_period_s)
    half_period = _half_period_samples(stroke, turns) * period
    frequency = 1.0 / (2.0 * half_period)
    if frequency_hz is None:
        notes.append(f"stroke frequency {frequency:.4g} Hz")
    elif abs(frequency - frequency_hz) > TEST_TOLERANCE * frequency_hz:
        raise LoopError(f"its stroke frequency is {frequency:.3f} Hz (a reversal every "
                        f"{half_period / period:.0f} samples of {period:g} s), not --frequency_hz "
                        f"{frequency_hz:g} (within {TEST_TOLERANCE:.0%}); check --sample_period_s "
                        "or leave --frequency_hz out to take it from the loop")
    else:
        frequency = frequency_hz
    options = dataclasses.replace(options, stroke_amplitude_m=amplitude,
                                  stroke_frequency_hz=frequency)
    try:
        options.check(front)
    except ValueError as e:
        raise LoopError(f"the loop's test is not one the rig can run: {e}") from None
    if np.median(sliding) < 0:
        raise LoopError(f"the force opposes the stroke's motion while sliding (median "
                        f"{np.median(sliding):.4g} N): its sign is the opposite of the rig's "
                        "(force_N: the load cell's force on the knuckle, + along + stroke); "
                        "negate the column")
    _check_force(car, options, stroke, force, noise_N(force, np.any([m for m, _ in middles],
                                                                    axis=0)))
    return options, period, notes


def _half_period_samples(stroke, turns):
    """The stroke's half period in samples: the slope of its mid-stroke crossings (linearly
    interpolated, one per half-cycle) against their count. The crossings, where the stroke is
    fastest, are sharp; its reversals are not (the rod rests there while it sticks)."""
    centre = 0.5 * (np.max(stroke) + np.min(stroke))
    crossings = []
    for a, b in zip(turns, turns[1:]):
        y = stroke[a:b + 1] - centre
        i = int(np.argmax(np.sign(y[1:]) != np.sign(y[:-1])))
        crossings.append(a + i + y[i] / (y[i] - y[i + 1]))
    return float(np.polyfit(np.arange(len(crossings)), crossings, 1)[0])


def _sample_period(loop, sample_period_s):
    if loop.t_s is None:
        if sample_period_s is None:
            raise LoopError("has no t_s column: give --sample_period_s (the time between its "
                            "samples)")
        return sample_period_s
    steps = np.diff(loop.t_s)
    step = float(np.median(steps)) if len(steps) else 0.0
    if not (step > 0 and np.all(np.abs(steps - step) <= 0.01 * step)):
        raise LoopError(f"its t_s column is not sampled uniformly (steps {np.min(steps):.4g} to "
                        f"{np.max(steps):.4g} s); resample it")
    if sample_period_s is not None and abs(step - sample_period_s) > 0.01 * step:
        raise LoopError(f"its t_s column steps {step:.4g} s, not --sample_period_s "
                        f"{sample_period_s:g}; leave --sample_period_s out to take it from t_s")
    return step


def _check_force(car, options, stroke, force, noise):
    """Refuses a force beyond what μ <= MU_MAX allows at the side load (see the module)."""
    normal = np.array([eq4_normal_force_N(car.front, options, q) for q in stroke])
    omega = 2 * math.pi * options.stroke_frequency_hz
    inertia = car.mass.front_knuckle_kg * options.stroke_amplitude_m * omega ** 2
    allowed = MU_MAX * OVERSHOOT * normal + inertia + NOISE_SIGMAS * noise
    worst = int(np.argmax(np.abs(force) - allowed))
    if abs(force[worst]) > allowed[worst]:
        where = side_force_where(car.front, options)
        raise LoopError(f"the force reaches {abs(force[worst]):.4g} N at stroke "
                        f"{stroke[worst]:.4g} m, beyond what μ <= {MU_MAX:g} allows at "
                        f"--side_force_N {options.side_force_N:g} {where} (N = "
                        f"{normal[worst]:.4g} N by eq. 4 on the rig: at most "
                        f"{allowed[worst]:.4g} N with the rig's overshoot, the knuckle's "
                        "inertia and the noise); is the force in another unit, or the side "
                        "load or its point another?")


@dataclasses.dataclass
class ResidualCheck:
    residual_N: float
    noise_N: float
    floor_N: float
    confident: bool
    warning: str


def residual_check(stroke_m, force_N, *, sample_period_s, mu_d, normal_N, floor_N=0.0):
    """The fit's residual (RMS of force - μd·N(q)·sgn over the middle half of each half-cycle's
    travel) against the loop's own noise there, floored by ``floor_N`` (what the law leaves out
    while sliding); flagged (``confident`` False, ``warning``) above RESIDUAL_RATIO times it.
    ``sample_period_s`` is not used by the estimate (kept for the caller's record)."""
    stroke = np.asarray(stroke_m, dtype=float)
    force = np.asarray(force_N, dtype=float)
    normal = np.asarray(normal_N, dtype=float)
    middles = _middles(stroke, reversals(stroke))
    if not middles:
        raise LoopError("the stroke has no complete half-cycle")
    residual = np.concatenate([force[m] - d * mu_d * normal[m] for m, d in middles])
    rms = float(np.sqrt(np.mean(residual ** 2)))
    noise = noise_N(force, np.any([m for m, _ in middles], axis=0))
    scale = max(noise, floor_N)
    confident = rms <= RESIDUAL_RATIO * scale
    warning = "" if confident else (
        f"the fit's residual {rms:.3g} N is {rms / scale:.1f} times the loop's own noise "
        f"{noise:.3g} N (the force's scatter between neighbouring samples"
        + (f"; {floor_N:.2g} N allowed for the knuckle's inertia" if floor_N > noise else "")
        + "): the law (μd·N while sliding) does not describe this loop -- a gas or coil "
        "spring's force, another rig or another unit? μs and μd are not confident values")
    return ResidualCheck(rms, noise, floor_N, confident, warning)
