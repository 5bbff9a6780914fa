"""What a strut friction rig's loop says: the break-away and sliding forces per half-cycle, as
coefficients (``loop_statistics``; ``study.rig.fit`` turns them into the law's μs, μd).

The evaluation is the one strut rigs use (break-away force at each reversal, sliding force at
mid-stroke), made into coefficients with the normal force N(q) of eq. (4) for the rig's side
load and the strut's geometry:

- half-cycles run between the stroke's reversals (found on the stroke with a hysteresis of half
  its amplitude, so noise does not make false reversals); the first motion from rest is not a
  half-cycle;
- break-away: at the start of each half-cycle the strut sticks and the load rises along a ramp
  until it breaks free, then drops. The ramp is fitted by a line over the ``RAMP_SAMPLES``
  samples before the peak sample; the break-away is the line's value half a sample before the
  peak (the strut held at the sample before and broke at the peak: the true value lies
  between them) and half a sample's rise is a systematic uncertainty added to the statistical
  one. The knuckle is stuck there, so the load cell reads no inertia;
- sliding: the median of the force over the middle half of the half-cycle's travel, where the
  sinusoidal stroke's acceleration (so the inertia in the load cell) is smallest;
- μ per half-cycle is the force over N(q) at that sample; the estimate is the mean over the
  half-cycles, its 95 % confidence half-width t(0.975, n-1)·s/√n (plus the systematic term).
  The break-away so found is the *apparent* μs: the load still rises for a step or two after
  the strut breaks free (the knuckle's inertia against the rig's compliance), so a rig's peak
  overshoots μs·N by an amount its dynamics set; ``study.rig.fit`` removes it with the rig's
  model;
- the fit's residual: the RMS of the force minus the fitted sliding force μd·N(q)·sgn over the
  sliding samples (noise and what the law does not describe);
- Δmax is resolved when the stroke's noise (the RMS of its second difference / √6) is below a
  third of the stroke the strut creeps while stuck; Δv when the velocity's resolution
  (√2 × stroke noise / sample period) is below Δv. Where they are resolved the rig's loop gives
  them only through a model of the user's rig; here they are reported as resolved or not.
"""

import dataclasses
import math

import numpy as np
from scipy import stats
from drake_car.law.errors import InputError

RAMP_SAMPLES = 8
MIN_HALF_CYCLES = 3


class LoopError(InputError):
    """A loop that cannot be evaluated (too short, no reversals, bad columns)."""


@dataclasses.dataclass
class HalfCycle:
    start: int
    end: int
    direction: float
    breakaway_N: float
    breakaway_mu: float
    breakaway_step_N: float  # the ramp's rise over one sample at the break-away
    sliding_N: float
    sliding_mu: float


@dataclasses.dataclass
class LoopStatistics:
    apparent_mu_s: float
    apparent_mu_s_ci95: float
    mu_d: float
    mu_d_ci95: float
    half_cycles: int
    residual_rms_N: float
    stroke_noise_m: float
    dmax_resolved: bool
    dv_resolved: bool
    cycles: list

    def summary(self):
        return {k: v for k, v in dataclasses.asdict(self).items() if k != "cycles"}


def reversals(stroke_m):
    """Indices of the stroke's reversals (alternating maxima and minima)."""
    x = np.asarray(stroke_m, dtype=float)
    centre = 0.5 * (np.max(x) + np.min(x))
    half = 0.5 * (np.max(x) - np.min(x))
    if not half > 0:
        raise LoopError("the stroke does not move")
    band = 0.5 * half
    # Alternating excursions above +band and below -band; a reversal is the extremum of each.
    state = 0
    marks = []  # (start, sign)
    for i, value in enumerate(x - centre):
        if value > band and state != 1:
            state = 1
            marks.append((i, 1))
        elif value < -band and state != -1:
            state = -1
            marks.append((i, -1))
    points = []  # the last excursion has no next mark: it may not have turned yet
    for (start, sign), (following, _) in zip(marks, marks[1:]):
        segment = x[start:following]
        points.append(start + int(np.argmax(segment) if sign > 0 else np.argmin(segment)))
    return points


def stroke_noise_m(stroke_m):
    """The stroke's noise from its second difference (a white noise σ gives σ√6)."""
    x = np.asarray(stroke_m, dtype=float)
    if len(x) < 4:
        return 0.0
    return float(np.std(np.diff(x, 2)) / math.sqrt(6.0))


