"""The strut side-load friction rig (sim/strut_rig.py) and its loop evaluation (study/rig)."""

import numpy as np
import pytest
from numpy.testing import assert_allclose

from drake_car.law.checks import ParameterError
from drake_car.law.friction.frd import StrutFrictionParameters
from drake_car.model.parameters import CarParameters
from drake_car.sim.strut_rig import (
    StrutRigOptions, corner_side_force_N, eq4_normal_force_N, simulate_strut_rig)
from drake_car.study.rig.analysis import loop_statistics
from drake_car.study.rig.loops import SYNTHETIC_LAW, synthetic_fit

CAR = CarParameters()


@pytest.fixture(scope="module")
def loop():
    options = StrutRigOptions(side_force_N=1000.0, stroke_amplitude_m=0.01,
                              stroke_frequency_hz=1.0)
    law = StrutFrictionParameters(mu_s=0.2, mu_d=0.15)
    return options, law, simulate_strut_rig(CAR, options, law, cycles=2.5)


def test_normal_force_is_eq4_of_the_side_load(loop):
    """The system's N (from Drake's joint reaction) against eq. 4's closed form at each stroke:
    quasi-static, so they differ only by the knuckle's inertia in the reaction (m·a, at most
    13 kg × 0.4 m/s² × the lever ratio ≈ 0.5 % here) and N's one-step lag (0.3 % of N per
    step at 63 mm/s); 1 % bounds both."""
    options, _, h = loop
    moving = h["t"] > 0.1
    expected = [eq4_normal_force_N(CAR.front, options, q) for q in h["stroke_m"][moving]]
    assert_allclose(h["normal_N"][moving], expected, rtol=0.01,
                    err_msg="rig N against |F| sqrt(1 + (a/d)^2)")


def test_sliding_and_breakaway_forces(loop):
    """Sliding at μd·N: the sliding samples' friction equals μd·N(q) to the Stribeck band's
    absence (exact above 1.5 Δv); the break-away load is at least μs·N and at most one step's
    load rise above it plus the inertia of the knuckle starting to move (the apparent μs)."""
    options, law, h = loop
    stats = loop_statistics(h["stroke_m"], h["load_cell_N"], h["normal_N"],
                            sample_period_s=options.time_step_s)
    assert stats.half_cycles >= 3
    assert_allclose(stats.mu_d, law.mu_d, rtol=2e-3, err_msg="sliding μ")
    for c in stats.cycles:
        assert law.mu_s <= c.breakaway_mu <= 1.15 * law.mu_s, c


def test_the_lubricated_strut_is_viscous():
    options = StrutRigOptions(side_force_N=1000.0, stroke_amplitude_m=0.005,
                              stroke_frequency_hz=1.0)
    h = simulate_strut_rig(CAR, options, None, cycles=1.0)
    c = CAR.front.strut_damping_Nspm
    assert_allclose(h["friction_N"], -c * h["velocity_mps"], atol=1e-9)


def test_corner_side_force_is_the_moment_balance():
    f = CAR.front
    lever = f.top_mount_height_m - f.ball_joint_height_m
    assert_allclose(corner_side_force_N(f, 3800.0), 3800.0 * f.ball_joint_offset_b_m / lever)


def test_bad_options_are_refused():
    with pytest.raises(ParameterError, match="stroke_amplitude_m"):
        StrutRigOptions(stroke_amplitude_m=0.2).check(CAR.front)
    with pytest.raises(ParameterError, match="side_force_N"):
        StrutRigOptions(side_force_N=1e6).check(CAR.front)


@pytest.mark.slow
def test_fit_recovers_mu_s_of_a_synthetic_loop():
    """The done-when: a loop made by the rig with known μs, μd plus noise; the fit recovers μs
    within its stated 95 % confidence and μd within its own."""
    *_, fit = synthetic_fit(CAR)
    assert abs(fit.mu_s - SYNTHETIC_LAW[0]) <= fit.mu_s_ci95, fit
    assert abs(fit.mu_d - SYNTHETIC_LAW[1]) <= max(fit.mu_d_ci95, 1e-3), fit
    assert fit.mu_s_ci95 < 0.05, fit  # the confidence says something
    assert not fit.dv_resolved  # 2 µm at 1 kHz resolves 3 mm/s, not Δv = 0.1 mm/s
