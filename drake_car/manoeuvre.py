"""The paper's manoeuvre: timeline, drive (prescribed front-wheel rotation) and the lane-change
rack profile (an Akima spline, the paper's ref. [1]), as Drake trajectories."""

import dataclasses

import numpy as np
from pydrake.trajectories import PiecewisePolynomial

from drake_car.law.akima import akima_slopes

PHASES = ("I", "II", "III", "IV")


@dataclasses.dataclass
class Timeline:
    """Phase I: settling from the design position (``settle_s``), then speeding up to
    ``speed_kph`` in ``speed_up_s``; II: straight; III: the lane change; IV: calming down."""

    settle_s: float = 0.8
    speed_up_s: float = 3.0
    straight_s: float = 1.2
    lane_change_s: float = 2.4
    calm_s: float = 2.6
    speed_kph: float = 60.0

    def __post_init__(self):
        for name in ("settle_s", "straight_s", "calm_s"):
            if not getattr(self, name) >= 0:
                raise ValueError(f"timeline {name} = {getattr(self, name)} must be >= 0")
        for name in ("speed_up_s", "lane_change_s", "speed_kph"):
            if not getattr(self, name) > 0:
                raise ValueError(f"timeline {name} = {getattr(self, name)} must be > 0")

    @property
    def speed_mps(self):
        return self.speed_kph / 3.6

    def boundaries(self):
        """Start times of phases II, III, IV and the end time."""
        t2 = self.settle_s + self.speed_up_s
        t3 = t2 + self.straight_s
        t4 = t3 + self.lane_change_s
        return t2, t3, t4, t4 + self.calm_s

    @property
    def duration_s(self):
        return self.boundaries()[3]

    def phase(self, t):
        t2, t3, t4, _ = self.boundaries()
        return "I" if t < t2 else "II" if t < t3 else "III" if t < t4 else "IV"


def speed_profile(t, timeline: Timeline, blend_s=0.3):
    """Car speed (m/s) and distance (m) at ``t``: at rest while settling, then a constant
    acceleration with its jerk smoothed over ``blend_s`` at both ends, reaching the target speed
    exactly ``speed_up_s`` after it began; constant afterwards."""
    t0, duration, target = timeline.settle_s, timeline.speed_up_s, timeline.speed_mps
    blend = min(blend_s, duration / 3)
    times = np.linspace(0.0, duration, 2001)
    jerk_up = np.clip(times / blend, 0, 1)
    jerk_down = np.clip((duration - times) / blend, 0, 1)
    shape = np.minimum(jerk_up ** 2 * (3 - 2 * jerk_up), jerk_down ** 2 * (3 - 2 * jerk_down))
    accel = shape / np.trapezoid(shape, times) * target
    speed = np.concatenate([[0.0], np.cumsum(0.5 * (accel[1:] + accel[:-1]) * np.diff(times))])
    dist = np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(times))])
    t = np.asarray(t, dtype=float)
    tau = np.clip(t - t0, 0.0, None)
    v = np.where(tau >= duration, target, np.interp(tau, times, speed))
    s = np.where(tau >= duration, dist[-1] + target * (tau - duration), np.interp(tau, times, dist))
    return v, s


def drive_trajectory(timeline: Timeline, rolling_radius_m, sample_s=0.005):
    """Desired [φ_left, φ_right] front-wheel rotation angles (rad) and their rates: the wheels
    roll the car along the speed profile (φ = s / R_e)."""
    if not rolling_radius_m > 0:
        raise ValueError(f"rolling_radius_m = {rolling_radius_m} must be > 0")
    t = np.arange(0.0, timeline.duration_s + sample_s, sample_s)
    v, s = speed_profile(t, timeline)
    angle = np.vstack([s, s]) / rolling_radius_m
    rate = np.vstack([v, v]) / rolling_radius_m
    return PiecewisePolynomial.CubicHermite(t, angle, rate)


@dataclasses.dataclass
class LaneChangeProfile:
    """Rack displacement knots of the lane change, relative to its start (s, m; rack to the
    left positive). Case "a" starts with a left turn; case "b" is its mirror image."""

    knot_times_s: tuple = (0.0, 0.3, 0.6, 0.9, 1.2, 1.5, 1.8, 2.1, 2.4)
    # One period of a sine at unit amplitude; ``amplitude_m`` and ``second_lobe`` (the right
    # turn's amplitude relative to the left turn's) are calibrated (see experiments/
    # calibrate_lane_change.py and scenes).
    knot_shape: tuple = (0.0, 0.7071, 1.0, 0.7071, 0.0, -0.7071, -1.0, -0.7071, 0.0)
    amplitude_m: float = 0.012
    second_lobe: float = 1.0

    def knots(self, case):
        if case not in ("a", "b"):
            raise ValueError(f"lane-change case {case!r} must be 'a' or 'b'")
        shape = np.array(self.knot_shape, dtype=float)
        shape[shape < 0] *= self.second_lobe
        sign = 1.0 if case == "a" else -1.0
        return np.array(self.knot_times_s, dtype=float), sign * self.amplitude_m * shape


def rack_trajectory(timeline: Timeline, profile: LaneChangeProfile, case):
    """Rack displacement vs time (m) through the whole run: zero, then the Akima spline through
    the lane-change knots during phase III, then zero. ``case`` 'a', 'b' or 'straight'.

    Two zero knots are added before and after the manoeuvre (one knot spacing apart): on such
    flat stretches Akima's slopes are exactly zero, so the rack rests before and after and the
    spline joins the rest with zero slope."""
    _, t3, t4, end = timeline.boundaries()
    if case == "straight":
        return PiecewisePolynomial.FirstOrderHold([0.0, end], np.zeros((1, 2)))
    times, values = profile.knots(case)
    times = t3 + times * (timeline.lane_change_s / times[-1])
    h = times[1] - times[0]
    times = np.concatenate([[t3 - 2 * h, t3 - h], times, [t4 + h, t4 + 2 * h]])
    values = np.concatenate([[0.0, 0.0], values, [0.0, 0.0]])
    slopes = akima_slopes(times, values)
    breaks, samples, rates = times, values, slopes
    if times[0] > 0.0:
        breaks = np.concatenate([[0.0], breaks])
        samples = np.concatenate([[0.0], samples])
        rates = np.concatenate([[0.0], rates])
    if breaks[-1] < end:
        breaks = np.concatenate([breaks, [end]])
        samples = np.concatenate([samples, [0.0]])
        rates = np.concatenate([rates, [0.0]])
    return PiecewisePolynomial.CubicHermite(breaks, samples.reshape(1, -1),
                                            rates.reshape(1, -1))
