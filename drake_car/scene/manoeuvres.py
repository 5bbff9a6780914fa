"""What the car does: the manoeuvres a scene chooses by YAML tag (``!Settle``, ``!Straight``,
``!LaneChange``, ``!RampSteer``, ``!StepSteer``), each with its timeline, speed profile and
rack trajectory (Drake trajectories). The lane change's rack follows an Akima spline (the
paper's ref. [1]) through the knots of one sine period.

A driving manoeuvre has the paper's phases (section 4): I the car at rest (``settle_s``), then
speeding up to ``speed_kph`` in ``speed_up_s``; II straight ahead; III the steering manoeuvre
(``steer_s``); IV calming down (``calm_s``).

What adapts to the car: a launch left out (``speed_up_s`` None) is the paper's 3 s if the car's
drive can follow it, else as long as its drive allows (``scene.launch``, resolved where the
scene is loaded); a lane change without ``amplitude_m`` and ``second_lobe`` has its rack
calibrated for the car that runs (``sim.lane_change_calibration``). What a manoeuvre must do,
and whether a run did it: ``scene.manoeuvre_targets``.
"""

import dataclasses
import typing

import numpy as np
from pydrake.trajectories import PiecewisePolynomial

from drake_car.law.numerics.akima import akima_slopes
from drake_car.law.checks import ParameterError, checked, nonnegative, one_of, positive
from drake_car.law.errors import InputError

PHASES = ("I", "II", "III", "IV")
# A run longer than this (simulated) is refused: at ~2 ms of wall time per simulated ms it would
# take hours; a minute of simulated time is the longest a study here needs.
MAX_DURATION_S = 600.0
# Speeds a passenger car drives (km/h).
MAX_SPEED_KPH = 250.0
# The lane change's rack knots: one sine period at unit amplitude over ``steer_s``.
LANE_CHANGE_KNOT_SHAPE = (0.0, 0.7071, 1.0, 0.7071, 0.0, -0.7071, -1.0, -0.7071, 0.0)
# The paper's launch (section 4): 60 km/h in 3 s.
PAPER_SPEED_UP_S = 3.0
# The paper's lane change (section 4): the track moves 3.7 m sideways.
PAPER_SHIFT_M = 3.7


@dataclasses.dataclass
class Timeline:
    """The paper's phases I-IV (s) and the cruising speed (km/h). ``speed_up_s`` None: the
    paper's 3 s if the car's drive can follow it, else as long as its drive allows
    (``scene.launch.resolve_launch``, where the scene is loaded: the saved scene holds the
    number); a number is the launch as given."""

    settle_s: float = 0.8
    speed_up_s: typing.Optional[float] = None
    straight_s: float = 1.2
    steer_s: float = 2.4
    calm_s: float = 2.6
    speed_kph: float = 60.0

    def check(self):
        nonnegative(self, "settle_s", "straight_s", "calm_s")
        positive(self, "steer_s", "speed_kph")
        if self.speed_up_s is not None:
            positive(self, "speed_up_s")
        if self.speed_kph > MAX_SPEED_KPH:
            raise ParameterError("speed_kph", self.speed_kph,
                                 f"must be <= {MAX_SPEED_KPH:g} km/h (a passenger car)")
        if self.duration_s > MAX_DURATION_S:
            # the one that made it long
            longest = max(("settle_s", "speed_up_s", "straight_s", "steer_s", "calm_s"),
                          key=lambda name: getattr(self, name) or 0.0)
            raise ParameterError(longest, getattr(self, longest),
                                 f"makes the run {self.duration_s:g} s long; runs are limited "
                                 f"to {MAX_DURATION_S:g} s of simulated time")
        return self

    @property
    def speed_mps(self):
        return self.speed_kph / 3.6

    @property
    def launch_s(self):
        """The launch's length (s): ``speed_up_s``, or the paper's 3 s while it is unresolved
        (a timeline made in Python and not yet run)."""
        return PAPER_SPEED_UP_S if self.speed_up_s is None else self.speed_up_s

    def boundaries(self):
        """Start times of phases II, III, IV and the end time."""
        t2 = self.settle_s + self.launch_s
        t3 = t2 + self.straight_s
        t4 = t3 + self.steer_s
        return t2, t3, t4, t4 + self.calm_s

    @property
    def duration_s(self):
        return self.boundaries()[3]

    def phase(self, t):
        t2, t3, t4, _ = self.boundaries()
        return "I" if t < t2 else "II" if t < t3 else "III" if t < t4 else "IV"


