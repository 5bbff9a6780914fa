"""The explicit (reference) scheme converges on the friction rig's closed-form cases as its step
shrinks, to the law's own solution, which lies within the regularisation's derived distance of
the Coulomb closed form (``law.friction.coulomb``); the fast scheme converges to it.

Tolerances, from the model:
- Two steps agreeing: halving the step moves a result by less than one step's worth of it (the
  period by less than the step dt; a velocity by less than a·dt). Both schemes decide each phase
  switch at the end of a step and apply the law's force one step late, so each event of a cycle
  moves by up to a step; a first-order scheme halves that with the step.
- The fast scheme agrees with the reference: by Richardson's estimate of a first-order scheme,
  its error at dt/2 is about its change from dt to dt/2; it must be within 1.5 times that.
- The law's period against Coulomb's: within ``coulomb.belt_shift``'s bracket (derived there),
  widened by the step.
"""

import math

import numpy as np
import pytest

from drake_car.law.friction.coulomb import incline_acceleration_mps2
from drake_car.study.rig.closed_forms import (
    BELT, BELT_LAW, INCLINE_LAW, belt_bracket, run_belt, run_incline, run_oscillator)

G = 9.81
# The belt case's explicit stability limit is 2 m Δv / (1.5 μs N) = 0.33 ms.
BELT_REFERENCE_STEPS_S = (8e-5, 4e-5)
BELT_FAST_STEPS_S = (2e-4, 1e-4)
BELT_SHORT_S = 1.2  # the first cycle (from rest) and one limit cycle


def _belt(scheme, steps, duration_s=BELT_SHORT_S):
    return [run_belt(scheme, dt, duration_s=duration_s) for dt in steps]


def test_belt_reference_converges_and_the_fast_scheme_to_it():
    """Δv = 1 % of the belt's 0.1 m/s, Δmax = 1 % of the 10 mm stick (issue 32's belt)."""
    bracket = belt_bracket()
    coarse, fine = _belt("reference", BELT_REFERENCE_STEPS_S)
    period = fine.periods_s[-1]
    change = abs(coarse.periods_s[-1] - period)
    dt = BELT_REFERENCE_STEPS_S[0]
    print(f"reference: period {coarse.periods_s[-1]:.7f} / {period:.7f} s at {dt:g} / "
          f"{dt / 2:g} s, {100 * bracket.relative(period):+.3f} % of Coulomb's; bracket "
          f"{100 * bracket.relative(bracket.period_low_s):+.2f} .. "
          f"{100 * bracket.relative(bracket.period_high_s):+.2f} %")
    assert change < dt, (coarse.periods_s, fine.periods_s)
    assert bracket.period_low_s - dt <= period <= bracket.period_high_s + dt
    # The derivation's parts: where the slip starts, how far the block lags in the band, and
    # the identity that puts them together (its residual is the scheme's error: it halves).
    x_s = BELT_LAW.mu_s * BELT["normal_force_N"] / BELT["spring_Npm"]
    xi = fine.slip_start_m[-1] - x_s
    assert 0 <= xi <= bracket.exit_bound_m, (xi, bracket.exit_bound_m)
    assert 0 <= fine.lag_m[-1] <= bracket.lag_bound_m, (fine.lag_m, bracket.lag_bound_m)
    residual = [abs(r.law_period_s[-1] - r.periods_s[-1]) for r in (coarse, fine)]
    assert residual[1] < 0.6 * residual[0] and residual[0] < dt, residual

    fast = _belt("fast", BELT_FAST_STEPS_S)
    fast_change = abs(fast[0].periods_s[-1] - fast[1].periods_s[-1])
    distance = abs(fast[1].periods_s[-1] - period)
    print(f"fast: {fast[0].periods_s[-1]:.7f} / {fast[1].periods_s[-1]:.7f} s at "
          f"{BELT_FAST_STEPS_S[0]:g} / {BELT_FAST_STEPS_S[1]:g} s")
    assert fast_change < BELT_FAST_STEPS_S[0]
    assert distance <= 1.5 * fast_change + change, (distance, fast_change, change)


@pytest.mark.slow
@pytest.mark.parametrize("law", [BELT_LAW, BELT_LAW.__class__(mu_s=0.4, mu_d=0.3)],
                         ids=["dv 1 % of V", "the paper's dv and dmax"])