def half_cycles(stroke_m, force_N, normal_N):
    """The half-cycles' break-away and sliding forces (``HalfCycle`` list)."""
    x = np.asarray(stroke_m, dtype=float)
    f = np.asarray(force_N, dtype=float)
    n = np.asarray(normal_N, dtype=float)
    turns = reversals(x)
    out = []
    for a, b in zip(turns, turns[1:]):
        direction = math.copysign(1.0, x[b] - x[a])
        g = direction * f[a:b]
        first = max(RAMP_SAMPLES + 2, int(0.4 * (b - a)))
        peak = int(np.argmax(g[:first]))
        if peak < RAMP_SAMPLES:
            continue  # no ramp to fit (the reversal's break-away is not resolved)
        k = np.arange(peak - RAMP_SAMPLES, peak)
        slope, intercept = np.polyfit(k, g[k], 1)
        breakaway = slope * (peak - 0.5) + intercept
        travel = (x[a:b] - x[a]) * direction
        span = abs(x[b] - x[a])
        middle = (travel > 0.25 * span) & (travel < 0.75 * span)
        if not middle.any():
            continue
        sliding = float(np.median(g[middle]))
        sliding_mu = float(np.median(g[middle] / n[a:b][middle]))
        out.append(HalfCycle(a, b, direction, float(breakaway),
                             float(breakaway / n[a + peak]), float(abs(slope)), sliding,
                             sliding_mu))
    return out


def _mean_ci95(values):
    values = np.asarray(values, dtype=float)
    if len(values) < 2:
        return float(values.mean()), math.inf
    half = stats.t.ppf(0.975, len(values) - 1) * values.std(ddof=1) / math.sqrt(len(values))
    return float(values.mean()), float(half)


def loop_statistics(stroke_m, force_N, normal_N, *, sample_period_s=None, dmax_m=5e-6, dv_mps=1e-4):
    """The apparent μs (break-away) and μd (sliding) of a measured loop (stroke m, force N, the normal force N(q) of eq. 4 at
    each sample); ``sample_period_s`` (None: unknown) decides whether Δv is resolved,
    ``dmax_m``/``dv_mps`` the values tested for resolution. Raises LoopError."""
    x = np.asarray(stroke_m, dtype=float)
    f = np.asarray(force_N, dtype=float)
    n = np.asarray(normal_N, dtype=float)
    if not (len(x) == len(f) == len(n)) or len(x) < 20:
        raise LoopError(f"stroke, force and normal force must have one length >= 20 "
                        f"(got {len(x)}, {len(f)}, {len(n)})")
    if not (np.isfinite(x).all() and np.isfinite(f).all()):
        raise LoopError("the loop has a value that is not a finite number")
    if not (n > 0).all():
        raise LoopError("the normal force must be > 0 at every sample (a side load is needed)")
    cycles = half_cycles(x, f, n)
    if len(cycles) < MIN_HALF_CYCLES:
        raise LoopError(f"the loop has {len(cycles)} complete half-cycles with a resolved "
                        f"break-away; at least {MIN_HALF_CYCLES} are needed")
    mu_s, ci_s = _mean_ci95([c.breakaway_mu for c in cycles])
    systematic = 0.5 * np.mean([c.breakaway_step_N / n[c.start] for c in cycles])
    mu_d, ci_d = _mean_ci95([c.sliding_mu for c in cycles])
    residuals = []
    for c in cycles:
        travel = (x[c.start:c.end] - x[c.start]) * c.direction
        span = abs(x[c.end] - x[c.start])
        middle = (travel > 0.25 * span) & (travel < 0.75 * span)
        model = c.direction * mu_d * n[c.start:c.end][middle]
        residuals.append(f[c.start:c.end][middle] - model)
    residual = float(np.sqrt(np.mean(np.concatenate(residuals) ** 2)))
    noise = stroke_noise_m(x)
    dv_resolved = (sample_period_s is not None
                   and math.sqrt(2.0) * noise / sample_period_s < dv_mps)
    return LoopStatistics(apparent_mu_s=mu_s, apparent_mu_s_ci95=ci_s + float(systematic), mu_d=mu_d, mu_d_ci95=ci_d,
                   half_cycles=len(cycles), residual_rms_N=residual, stroke_noise_m=noise,
                   dmax_resolved=bool(noise < dmax_m / 3.0), dv_resolved=bool(dv_resolved),
                   cycles=cycles)