def speed_profile(t, timeline: Timeline, blend_s=0.3):
    """Car speed (m/s), distance (m) and acceleration (m/s²) at times ``t``: at rest while
    settling, then an acceleration with its jerk smoothed over ``blend_s`` at both ends,
    reaching the target speed exactly ``speed_up_s`` after it began; constant afterwards."""
    t0, duration, target = timeline.settle_s, timeline.launch_s, timeline.speed_mps
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
    after = tau >= duration
    v = np.where(after, target, np.interp(tau, times, speed))
    s = np.where(after, dist[-1] + target * (tau - duration), np.interp(tau, times, dist))
    a = np.where(after | (t < t0), 0.0, np.interp(tau, times, accel))
    return v, s, a


def _hold_at_zero(end_s):
    return PiecewisePolynomial.FirstOrderHold([0.0, max(end_s, 1e-3)], np.zeros((1, 2)))


class DrivingManoeuvre:
    """What every driving manoeuvre shares (not loadable itself): it drives, its ``timeline``
    (the paper's phases I-IV) gives its end and phases, ``check()`` checks the timeline and then
    the manoeuvre's own fields (``_check_own``). A manoeuvre gives ``rack()``, the rack's
    displacement over the run (m, a Drake trajectory)."""

    drives = True

    def check(self):
        checked(self.timeline, "timeline")
        self._check_own()
        return self

    def _check_own(self):
        pass

    @property
    def end_s(self):
        return self.timeline.duration_s

    def phase(self, t):
        return self.timeline.phase(t)


@dataclasses.dataclass
class Settle:
    """The car at rest on its tyres, no drive, the rack held straight (the paper's first 0.8 s,
    or a static equilibrium)."""

    duration_s: float = 5.0

    def check(self):
        positive(self, "duration_s")
        if self.duration_s > MAX_DURATION_S:
            raise ParameterError("duration_s", self.duration_s,
                                 f"must be <= {MAX_DURATION_S:g} s of simulated time")
        return self

    drives = False
    timeline = None

    @property
    def end_s(self):
        return self.duration_s

    def phase(self, t):
        return "I"

    def rack(self):
        return _hold_at_zero(self.duration_s)


@dataclasses.dataclass
class Straight(DrivingManoeuvre):
    """Speed up and drive straight on (phase III without steering)."""

    timeline: Timeline = dataclasses.field(default_factory=Timeline)

    def rack(self):
        return _hold_at_zero(self.end_s)


@dataclasses.dataclass
class LaneChange(DrivingManoeuvre):
    """The paper's lane change (Fig. 13), defined by what it does: the car's track moves
    ``shift_m`` sideways during phase III (``timeline.steer_s``, at ``timeline.speed_kph``) and
    ends parallel to its start; case "a" starts with a left turn, "b" is its mirror image. The
    rack follows an Akima spline through one sine period of ``amplitude_m`` during phase III,
    ``second_lobe`` scaling the return turn. Both None (the default): calibrated for the car
    that runs, case a, so that it does what the manoeuvre says (``sim.lane_change_calibration``:
    the shipped Escort's calibration where its inputs match, else cached by content); both
    given: that rack, as given (an open-loop input; the run is still checked against
    ``shift_m``)."""

    case: str = "a"
    timeline: Timeline = dataclasses.field(default_factory=Timeline)
    shift_m: float = PAPER_SHIFT_M
    amplitude_m: typing.Optional[float] = None
    second_lobe: typing.Optional[float] = None

    @property
    def calibrated(self):
        """Whether the rack's profile is known (given, or calibrated for the car)."""
        return self.amplitude_m is not None and self.second_lobe is not None

    def _check_own(self):
        one_of(self, "case", ("a", "b"))
        positive(self, "shift_m")
        if self.shift_m > 10.0:
            raise ParameterError("shift_m", self.shift_m,
                                 "must be <= 10 m (a lane change: the paper's 3.7 m)")
        if self.amplitude_m is not None:
            positive(self, "amplitude_m")
            if self.amplitude_m > 0.1:
                raise ParameterError("amplitude_m", self.amplitude_m, "must be <= 0.1 m (a "
                                     "rack's whole stroke is about ±0.07 m)")
        if self.second_lobe is not None and not 0.5 <= self.second_lobe <= 2.0:
            raise ParameterError("second_lobe", self.second_lobe, "must lie in [0.5, 2]")
        if (self.amplitude_m is None) != (self.second_lobe is None):
            given = "amplitude_m" if self.second_lobe is None else "second_lobe"
            raise ParameterError(given, getattr(self, given),
                                 "goes with amplitude_m and second_lobe both given (a rack "
                                 "as given) or neither (calibrated for the car)")

    def knots(self):
        if not self.calibrated:
            raise InputError("LaneChange: the rack's profile is not calibrated for the car "
                             "yet: build the scene as it runs, drake_car.scene_as_it_runs("
                             "scene) (drake_car.simulate does so itself), or give amplitude_m "
                             "and second_lobe")
        shape = np.array(LANE_CHANGE_KNOT_SHAPE)
        shape[shape < 0] *= self.second_lobe
        sign = 1.0 if self.case == "a" else -1.0
        times = np.linspace(0.0, 1.0, len(shape))
        return times, sign * self.amplitude_m * shape

    def rack(self, until_s=None):
        """Rack displacement vs time (m, rack to the left +) through the whole run: zero, the
        Akima spline through the knots during phase III, zero. Two zero knots are added before
        and after, one knot spacing apart: on such flat stretches Akima's slopes are exactly
        zero, so the rack rests before and after and joins the rest with zero slope.
        ``until_s``: the run's end; a run that ends before phase III needs no calibrated
        profile (its rack rests throughout)."""
        _, t3, t4, end = self.timeline.boundaries()
        if not self.calibrated and until_s is not None and until_s <= t3:
            return _hold_at_zero(end)
        times, values = self.knots()
        times = t3 + times * self.timeline.steer_s
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


