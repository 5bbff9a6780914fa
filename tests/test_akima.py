"""The Akima spline of the steering source against scipy's independent implementation."""

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.interpolate import Akima1DInterpolator

from drake_car.law.akima import akima_slopes, hermite_eval
from drake_car.manoeuvre import LaneChangeProfile, Timeline, rack_trajectory


@pytest.mark.parametrize("seed", range(5))
def test_matches_scipy(seed):
    rng = np.random.default_rng(seed)
    x = np.cumsum(rng.uniform(0.05, 1.0, 15))
    y = rng.normal(size=15)
    y[5:9] = 0.3  # a flat stretch, where Akima's weights vanish
    t = np.linspace(x[0], x[-1], 4001)
    value, slope = hermite_eval(x, y, akima_slopes(x, y), t)
    reference = Akima1DInterpolator(x, y)
    assert_allclose(value, reference(t), atol=1e-12)
    assert_allclose(slope, reference(t, 1), atol=1e-10)


def test_rack_trajectory_is_the_akima_spline_and_continuous():
    timeline = Timeline()
    profile = LaneChangeProfile(amplitude_m=0.009)
    trajectory = rack_trajectory(timeline, profile, "a")
    _, t3, t4, end = timeline.boundaries()
    times, values = profile.knots("a")
    times = t3 + times * timeline.lane_change_s / times[-1]
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
    mirrored = rack_trajectory(timeline, profile, "b")
    for ti in np.linspace(t3, t4, 50):
        assert mirrored.value(ti)[0, 0] == pytest.approx(-trajectory.value(ti)[0, 0])


def test_bad_knots():
    with pytest.raises(ValueError, match="strictly increasing"):
        akima_slopes([0, 1, 1, 2], [0, 1, 2, 3])
    with pytest.raises(ValueError, match="at least 3"):
        akima_slopes([0, 1], [0, 1])
    with pytest.raises(ValueError, match="case"):
        LaneChangeProfile().knots("c")
