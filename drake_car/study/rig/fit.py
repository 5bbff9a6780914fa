"""Fit the friction law's μs and μd to a measured strut loop, with the rig's model.

μd is the sliding force over N(q) (``analysis.loop_statistics``). μs is not the peak over N: a
rig's peak overshoots μs·N by what its dynamics add after the break-away (the knuckle's mass
against the load path's stiffness). The fit runs the rig (``sim.rigs.strut``) with the measured
test's side load, stroke and frequency and finds, the μs whose simulated
apparent μs (the same estimator on the simulated loop) equals the measured one: the rig runs
at ``GRID_POINTS`` values of μs from 0.75 × the apparent value (or μd) to the apparent value
(the rig only adds to the peak), a line is fitted through (μs, simulated apparent μs) and
inverted. The simulated apparent μs is a staircase, not a line (the break-away falls on one of
the rig's steps; one step's load increase is ~0.02 in μ at 1 Hz, 10 mm), so the 95 %
confidence of μs combines the measured apparent μs's confidence with the grid's scatter about
its line (t(0.975, n-2)·s), divided by the line's slope.

Values outside the law's range (μd < 0, μs above ``MU_MAX``) are refused naming them; a fit
whose residual is far above the loop's own noise (``measured.residual_check``) is flagged:
``confident`` False and the reason in ``warnings``, never a confident value.
"""

import dataclasses
import logging
import math

import numpy as np
from scipy import stats

from drake_car.law.friction.frd import StrutFrictionParameters
from drake_car.sim.rigs.at_rest import SIDE_FORCE_POINT_BELOW_TOP_M
from drake_car.sim.rigs.strut import eq4_normal_force_N, simulate_strut_rig
from drake_car.study.rig.analysis import LoopError, loop_statistics
from drake_car.study.rig.measured import MU_MAX, read_loop, residual_check, rig_of_loop

log = logging.getLogger(__name__)

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
    noise_N: float = 0.0  # the loop's own noise (measured.residual_check)
    confident: bool = True
    warnings: list = dataclasses.field(default_factory=list)

    def summary(self):
        return dataclasses.asdict(self)

    def line(self):
        """The fit in a line: with its 95 % confidence, or said to be no confident value."""
        values = (f"μs = {self.mu_s:.4f} ± {self.mu_s_ci95:.4f}, μd = {self.mu_d:.4f} ± "
                  f"{self.mu_d_ci95:.4f} (95 %)")
        if self.confident:
            return values
        return (f"μs = {self.mu_s:.4f}, μd = {self.mu_d:.4f}: not a confident value (the "
                "law does not describe the loop: see the warning; the ± would assume it does)")


def fit_loop_file(car, path, *, side_force_N=None,
                  side_force_point_below_top_m=SIDE_FORCE_POINT_BELOW_TOP_M, amplitude_m=None,
                  frequency_hz=None, sample_period_s=None):
    """(LoopFit, StrutRigOptions of the test, what was taken from the loop) of the measured
    loop in CSV ``path``: read, checked against the rig and the options given
    (``measured.rig_of_loop``; the side force at the top mount unless
    ``side_force_point_below_top_m`` says where else), fitted; a LoopError names --measured
    and the file. What was taken from the loop is logged (info), a flagged fit's warning too
    (warning)."""
    try:
        loop = read_loop(path)
        options, period, notes = rig_of_loop(
            car, loop, side_force_N=side_force_N,
            side_force_point_below_top_m=side_force_point_below_top_m, amplitude_m=amplitude_m,
            frequency_hz=frequency_hz, sample_period_s=sample_period_s)
        for note in notes:
            log.info("--measured %s: from the loop: %s", path, note)
        fit = fit_measured_loop(car, options, loop.stroke_m, loop.force_N,
                                sample_period_s=period)
    except LoopError as e:
        raise LoopError(f"--measured {path}: {e}") from None
    for warning in fit.warnings:
        log.warning("--measured %s: %s", path, warning)
    return fit, options, notes


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
    if not 0 <= mu_d <= MU_MAX:
        raise LoopError(f"its sliding force gives μd = {mu_d:.4g}; the law allows 0 <= μd <= "
                        f"{MU_MAX:g} (is the force's sign, its unit or the side load another?)")
    if not mu_d < MU_MAX:
        raise LoopError(f"its break-away gives an apparent μs of {target:.4g} over μd = "
                        f"{mu_d:.4g}: no μs <= {MU_MAX:g} of the law lies between them")

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
    top = min(target, MU_MAX)  # the law's limit
    grid = np.linspace(min(max(mu_d, GRID_LOW * target), 0.99 * top), top, GRID_POINTS)
    values = np.array([apparent(m) for m in grid])
    slope, intercept = np.polyfit(grid, values, 1)
    if not slope > 0:
        raise LoopError("the rig's break-away does not grow with μs near the measured value: "
                        "μs is not identifiable from this loop")
    mu_s = float((target - intercept) / slope)
    if not mu_d <= mu_s <= MU_MAX:
        raise LoopError(f"the fitted μs = {mu_s:.4g} lies outside the law's range μd = "
                        f"{mu_d:.4g} <= μs <= {MU_MAX:g} (apparent μs {target:.4g})")
    scatter = values - (slope * grid + intercept)
    model_ci = stats.t.ppf(0.975, GRID_POINTS - 2) * scatter.std(ddof=2)
    ci = math.hypot(measured.apparent_mu_s_ci95, model_ci) / slope
    omega = 2 * math.pi * options.stroke_frequency_hz
    check = residual_check(stroke_m, force_N, sample_period_s=sample_period_s, mu_d=mu_d,
                           normal_N=normal, floor_N=car.mass.front_knuckle_kg * omega ** 2
                           * options.stroke_amplitude_m / 2)  # the inertia while sliding
    return LoopFit(mu_s=mu_s, mu_s_ci95=float(ci),
                   mu_d=mu_d, mu_d_ci95=measured.mu_d_ci95, apparent_mu_s=target,
                   apparent_mu_s_ci95=measured.apparent_mu_s_ci95, peak_slope=float(slope),
                   model_scatter_ci95=float(model_ci), half_cycles=measured.half_cycles,
                   residual_rms_N=measured.residual_rms_N,
                   stroke_noise_m=measured.stroke_noise_m,
                   dmax_resolved=measured.dmax_resolved, dv_resolved=measured.dv_resolved,
                   noise_N=check.noise_N, confident=check.confident,
                   warnings=[check.warning] if check.warning else [])