@dataclasses.dataclass
class RampSteer(DrivingManoeuvre):
    """Steady-state cornering by the continuous method of ISO 4138 (constant speed, slowly
    increasing steer): after phases I and II the rack ramps from 0 to ``rack_m`` over phase III
    and is held through phase IV."""

    timeline: Timeline = dataclasses.field(
        default_factory=lambda: Timeline(straight_s=1.0, steer_s=20.0, calm_s=1.0))
    rack_m: float = 0.01

    def _check_own(self):
        _check_rack_stroke(self.rack_m)

    def rack(self):
        _, t3, t4, end = self.timeline.boundaries()
        return PiecewisePolynomial.FirstOrderHold(
            [0.0, t3, t4, max(end, t4 + 1e-3)], np.array([[0.0, 0.0, self.rack_m, self.rack_m]]))


@dataclasses.dataclass
class StepSteer(DrivingManoeuvre):
    """Step steer (ISO 7401): at the start of phase III the rack moves to ``rack_m`` in
    ``rise_s`` (a ramp, the standard's fast "step") and is held through phases III and IV."""

    timeline: Timeline = dataclasses.field(
        default_factory=lambda: Timeline(straight_s=1.0, steer_s=3.0, calm_s=0.0))
    rack_m: float = 0.004
    rise_s: float = 0.15

    def _check_own(self):
        positive(self, "rise_s")
        _check_rack_stroke(self.rack_m)
        if self.rise_s >= self.timeline.steer_s:
            raise ParameterError("rise_s", self.rise_s,
                                 f"must be shorter than timeline.steer_s = "
                                 f"{self.timeline.steer_s}")

    def rack(self):
        _, t3, _, end = self.timeline.boundaries()
        top = t3 + self.rise_s
        return PiecewisePolynomial.FirstOrderHold(
            [0.0, t3, top, max(end, top + 1e-3)],
            np.array([[0.0, 0.0, self.rack_m, self.rack_m]]))


Manoeuvre = typing.Union[LaneChange, Straight, Settle, RampSteer, StepSteer]


def _check_rack_stroke(rack_m):
    if not (abs(rack_m) <= 0.07 and rack_m != 0):
        raise ParameterError("rack_m", rack_m,
                             "must be non-zero and within the rack's stroke of ±0.07 m")


def speed_trajectory(timeline: Timeline, sample_s=0.005):
    """[v, a] of the speed profile (m/s, m/s²) as a piecewise-linear trajectory."""
    t = np.arange(0.0, timeline.duration_s + sample_s, sample_s)
    v, _, a = speed_profile(t, timeline)
    return PiecewisePolynomial.FirstOrderHold(t, np.vstack([v, a]))


def wheel_rotation_trajectory(timeline: Timeline, rolling_radius_m, sample_s=0.005):
    """Desired [φ_left, φ_right] front-wheel rotation angles (rad) and their rates: the wheels
    roll the car along the speed profile (φ = s / R_e): the paper's prescribed drive."""
    if not rolling_radius_m > 0:
        raise ValueError(f"rolling_radius_m = {rolling_radius_m} must be > 0")
    t = np.arange(0.0, timeline.duration_s + sample_s, sample_s)
    v, s, _ = speed_profile(t, timeline)
    angle = np.vstack([s, s]) / rolling_radius_m
    rate = np.vstack([v, v]) / rolling_radius_m
    return PiecewisePolynomial.CubicHermite(t, angle, rate)
