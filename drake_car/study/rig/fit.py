"""Fit the friction law's μs and μd to a measured strut loop, with the rig's model.

μd is the sliding force over N(q) (``analysis.loop_statistics``). μs is not the peak over N: a
rig's peak overshoots μs·N by what its dynamics add after the break-away (the knuckle's mass
against the load path's stiffness). The fit runs the rig (``sim.strut_rig``) with the measured
test's side load, stroke and frequency and finds, the μs whose simulated
apparent μs (the same estimator on the simulated loop) equals the measured one: the rig runs
at ``GRID_POINTS`` values of μs from 0.75 × the apparent value (or μd) to the apparent value
(the rig only adds to the peak), a line is fitted through (μs, simulated apparent μs) and
inverted. The simulated apparent μs is a staircase, not a line (the break-away falls on one of
the rig's steps; one step's load increase is ~0.02 in μ at 1 Hz, 10 mm), so the 95 %
confidence of μs combines the measured apparent μs's confidence with the grid's scatter about
its line (t(0.975, n-2)·s), divided by the line's slope.
"""

import dataclasses
import math

import numpy as np
from scipy import stats

from drake_car.law.friction.frd import StrutFrictionParameters
from drake_car.sim.rigs.strut import eq4_normal_force_N, simulate_strut_rig
from drake_car.study.rig.analysis import LoopError, loop_statistics

FIT_CYCLES = 5.0  # nine complete half-cycles after the first motion
GRID_POINTS = 5
GRID_LOW = 0.75


@dataclasses.dataclass
class LoopFit:
    mu_s: float
    mu_s_ci95: float
    mu_d: float
    mu_d_ci95: float
    apparent_mu_s: float
    apparent_mu_s_ci95: float
    peak_slope: float  # d(apparent μs)/d(μs) on the rig
    model_scatter_ci95: float  # the grid's scatter about its line (the step's discreteness)
    half_cycles: int
    residual_rms_N: float
    stroke_noise_m: float
    dmax_resolved: bool
    dv_resolved: bool

    def summary(self):
        return dataclasses.asdict(self)


def normal_forces_N(car, options, stroke_m):
    return np.array([eq4_normal_force_N(car.front, options, q) for q in stroke_m])


def fit_measured_loop(car, options, stroke_m, force_N, *, sample_period_s,
                      template: StrutFrictionParameters | None = None):
    """Fits μs, μd to the loop (stroke, force) measured on a rig run as ``options`` (side load,
    stroke, frequency, rig stiffness); ``template``: the law's other parameters (Δmax, Δv,
    shapes; default the paper's)."""
    template = template or StrutFrictionParameters()
    normal = normal_forces_N(car, options, stroke_m)
    measured = loop_statistics(stroke_m, force_N, normal, sample_period_s=sample_period_s,
                               dmax_m=template.dmax_translation_m,
                               dv_mps=template.dv_translation_mps)
    mu_d = measured.mu_d
    target = measured.apparent_mu_s

    def apparent(mu_s):
        law = dataclasses.replace(template, mu_s=mu_s, mu_d=min(mu_d, mu_s))
        h = simulate_strut_rig(car, options, law, cycles=FIT_CYCLES)
        if not np.isfinite(h["load_cell_N"]).all():
            raise LoopError("the rig's model diverged")
        stats = loop_statistics(h["stroke_m"], h["load_cell_N"], h["normal_N"],
                                sample_period_s=options.time_step_s)
        return stats.apparent_mu_s

    # The apparent μs is never below μs (the rig only adds to the peak): a grid from
    # max(μd, 0.75 × apparent) to the apparent value, a line through it, inverted.
    grid = np.linspace(max(mu_d, GRID_LOW * target), target, GRID_POINTS)
    values = np.array([apparent(m) for m in grid])
    slope, intercept = np.polyfit(grid, values, 1)
    if not slope > 0:
        raise LoopError("the rig's break-away does not grow with μs near the measured value: "
                        "μs is not identifiable from this loop")
    mu_s = (target - intercept) / slope
    scatter = values - (slope * grid + intercept)
    model_ci = stats.t.ppf(0.975, GRID_POINTS - 2) * scatter.std(ddof=2)
    ci = math.hypot(measured.apparent_mu_s_ci95, model_ci) / slope
    return LoopFit(mu_s=float(mu_s), mu_s_ci95=float(ci),
                   mu_d=mu_d, mu_d_ci95=measured.mu_d_ci95, apparent_mu_s=target,
                   apparent_mu_s_ci95=measured.apparent_mu_s_ci95, peak_slope=float(slope),
                   model_scatter_ci95=float(model_ci), half_cycles=measured.half_cycles,
                   residual_rms_N=measured.residual_rms_N,
                   stroke_noise_m=measured.stroke_noise_m,
                   dmax_resolved=measured.dmax_resolved, dv_resolved=measured.dv_resolved)
