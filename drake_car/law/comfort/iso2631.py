"""ISO 2631-1:1997 frequency weighting Wk (vertical whole-body vibration of a seated person,
z-axis at the seat surface) and the weighted RMS acceleration (pure numpy).

Wk is the product of four analogue filters in the Laplace variable p = j 2 pi f (ISO 2631-1,
Annex A, "Definition of frequency weightings"; parameters from its table of weighting
parameters, row Wk):

- band limiting, a 2nd-order Butterworth high pass at f1 = 0.4 Hz and low pass at
  f2 = 100 Hz (Q1 = Q2 = 1/sqrt 2):  Hh = 1 / (1 + sqrt2 w1/p + (w1/p)^2),
  Hl = 1 / (1 + sqrt2 p/w2 + (p/w2)^2);
- the acceleration-velocity transition, f3 = 12.5 Hz, f4 = 12.5 Hz, Q4 = 0.63:
  Ht = (1 + p/w3) / (1 + p/(Q4 w4) + (p/w4)^2)  (proportional to acceleration below f4,
  to velocity above);
- the upward step, f5 = 2.37 Hz, Q5 = 0.91, f6 = 3.35 Hz, Q6 = 0.91:
  Hs = (p^2 + p w5/Q5 + w5^2) / (p^2 + p w6/Q6 + w6^2)  (gain (f5/f6)^2 = 0.5 below f5,
  1 above f6),

with w_i = 2 pi f_i. Wk = Hh Hl Ht Hs; |Wk| is the standard's tabulated weighting factor
(largest, 1.054, at 6.3 Hz). The weighted RMS acceleration a_w = sqrt(mean(a_w(t)^2)),
a_w(t) the signal filtered by Wk (ISO 2631-1, 6.1, the basic evaluation method).
"""

import math

import numpy as np

from drake_car.law.checks import ParameterError

# ISO 2631-1:1997, the weighting parameters of Wk (Hz and the quality factors).
WK = {"f1_Hz": 0.4, "f2_Hz": 100.0, "f3_Hz": 12.5, "f4_Hz": 12.5, "Q4": 0.63,
      "f5_Hz": 2.37, "Q5": 0.91, "f6_Hz": 3.35, "Q6": 0.91}
# The highest frequency the weighting's one-third-octave bands reach for Wk (ISO 2631-1's
# band-limited range for health, comfort and perception: 0.5-80 Hz).
UPPER_BAND_HZ = 80.0


def wk_response(f_Hz):
    """Wk's complex frequency response at ``f_Hz`` (> 0; 0 at f = 0)."""
    f = np.asarray(f_Hz, dtype=float)
    p = 2j * math.pi * np.where(f > 0, f, 1.0)
    w = {k: 2.0 * math.pi * v for k, v in WK.items() if k.endswith("_Hz")}
    high_pass = 1.0 / (1.0 + math.sqrt(2.0) * w["f1_Hz"] / p + (w["f1_Hz"] / p) ** 2)
    low_pass = 1.0 / (1.0 + math.sqrt(2.0) * p / w["f2_Hz"] + (p / w["f2_Hz"]) ** 2)
    transition = (1.0 + p / w["f3_Hz"]) / (1.0 + p / (WK["Q4"] * w["f4_Hz"])
                                           + (p / w["f4_Hz"]) ** 2)
    step = ((p ** 2 + p * w["f5_Hz"] / WK["Q5"] + w["f5_Hz"] ** 2)
            / (p ** 2 + p * w["f6_Hz"] / WK["Q6"] + w["f6_Hz"] ** 2))
    return np.where(f > 0, high_pass * low_pass * transition * step, 0.0)


def wk_weighted(a_mps2, sample_period_s):
    """The signal weighted by Wk, filtered in the frequency domain (the record taken as one
    period; its mean is removed by the high pass). The sampling must resolve the weighting:
    its Nyquist frequency must be at least ``UPPER_BAND_HZ``."""
    a = np.asarray(a_mps2, dtype=float)
    nyquist = 0.5 / sample_period_s
    if nyquist < UPPER_BAND_HZ:
        raise ParameterError("sample_period_s", sample_period_s,
                             f"gives a Nyquist frequency of {nyquist:g} Hz, below Wk's "
                             f"{UPPER_BAND_HZ:g} Hz band; sample at <= "
                             f"{0.5 / UPPER_BAND_HZ:g} s")
    f = np.fft.rfftfreq(a.size, sample_period_s)
    return np.fft.irfft(np.fft.rfft(a) * wk_response(f), a.size)


def weighted_rms(a_mps2, sample_period_s):
    """ISO 2631-1's frequency-weighted RMS acceleration a_w (m/s^2) of a record with Wk."""
    return float(np.sqrt(np.mean(wk_weighted(a_mps2, sample_period_s) ** 2)))
