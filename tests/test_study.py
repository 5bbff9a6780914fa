"""The paper's study: the claim logic on synthetic histories with known verdicts, and a
shortened study end to end."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np

from drake_car.manoeuvre import Timeline
from drake_car.outputs import read_csv
from drake_car.study import (
    CASES, FRICTION_SETS, RUN_COLUMNS, count_reaching, evaluate_claims, run_name)

ROOT = Path(__file__).resolve().parents[1]
TIMELINE = Timeline()
LOADS = {"fl": 3800.0, "fr": 3800.0}


def synthetic(case, number, *, jammed_returns=False, asymmetric_end=0.0, rotation=0.02,
              mu1_peaks=2):
    """A history shaped like the paper's: rods move in phase I (set 3 stays put unless
    ``jammed_returns``), swing during the lane change (mirrored for case b) and end at a new
    position with friction."""
    t = np.arange(0.0, TIMELINE.duration_s + 1e-9, 0.01)
    t2, t3, t4, _ = TIMELINE.boundaries()
    sign = 1.0 if case == "a" else -1.0
    h = {c: np.zeros_like(t) for c in RUN_COLUMNS if c != "phase"}
    h["t"] = t
    h["phase"] = [TIMELINE.phase(x) for x in t]
    for side, s in (("left", 1.0), ("right", -1.0)):
        dd = np.where(t < TIMELINE.settle_s, 0.01 * t / TIMELINE.settle_s, 0.01)
        if number < 3 or jammed_returns:  # return movement late in phase I
            dd = np.where(t > t2, 0.0, dd)
        swing = np.sin(np.pi * np.clip((t - t3) / (t4 - t3), 0, 1) * 2) * 0.05 * s * sign
        end_offset = 0.0 if number == 1 else 0.004 * number
        if number > 1:
            end_offset += s * sign * asymmetric_end
        dd = dd + swing + np.where(t >= t4, end_offset, 0.0)
        h[f"dd_{side}_m"] = dd
        h[f"rot_{side}_rad"] = rotation * np.sin(t)
        mu1 = np.zeros_like(t)
        for k in range(mu1_peaks):
            mu1[100 + 200 * k: 120 + 200 * k] = FRICTION_SETS[2][0]
        h[f"mu1_{side}"] = mu1
        h[f"N_{side}_N"] = np.full_like(t, 1500.0)
    h["Fz_fl_N"] = 3800 + 10000 * (h["dd_left_m"] - h["dd_right_m"])
    h["Fz_fr_N"] = 3800 - 10000 * (h["dd_left_m"] - h["dd_right_m"])
    return h


def claims_for(**kwargs):
    runs = {run_name(c, n): synthetic(c, n, **kwargs) for c in CASES for n in FRICTION_SETS}
    claims, _ = evaluate_claims(runs, TIMELINE, LOADS)
    return [c["reproduced"] for c in claims], claims


def test_paper_like_histories_reproduce_every_claim():
    verdicts, claims = claims_for()
    assert verdicts == [True] * 6, [c["number"] for c in claims]


def test_each_claim_can_fail():
    assert claims_for(jammed_returns=True)[0][0] is False
    assert claims_for(asymmetric_end=0.002)[0][2] is False  # 4 mm left-right at b: 40 N
    assert claims_for(rotation=0.06)[0][4] is False  # 3.4 deg
    assert claims_for(mu1_peaks=3)[0][5] is False


def test_symmetry_claim_fails_for_an_asymmetric_car():
    runs = {run_name(c, n): synthetic(c, n) for c in CASES for n in FRICTION_SETS}
    runs["b_2"]["dd_right_m"] = runs["b_2"]["dd_right_m"] + 0.01
    claims, _ = evaluate_claims(runs, TIMELINE, LOADS)
    assert claims[3]["reproduced"] is False


def test_count_reaching():
    assert count_reaching([0, 0.2, 0.2, 0.1, 0.2, 0.0], 0.2) == 2
    assert count_reaching([0.2, 0.2, 0.0], 0.2) == 1
    assert count_reaching([0.0, 0.19999], 0.2) == 0


def test_shortened_study_end_to_end(tmp_path):
    out = tmp_path / "study"
    result = subprocess.run(
        [sys.executable, str(ROOT / "experiments" / "lane_change.py"), "--out", str(out),
         "--scale_time", "0.15", "--no_verify", "--no_html", "--jobs", "2"],
        capture_output=True, text=True, timeout=900)
    assert result.returncode == 0, result.stderr[-3000:]
    assert "lane-change study: 6/6" in result.stderr
    for case in CASES:
        for number in FRICTION_SETS:
            h = read_csv(out / f"{case}_{number}.csv")
            assert list(h) == list(RUN_COLUMNS)
            for name, values in h.items():
                if name != "phase":
                    assert np.all(np.isfinite(values)), (case, number, name)
            assert set(h["phase"]) == {"I", "II", "III", "IV"}
            assert list(dict.fromkeys(h["phase"])) == ["I", "II", "III", "IV"]
            scene = json.loads((out / f"{case}_{number}.scene.json").read_text())
            assert scene["friction_set"] == number
    for name in ("fig13.png", "fig14_a.png", "fig14_b.png", "fig15_a.png", "fig15_b.png",
                 "fig16.png", "wheel_loads.png", "diagram.svg", "report.md"):
        assert (out / name).stat().st_size > 0, name
    summary = json.loads((out / "summary.json").read_text())
    assert len(summary["claims"]) == 6
    assert all(isinstance(c["reproduced"], bool) for c in summary["claims"])
    assert set(summary["rod_positions"]) == {f"{c}_{n}" for c in CASES for n in FRICTION_SETS}
    assert "## The paper's claims" in (out / "report.md").read_text()
