"""The ride laws: ISO 8608 road profiles (their PSD and the tracks' coherence against the
standard's and the model's, within the estimator's own scatter) and ISO 2631-1's Wk weighting
(against the standard's tabulated factors)."""

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from drake_car.law.checks import ParameterError
from drake_car.law.comfort.iso2631 import weighted_rms, wk_response
from drake_car.law.road.iso8608 import (
    CLASS_BOUNDS_M3, CLASS_GD_N0_M3, bessel_k1_times_x, displacement_psd, generate_tracks,
    periodogram, road_profile, track_correlation)

# ISO 2631-1:1997, Annex A, Table A.2 ("Principal frequency weightings in one-third octaves"),
# column Wk, factor x 1000, at the nominal band centre frequencies (Hz).
WK_TABLE = {0.1: 31.2, 0.125: 48.6, 0.16: 79.0, 0.2: 121, 0.25: 182, 0.315: 263, 0.4: 352,
            0.5: 418, 0.63: 459, 0.8: 477, 1.0: 482, 1.25: 484, 1.6: 494, 2.0: 531, 2.5: 631,
            3.15: 804, 4.0: 967, 5.0: 1039, 6.3: 1054, 8.0: 1036, 10.0: 988, 12.5: 902,
            16.0: 768, 20.0: 636, 25.0: 513, 31.5: 405, 40.0: 314, 50.0: 246, 63.0: 186,
            80.0: 132, 100.0: 88.7, 125.0: 54.0, 160.0: 28.5, 200.0: 15.2, 250.0: 7.90,
            315.0: 3.98, 400.0: 1.95}


def _last_digit(value):
    """One unit in the last digit of a factor printed to three significant figures."""
    return 10.0 ** (math.floor(math.log10(value)) - 2)


@pytest.mark.parametrize("f_Hz", sorted(WK_TABLE))
def test_wk_matches_the_standards_table(f_Hz):
    # The table gives three significant figures: rounding alone is half a unit of the last
    # digit. Two entries (1.25 and 16 Hz) sit 0.55 and 0.70 units from the formula with the
    # standard's parameters (the table was computed with its own arithmetic, not stated), so
    # the tolerance is one unit of the last digit: 0.1 % to 1 % of the value.
    computed = 1000.0 * abs(wk_response(f_Hz))
    table = WK_TABLE[f_Hz]
    assert abs(computed - table) <= _last_digit(table), (f_Hz, computed, table)


def test_wk_shape():
    assert wk_response(0.0) == 0.0
    # the acceleration-velocity transition: velocity proportional well above 12.5 Hz (one
    # decade: a factor 10 lower, times the low pass at 100 Hz ~ 1 below 40 Hz)
    ratio = abs(wk_response(40.0)) / abs(wk_response(20.0))
    assert 0.45 < ratio < 0.52, ratio


def test_weighted_rms_of_a_sine_is_its_weighted_amplitude():
    dt = 1e-3
    t = np.arange(0, 10.0, dt)
    for f in (1.0, 6.3, 40.0):  # whole periods in the record: no leakage
        a = 2.0 * np.sin(2 * math.pi * f * t)
        # rms of a sine of amplitude 2 is sqrt 2; the filter's gain at f; FFT exact to 1e-12
        assert_allclose(weighted_rms(a, dt), math.sqrt(2.0) * abs(wk_response(f)), rtol=1e-9,
                        err_msg=f"{f} Hz")


def test_weighting_refuses_a_sampling_below_its_band():
    with pytest.raises(ParameterError, match="sample_period_s"):
        weighted_rms(np.zeros(100), 0.01)


def test_class_values_are_the_geometric_means_of_their_bounds():
    for name, gd in CLASS_GD_N0_M3.items():
        low, high = CLASS_BOUNDS_M3[name]
        assert_allclose(gd, high / 2 if low == 0 else math.sqrt(low * high), err_msg=name)
    assert_allclose(displacement_psd(0.1, "C"), 256e-6)
    assert_allclose(displacement_psd(1.0, "C"), 256e-6 / 100)


def test_bessel_product_against_scipy():
    special = pytest.importorskip("scipy.special")
    x = np.array([1e-3, 0.01, 0.1, 0.5, 1.0, 3.0, 10.0, 30.0])
    assert_allclose(bessel_k1_times_x(x), x * special.k1(x), rtol=1e-8)
    assert bessel_k1_times_x(0.0)[0] == 1.0


@pytest.mark.parametrize("road_class", ["A", "B", "C", "D"])
def test_generated_psd_matches_the_class(road_class):
    """Octave-band averages of the periodogram against the class's PSD. For this generator the
    band average over m bins is Gd chi^2_2m / 2m: relative standard deviation 1/sqrt(m); the
    bound is 4 of them (a false alarm in one of the ~8 bands at < 1e-3)."""
    spacing = 0.05
    x, left, right, _, _ = generate_tracks(road_class, seed=7, length_m=2000.0,
                                           spacing_m=spacing)
    for z in (left, right):
        n, g = periodogram(z, spacing)
        low = 0.011
        while low * 2 <= 2.83:
            band = (n >= low) & (n < 2 * low)
            m = int(band.sum())
            ratio = g[band].sum() / displacement_psd(n[band], road_class).sum()
            # the class's PSD weighted alike: sum of estimates over sum of the true values
            assert abs(ratio - 1.0) < 4.0 / math.sqrt(m), (road_class, low, m, ratio)
            low *= 2
        outside = (n > 0) & ((n < 0.011) | (n > 2.83))
        assert np.all(g[outside] < 1e-20 * g.max()), "power outside the band"


def test_tracks_coherence_is_the_isotropic_models():
    """The band-averaged real cross-spectrum over the auto-spectrum against rho: its scatter
    over m bins (2m real pairs) is about (1 - rho^2) / sqrt(2m); bound 4 of those plus rho's
    own change across the band."""
    spacing, track = 0.05, 1.4
    _, left, right, n, rho = generate_tracks("C", seed=3, length_m=4000.0, spacing_m=spacing,
                                             track_m=track)
    zl, zr = np.fft.rfft(left), np.fft.rfft(right)
    for low in (0.011, 0.03, 0.1, 0.3, 1.0):
        band = (n >= low) & (n < 2 * low)
        m = int(band.sum())
        estimate = np.real(zl[band] * np.conj(zr[band])).sum() / (np.abs(zl[band]) ** 2).sum()
        expected = rho[band].mean()
        spread = np.ptp(rho[band])
        bound = 4 * (1 - expected ** 2) / math.sqrt(2 * m) + spread
        assert abs(estimate - expected) < bound, (low, m, estimate, expected, bound)
    assert_allclose(track_correlation(0.0, track), 1.0)
    assert track_correlation(1.0, track)[0] < 1e-3  # 1 m waves: independent tracks


def test_profile_is_seeded_flat_at_the_start_and_checked():
    a = road_profile("B", seed=1, length_m=100.0)
    b = road_profile("B", seed=1, length_m=100.0)
    c = road_profile("B", seed=2, length_m=100.0)
    assert a == b and a != c
    assert a.flat_up_to_m() == 5.0
    assert a.height(2.0, 0.5) == 0.0
    assert a.height(50.0, 0.5) != a.height(50.0, -0.5)
    with pytest.raises(ParameterError, match="road_class"):
        road_profile("F", seed=1, length_m=100.0)
