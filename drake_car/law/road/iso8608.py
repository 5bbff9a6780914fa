"""Random road profiles of the ISO 8608 classes (pure numpy): two parallel wheel tracks, a
Gaussian realisation of the standard's displacement PSD from a seed, with the left-right
coherence of an isotropic road surface.

**The PSD** (ISO 8608:2016, "Mechanical vibration - Road surface profiles - Reporting of
measured data", the classification of roads by their displacement PSD; values unchanged from
ISO 8608:1995): Gd(n) = Gd(n0) (n / n0)^-w, reference spatial frequency n0 = 0.1 cycles/m,
waviness w = 2; the classes' geometric-mean Gd(n0) (class bounds in brackets), in 1e-6 m^3:
A 16 (< 32), B 64 (32-128), C 256 (128-512), D 1024 (512-2048). Gd is one-sided in n
(cycles/m): the profile's variance is the integral of Gd over n > 0.

**The generator**: the track is periodic over ``length_m`` on a grid of ``spacing_m`` and its
Fourier coefficients at n_k = k / length_m are independent Gaussians (filtered white noise in
the frequency domain, random amplitudes and phases, not a sum of sinusoids of fixed
amplitude): z(x) = sum_k a_k cos(2 pi n_k x) + b_k sin(2 pi n_k x), a_k, b_k ~ N(0, Gd(n_k)/L),
for n_k inside the band [``band_low``, ``band_high``] (default ISO 8608's range of spatial
frequencies, 0.011-2.83 cycles/m: wavelengths 0.35-90 m), none outside. A band-averaged
periodogram of m bins is then Gd times chi^2_2m / 2m (relative standard deviation 1/sqrt(m)),
which the tests use as their tolerance.

**Two tracks**: the right track's coefficients are rho a_k + sqrt(1 - rho^2) a'_k (the same for
b), with a'_k, b'_k independent of a_k, b_k: the cross-spectrum is rho Gd (real: no phase
between the tracks) and the coherence rho^2. rho is the isotropic surface's (Dodds & Robson,
"The description of road surface roughness", J. Sound Vib. 31(2), 1973, 175-183: the road's
2-D spectrum depends only on the wavenumber's magnitude): for w = 2 the 2-D spectrum goes as
k^-3, and the cross-spectrum of two parallel lines a track width B apart over the
auto-spectrum of one is rho(n) = x K1(x), x = 2 pi n B (derived here: integrate
(kappa^2 + eta^2)^-3/2 cos(eta B) over the lateral wavenumber eta; K1 the modified Bessel
function of the second kind). rho -> 1 for wavelengths much longer than B and decays as
exp(-x) below. Measured roads are often less coherent than isotropic at long wavelengths
(Bogsjo, Vehicle System Dynamics 45, 2007) [EST: the isotropic model is the standard
assumption, not fitted to a road].
"""

import math

import numpy as np

from drake_car.law.checks import ParameterError
from drake_car.law.road.profiles import MAX_LENGTH_M, SampledProfile

REFERENCE_FREQUENCY_CYCLES_PER_M = 0.1  # n0
WAVINESS = 2.0  # w
# ISO 8608:2016, the classes' geometric-mean Gd(n0) (m^3) and their bounds (m^3).
CLASS_GD_N0_M3 = {"A": 16e-6, "B": 64e-6, "C": 256e-6, "D": 1024e-6}
CLASS_BOUNDS_M3 = {"A": (0.0, 32e-6), "B": (32e-6, 128e-6), "C": (128e-6, 512e-6),
                   "D": (512e-6, 2048e-6)}
# ISO 8608's range of spatial frequencies (cycles/m).
BAND_CYCLES_PER_M = (0.011, 2.83)


def displacement_psd(n_cycles_per_m, road_class):
    """Gd(n) (m^3 = m^2 per cycle/m), one-sided, of ``road_class`` (A-D)."""
    n = np.asarray(n_cycles_per_m, dtype=float)
    return class_gd(road_class) * (n / REFERENCE_FREQUENCY_CYCLES_PER_M) ** -WAVINESS


def class_gd(road_class):
    if road_class not in CLASS_GD_N0_M3:
        raise ParameterError("road_class", road_class,
                             f"must be one of {', '.join(CLASS_GD_N0_M3)} (ISO 8608)")
    return CLASS_GD_N0_M3[road_class]


