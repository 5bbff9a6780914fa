"""Whether a number computed at successive halvings of the time step has converged: the one rule
of accuracy on demand, used by the global route on a whole run's outcomes (``sweep.refine``)
and by the local route on a window's rest positions (``sim.resolve``).

On the values at h, h/2, h/4, ... (the last three): with d1 = |x(h/2^(k-2)) - x(h/2^(k-1))| and
d2 = |x(h/2^(k-1)) - x(h/2^k)|, the error of the finest value is max(d2, 2^-p · d1) (for p = 1,
d2 is Richardson's estimate of the finer value's error; the floor keeps a branch jump followed
by two agreeing steps, 6.7 / 5.0 / 5.0, from passing as exact); it has converged when that
error is within the tolerance and the differences shrink as a scheme of order p makes them
shrink (d2 <= 1.5 · 2^-p · d1: the slack for a ratio measured on two differences), or both
differences are below a tenth of the tolerance (three steps agree where there is nothing left
to shrink, e.g. a count; a window's rest positions: ``sim.window.agreement_band``), or both
are within ``floor`` (the solver's own error: the step has taken it as far as the solver lets
it). The observed order is log2(d1/d2). Otherwise it has not converged, and its error is the
span of the last three values. Two steps alone cannot tell
"converged" from "both on the same wrong branch" of a stick-slip outcome, hence three."""

import math

SLACK = 1.5  # of the expected ratio 2^-p between successive differences
NOISE = 0.1  # of the tolerance: differences this small need not shrink


def classify(values, tolerance, order=1, floor=0.0, noise=None):
    """Convergence of a number from its ``values`` at successive halvings of the step (see the
    module); ``floor``: its solver error, below which differences need not shrink; ``noise``:
    the band below which they need not shrink either (None: ``NOISE`` of the tolerance).
    Returns {"converged", "value" (the finest), "error", "observed_order" (None when not
    measurable)}."""
    values = [float(v) for v in values]
    last = values[-1]
    if len(values) < 3:
        span = max(values) - min(values)
        return {"converged": False, "value": last, "error": span, "observed_order": None}
    x0, x1, x2 = values[-3:]
    d1, d2 = abs(x0 - x1), abs(x1 - x2)
    observed = math.log2(d1 / d2) if d1 > 0 and d2 > 0 else None
    shrinks = d2 <= SLACK * 2.0 ** -order * d1
    band = NOISE * tolerance if noise is None else noise
    quiet = max(d1, d2) <= max(band, floor)
    # The finest value's error: d2, but no less than d1 shrunk once at the scheme's order. A
    # last difference far below that (6.7, 5.0, 5.0: a branch jump, then two steps on the new
    # branch) is not the scheme's error shrinking: two values on a branch are not three.
    error = max(d2, 2.0 ** -order * d1)
    floored = max(d1, d2) <= floor  # the step has taken it as far as the solver lets it
    if (error <= tolerance and (shrinks or quiet)) or floored:
        return {"converged": True, "value": x2, "error": error, "observed_order": observed}
    return {"converged": False, "value": x2, "error": max(x0, x1, x2) - min(x0, x1, x2),
            "observed_order": observed}
