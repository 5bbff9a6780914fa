"""The Akima spline of the steering source against scipy's independent implementation."""

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.interpolate import Akima1DInterpolator

from drake_car.law.numerics.akima import akima_slopes, hermite_eval


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


def test_bad_knots():
    with pytest.raises(ValueError, match="strictly increasing"):
        akima_slopes([0, 1, 1, 2], [0, 1, 2, 3])
    with pytest.raises(ValueError, match="at least 3"):
        akima_slopes([0, 1], [0, 1])
