"""Akima's interpolation (H. Akima, J. ACM 17(4), 1970; the paper's ref. [1]), pure numpy.

Given knots (x_i, y_i), the slope at each knot is the weighted mean of the neighbouring secant
slopes m_{i-1}, m_i with weights |m_{i+1} - m_i| and |m_{i-1} - m_{i-2}| (the plain mean where
both weights vanish); two extra secants at each end are extrapolated linearly (Akima's eq. for
end points). Between knots the curve is the cubic Hermite polynomial through the values and
slopes: C¹ continuous, no overshoot on flat stretches.
"""

import numpy as np


def akima_slopes(x, y):
    """Slopes dy/dx at the knots (Akima 1970)."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if x.ndim != 1 or x.shape != y.shape:
        raise ValueError("Akima: x and y must be 1-D arrays of the same length")
    if x.size < 3:
        raise ValueError(f"Akima: needs at least 3 knots, got {x.size}")
    if not np.all(np.isfinite(x)) or not np.all(np.isfinite(y)):
        raise ValueError("Akima: knots must be finite")
    if np.any(np.diff(x) <= 0):
        raise ValueError("Akima: knot abscissae must be strictly increasing")
    m = np.diff(y) / np.diff(x)
    # Two extrapolated secants at each end: m_{-1} = 2 m_0 - m_1, m_{-2} = 2 m_{-1} - m_0.
    m_ext = np.concatenate([[3 * m[0] - 2 * m[1], 2 * m[0] - m[1]], m,
                            [2 * m[-1] - m[-2], 3 * m[-1] - 2 * m[-2]]])
    w_right = np.abs(m_ext[3:] - m_ext[2:-1])  # |m_{i+1} - m_i|
    w_left = np.abs(m_ext[1:-2] - m_ext[:-3])  # |m_{i-1} - m_{i-2}|
    left, right = m_ext[1:-2], m_ext[2:-1]  # m_{i-1}, m_i
    total = w_left + w_right
    scale = np.max(np.abs(m_ext)) if np.any(m_ext) else 1.0
    flat = total <= 1e-12 * scale
    slopes = np.where(flat, 0.5 * (left + right),
                      (w_right * left + w_left * right) / np.where(flat, 1.0, total))
    return slopes


def hermite_eval(x, y, slopes, t):
    """Evaluates the cubic Hermite interpolant and its derivative at ``t`` (clamped to the
    knots' range: constant before the first knot and after the last)."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    t = np.clip(np.asarray(t, dtype=float), x[0], x[-1])
    i = np.clip(np.searchsorted(x, t, side="right") - 1, 0, x.size - 2)
    h = x[i + 1] - x[i]
    s = (t - x[i]) / h
    h00, h10 = 2 * s ** 3 - 3 * s ** 2 + 1, s ** 3 - 2 * s ** 2 + s
    h01, h11 = -2 * s ** 3 + 3 * s ** 2, s ** 3 - s ** 2
    value = h00 * y[i] + h10 * h * slopes[i] + h01 * y[i + 1] + h11 * h * slopes[i + 1]
    d00, d10 = (6 * s ** 2 - 6 * s) / h, 3 * s ** 2 - 4 * s + 1
    d01, d11 = (-6 * s ** 2 + 6 * s) / h, 3 * s ** 2 - 2 * s
    derivative = d00 * y[i] + d10 * slopes[i] + d01 * y[i + 1] + d11 * slopes[i + 1]
    return value, derivative