def test_belt_reference_converges_at_first_order(law):
    """Three explicit steps at a quarter, an eighth and a sixteenth of the stability limit: the
    period's changes halve with the step (first order) and the finest lies in the bracket.
    Also with the paper's Δv = 1e-4 m/s and Δmax = 5 µm (0.1 % and 0.05 %)."""
    limit = 2 * BELT["mass_kg"] * law.dv_translation_mps / (
        1.5 * law.mu_s * BELT["normal_force_N"])
    steps = (limit / 4, limit / 8, limit / 16)
    runs = [run_belt("reference", dt, law=law) for dt in steps]
    periods = np.array([r.periods_s[-1] for r in runs])
    changes = np.abs(np.diff(periods))
    bracket = belt_bracket(law)
    print(f"periods {periods} s at {steps} s; changes {changes}; Coulomb "
          f"{bracket.coulomb.period_s:.7f} s, {100 * bracket.relative(periods[-1]):+.3f} %")
    assert np.all(changes < steps[:2]), changes
    assert 1.4 < changes[0] / changes[1] < 2.8, changes
    assert bracket.period_low_s - steps[-1] <= periods[-1] <= bracket.period_high_s + steps[-1]


def test_free_oscillator_decays_by_4_mu_d_n_over_k_per_cycle():
    """The explicit scheme at 1/2 and 1/4 of its limit (40 µs): each cycle's decay is Coulomb's
    4 μd N / k within the law's turn bound (second order in Δv, 1.3e-8 m here) plus the step's
    change; the fast scheme at 1 and 0.5 ms converges to it."""
    steps = (2e-5, 1e-5)
    coarse, fine = (run_oscillator("reference", dt) for dt in steps)
    assert fine.decay_per_cycle_m.size >= 3, fine.turns_m
    change = float(np.max(np.abs(coarse.decay_per_cycle_m - fine.decay_per_cycle_m)))
    error = float(np.max(np.abs(fine.decay_per_cycle_m - fine.coulomb_m)))
    print(f"reference: decay - 4 μd N / k at most {error:.2e} m (bound {fine.bound_m:.2e} m); "
          f"change on halving the step {change:.2e} m")
    assert error <= 2 * fine.bound_m + change, (error, fine.bound_m, change)
    fast = [run_oscillator("fast", dt) for dt in (1e-3, 5e-4)]
    fast_change = float(np.max(np.abs(fast[0].turns_m - fast[1].turns_m)))
    distance = float(np.max(np.abs(fast[1].turns_m - fine.turns_m)))
    print(f"fast: turning points {distance:.2e} m from the reference's at 0.5 ms, change "
          f"{fast_change:.2e} m from 1 ms")
    assert distance <= 1.5 * fast_change + change, (distance, fast_change)


def test_incline_reference_converges():
    """Two explicit steps on an incline: at 8° both hold the block at the creep's fixed point
    (the same to 1e-6 of it); at 14° both slide at g (sin θ - μd cos θ) (round-off) and their
    velocities after 0.3 s differ by less than a·dt, within the band transit's bound of a·t."""
    steps = (2e-5, 1e-5)
    stuck = [run_incline("reference", dt, 8.0) for dt in steps]
    np.testing.assert_allclose(stuck[0][0], stuck[1][0], rtol=1e-6)
    assert abs(stuck[1][0]) <= INCLINE_LAW.dmax_translation_m
    theta = math.radians(14.0)
    a = -incline_acceleration_mps2(incline_rad=theta, mu_d=INCLINE_LAW.mu_d)  # down
    slid = [run_incline("reference", dt, 14.0) for dt in steps]
    for _, _, slope in slid:
        np.testing.assert_allclose(slope, a, rtol=1e-6)
    assert abs(slid[0][1] - slid[1][1]) < abs(a) * steps[0]
    # The band transit: at most 1.5 Δv / (g (sin θ - μs cos θ)), with a friction between 0 and
    # μs N against Coulomb's μd N.
    transit = 1.5 * INCLINE_LAW.dv_translation_mps / (
        G * (math.sin(theta) - INCLINE_LAW.mu_s * math.cos(theta)))
    offset = G * math.cos(theta) * max(INCLINE_LAW.mu_d, INCLINE_LAW.mu_s - INCLINE_LAW.mu_d)
    assert abs(slid[1][1] - a * 0.3) <= offset * transit, (slid[1][1], a * 0.3)
