"""Manoeuvres: the lane change's rack (the paper's Akima spline), steps and ramps, the speed
profile."""

import dataclasses

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.interpolate import Akima1DInterpolator

from drake_car.law.checks import ParameterError
from drake_car.scene.manoeuvres import (
    LaneChange, RampSteer, StepSteer, Timeline, speed_profile)


def test_rack_trajectory_is_the_akima_spline_and_continuous():
    timeline = Timeline()
    manoeuvre = LaneChange(case="a", timeline=timeline, amplitude_m=0.009, second_lobe=1.0)
    trajectory = manoeuvre.rack()
    _, t3, t4, end = timeline.boundaries()
    times, values = manoeuvre.knots()
    times = t3 + times * timeline.steer_s
    h = times[1] - times[0]
    x = np.concatenate([[t3 - 2 * h, t3 - h], times, [t4 + h, t4 + 2 * h]])
    y = np.concatenate([[0, 0], values, [0, 0]])
    reference = Akima1DInterpolator(x, y)
    t = np.linspace(x[0], x[-1], 3001)
    drake = np.array([trajectory.value(ti)[0, 0] for ti in t])
    assert_allclose(drake, reference(t), atol=1e-12)
    # Rests before and after the manoeuvre; value and slope continuous at every break.
    for ti in (0.0, 1.0, t3 - 0.01, t4 + 0.7, end):
        assert trajectory.value(ti)[0, 0] == pytest.approx(0.0, abs=1e-15)
    rate = trajectory.derivative(1)
    for b in trajectory.get_segment_times()[1:-1]:
        for f in (trajectory, rate):
            assert_allclose(f.value(b - 1e-9), f.value(b + 1e-9), atol=1e-9)
    mirrored = dataclasses.replace(manoeuvre, case="b").rack()
    for ti in np.linspace(t3, t4, 50):
        assert mirrored.value(ti)[0, 0] == pytest.approx(-trajectory.value(ti)[0, 0])



def test_lane_change_case_is_checked():
    with pytest.raises(ParameterError, match="case = 'c' must be one of a, b"):
        LaneChange(case="c").check()


def test_speed_profile_reaches_the_speed_in_the_speed_up():
    timeline = Timeline()
    t2 = timeline.boundaries()[0]
    t = np.linspace(0, timeline.duration_s, 2001)
    v, s, a = speed_profile(t, timeline)
    assert np.all(v[t <= timeline.settle_s] == 0)
    assert_allclose(v[t >= t2], timeline.speed_mps, rtol=1e-12)
    # The distance is the integral of the speed and the speed that of the acceleration
    # (trapezoids on a 5 ms grid: second order, error below 1e-4 of the values).
    assert_allclose(np.trapezoid(v, t), s[-1], rtol=1e-4)
    assert_allclose(np.trapezoid(a, t), timeline.speed_mps, rtol=1e-3)


@pytest.mark.parametrize("manoeuvre", [RampSteer(rack_m=0.01), StepSteer(rack_m=0.004)])
def test_steer_inputs_start_at_phase_three_and_hold(manoeuvre):
    rack = manoeuvre.rack()
    _, t3, t4, end = manoeuvre.timeline.boundaries()
    assert rack.value(t3 - 1e-6)[0, 0] == pytest.approx(0.0, abs=1e-12)
    assert rack.value(end)[0, 0] == pytest.approx(manoeuvre.rack_m)
