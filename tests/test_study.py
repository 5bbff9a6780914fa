"""The paper's study: the claim logic on synthetic histories with known verdicts, and a
shortened study end to end."""

import numpy as np

from drake_car.scene.manoeuvres import Timeline
from drake_car.study.paper.claims import (
    CASES, RUN_COLUMNS, FrictionSet, StudyRun, count_reaching, evaluate_claims)

TIMELINE = Timeline()
SETS = {1: FrictionSet(1, 0.0, 0.0, 1250.0), 2: FrictionSet(2, 0.2, 0.15, 0.0),
        3: FrictionSet(3, 0.4, 0.3, 0.0)}
LOAD_N = 3800.0


def synthetic(case, number, *, jammed_returns=False, asymmetric_end=0.0, rotation=0.02,
              mu1_peaks=2, stays_put=False):
    """A history shaped like the paper's: rods move in phase I (set 3 stays put unless
    ``jammed_returns``), swing during the lane change (mirrored for case b) and end at a new
    position with friction (at the old one with ``stays_put``)."""
    t = np.arange(0.0, TIMELINE.duration_s + 1e-9, 0.01)
    t2, t3, t4, _ = TIMELINE.boundaries()
    sign = 1.0 if case == "a" else -1.0
    h = {c: np.zeros_like(t) for c in RUN_COLUMNS if c != "phase"}
    h["t"] = t
    h["phase"] = [TIMELINE.phase(x) for x in t]
    h["speed_mps"] = np.interp(t, [TIMELINE.settle_s, t2], [0.0, TIMELINE.speed_mps])
    for side, s in (("left", 1.0), ("right", -1.0)):
        dd = np.where(t < TIMELINE.settle_s, 0.01 * t / TIMELINE.settle_s, 0.01)
        if number < 3 or jammed_returns:  # return movement late in phase I
            dd = np.where(t > t2, 0.0, dd)
        swing = np.sin(np.pi * np.clip((t - t3) / (t4 - t3), 0, 1) * 2) * 0.05 * s * sign
        end_offset = 0.0 if (number == 1 or stays_put) else 0.004 * number
        if number > 1:
            end_offset += s * sign * asymmetric_end
        dd = dd + swing + np.where(t >= t4, end_offset, 0.0)
        h[f"dd_{side}_m"] = dd
        h[f"rot_{side}_rad"] = rotation * np.sin(t)
        mu1 = np.zeros_like(t)
        for k in range(mu1_peaks):
            mu1[100 + 200 * k: 120 + 200 * k] = SETS[2].mu_s
        h[f"mu1_{side}"] = mu1
        h[f"N_{side}_N"] = np.full_like(t, 1500.0)
    h["Fz_fl_N"] = LOAD_N + 10000 * (h["dd_left_m"] - h["dd_right_m"])
    h["Fz_fr_N"] = LOAD_N - 10000 * (h["dd_left_m"] - h["dd_right_m"])
    return h


def study_of(**kwargs):
    return {f"{c}_{n}": StudyRun(f"{c}_{n}", c, SETS[n], synthetic(c, n, **kwargs))
            for c in CASES for n in SETS}


def claims_for(**kwargs):
    claims, _ = evaluate_claims(study_of(**kwargs), TIMELINE)
    return [c["reproduced"] for c in claims], claims


def test_paper_like_histories_reproduce_every_claim():
    verdicts, claims = claims_for()
    assert verdicts == [True] * 6, [c["number"] for c in claims]


def test_each_claim_can_fail():
    assert claims_for(jammed_returns=True)[0][0] is False
    assert claims_for(stays_put=True)[0][1] is False  # the rods return to place a
    assert claims_for(asymmetric_end=0.002)[0][2] is False  # 4 mm left-right at b: 40 N
    assert claims_for(rotation=0.06)[0][4] is False  # 3.4 deg
    assert claims_for(mu1_peaks=3)[0][5] is False


def test_symmetry_claim_fails_for_an_asymmetric_car():
    study = study_of()
    study["b_2"].columns["dd_right_m"] = study["b_2"].columns["dd_right_m"] + 0.01
    claims, _ = evaluate_claims(study, TIMELINE)
    assert claims[3]["reproduced"] is False


def test_labels_come_from_the_sets():
    _, claims = claims_for()
    assert "μs = 0.4, μd = 0.3" in claims[0]["claim"]
    assert "μs = 0.2, μd = 0.15" in claims[5]["claim"]


def test_count_reaching():
    assert count_reaching([0, 0.2, 0.2, 0.1, 0.2, 0.0], 0.2) == 2
    assert count_reaching([0.2, 0.2, 0.0], 0.2) == 1
    assert count_reaching([0.0, 0.19999], 0.2) == 0