def bessel_k1_times_x(x):
    """x K1(x) for x >= 0 (1 at x = 0), from K1(x) = int_0^inf exp(-x cosh t) cosh t dt
    (trapezoid on t in [0, 12] with 4001 points: relative error < 1e-9 for x in [1e-3, 50])."""
    x = np.atleast_1d(np.asarray(x, dtype=float))
    t = np.linspace(0.0, 12.0, 4001)
    cosh = np.cosh(t)
    out = np.ones_like(x)
    small = x < 1e-6
    xs = x[~small][:, None]
    integrand = np.exp(-xs * cosh) * cosh
    out[~small] = x[~small] * np.trapezoid(integrand, t, axis=1)
    return out


def track_correlation(n_cycles_per_m, track_m):
    """rho(n) = x K1(x), x = 2 pi n B: the real cross-spectrum of the two tracks over the
    auto-spectrum of one (coherence rho^2), for an isotropic road of waviness 2."""
    return bessel_k1_times_x(2.0 * math.pi * np.asarray(n_cycles_per_m) * track_m)


def generate_tracks(road_class, *, seed, length_m, spacing_m=0.05, track_m=1.4,
                    band=BAND_CYCLES_PER_M):
    """(x (m), left z (m), right z (m), n (cycles/m), rho) of one realisation: ``length_m`` of
    road (periodic) on a grid of ``spacing_m``; ``n`` and ``rho`` on the Fourier grid."""
    gd0 = class_gd(road_class)
    count = int(round(length_m / spacing_m))
    if count < 16 or length_m > MAX_LENGTH_M:
        raise ParameterError("length_m", length_m,
                             f"must hold >= 16 samples of {spacing_m} m and be <= "
                             f"{MAX_LENGTH_M:g} m")
    low, high = band
    nyquist = 0.5 / spacing_m
    if not 0.0 < low < high <= nyquist:
        raise ParameterError("band", band, f"must satisfy 0 < low < high <= the grid's "
                                           f"Nyquist frequency {nyquist:g} cycles/m")
    length = count * spacing_m
    n = np.arange(count // 2 + 1) / length
    inside = (n >= low) & (n <= high)
    sigma = np.zeros_like(n)
    sigma[inside] = np.sqrt(gd0 * (n[inside] / REFERENCE_FREQUENCY_CYCLES_PER_M) ** -WAVINESS
                            / length)
    rng = np.random.default_rng(seed)
    a, b, a2, b2 = (sigma * rng.standard_normal(n.size) for _ in range(4))
    rho = np.zeros_like(n)
    rho[inside] = track_correlation(n[inside], track_m)
    other = np.sqrt(1.0 - rho ** 2)
    left = _synthesis(a, b, count)
    right = _synthesis(rho * a + other * a2, rho * b + other * b2, count)
    return np.arange(count) * spacing_m, left, right, n, rho


def _synthesis(a, b, count):
    """sum_k a_k cos(2 pi k i / N) + b_k sin(2 pi k i / N) on i = 0..N-1, by an inverse FFT."""
    spectrum = 0.5 * count * (a - 1j * b)
    spectrum[0] = 0.0
    return np.fft.irfft(spectrum, count)


def periodogram(z, spacing_m):
    """(n (cycles/m), one-sided PSD estimate (m^3)) of a periodic record: (a_k^2 + b_k^2) L / 2
    at n_k = k / L, the estimator whose mean is Gd(n_k) for this generator."""
    z = np.asarray(z, dtype=float)
    count = z.size
    length = count * spacing_m
    spectrum = np.fft.rfft(z)
    return np.arange(spectrum.size) / length, 2.0 * np.abs(spectrum) ** 2 / count ** 2 * length


def road_profile(road_class, *, seed, length_m, start_m=5.0, fade_m=5.0, spacing_m=0.05,
                 track_m=1.4, band=BAND_CYCLES_PER_M) -> SampledProfile:
    """A two-track ``SampledProfile`` (left ``z_m``, right ``z_right_m``): flat up to
    ``start_m`` (where the car stands), the random road faded in over ``fade_m`` with a
    raised cosine, then ``generate_tracks``' realisation up to ``start_m + length_m``."""
    x, left, right, _, _ = generate_tracks(road_class, seed=seed, length_m=length_m,
                                           spacing_m=spacing_m, track_m=track_m, band=band)
    s = np.clip(x / fade_m, 0.0, 1.0) if fade_m > 0 else np.ones_like(x)
    fade = 0.5 * (1.0 - np.cos(math.pi * s))
    fade[0] = 0.0
    stations = np.concatenate([[0.0], start_m + x])
    zl = np.concatenate([[0.0], fade * left])
    zr = np.concatenate([[0.0], fade * right])
    return SampledProfile(x_m=[float(v) for v in stations], z_m=[float(v) for v in zl],
                          z_right_m=[float(v) for v in zr]).check()
