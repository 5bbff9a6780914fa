"""What the study's reader gets, on synthetic histories (``test_study``): the claims' deciding
numbers, their numerical error from a half-step study, the figures (each written, no legend
over data), the report (terms first, every verdict beside its threshold, peak and steady, an
error estimate on every deciding number, a figure linked to every claim) and the Diagram's
overview drawing."""

import json
import re
import shutil
import subprocess

import matplotlib.pyplot as plt
import numpy as np
import pytest

from drake_car.results.diagram import diagram_overview_dot
from drake_car.study.paper.figures import FIGURES, all_figures, legend_overlaps, place_windows
from drake_car.study.paper.measures import claim_measures
from drake_car.study.paper.claims import evaluate_claims, place_values
from drake_car.study.paper.measures import error_estimates, holds
from drake_car.study.paper.report import CLAIM_FIGURES, _flip, quantity, report, summary
from test_study import TIMELINE, study_of

VARIANTS = ({}, {"jammed_returns": True}, {"stays_put": True}, {"asymmetric_end": 0.002},
            {"rotation": 0.06}, {"mu1_peaks": 3})


class FakeRun:
    """What ``summary`` reads of a sim Run."""

    def record(self):
        return {"wall_s": 1.0, "real_time_factor": 10.0, "frozen_sap_steps": 0,
                "scene_hash": "0123456789abcdef"}


def made(study, half_study=None, figures=None):
    """summary and report of a synthetic study (with a half-step study, or without)."""
    claims, shifts = evaluate_claims(study, TIMELINE)
    half = None
    if half_study is not None:
        half_claims, _ = evaluate_claims(half_study, TIMELINE)
        half = {"time_step_s": {n: 5e-4 for n in study},
                "verdicts": [c["reproduced"] for c in half_claims],
                "numbers": [c["number"] for c in half_claims],
                "measures": claim_measures(half_study, TIMELINE)}
    s = summary(study, claims, shifts, TIMELINE, runs={n: FakeRun() for n in study},
                half=half, figures=dict(FIGURES) if figures is None else figures, wall_s=3.0,
                provenance={"command": "test", "git_commit": "0" * 40, "drake": "1.51",
                            "created_utc": "now"})
    return s, report(s)


def nudged(study, by=2e-5):
    """``study`` as if run at half the step: every rod position moved by ``by`` (m) late in
    the run on one side, so the numbers change a little."""
    for r in study.values():
        t = r.columns["t"]
        r.columns["dd_left_m"] = r.columns["dd_left_m"] + np.where(t > 9.0, by, 0.0)
        r.columns["rot_left_rad"] = r.columns["rot_left_rad"] * 1.001
    return study


@pytest.mark.parametrize("variant", VARIANTS)
def test_measures_decide_as_the_claims(variant):
    study = study_of(**variant)
    claims, _ = evaluate_claims(study, TIMELINE)
    measures = claim_measures(study, TIMELINE)
    assert len(measures) == len(claims)
    for claim, rows in zip(claims, measures):
        assert any(m["decides"] for m in rows)
        assert all(holds(m) for m in rows if m["decides"]) == claim["reproduced"], claim["claim"]


def test_place_windows_are_what_place_values_averages():
    h = study_of()["a_2"].columns
    windows = place_windows(h, TIMELINE)
    for (a, b), value in zip(windows.values(), place_values(h, TIMELINE, "dd_left_m")):
        inside = (h["t"] >= a) & ((h["t"] < b) if b < h["t"][-1] else (h["t"] <= b))
        assert np.mean(h["dd_left_m"][inside]) == pytest.approx(value)


def test_error_estimates_give_the_difference_and_extrapolate_where_the_order_is_known():
    measure = {"name": "x", "value": 1.0, "unit": "m", "relation": "<=", "threshold": 1.5,
               "runs": ["a_1"], "decides": True}
    count = dict(measure, unit="count", relation="==", threshold=2, value=0)
    half = [[dict(measure, value=0.9), dict(count, value=0)]]
    rows = error_estimates([[measure, count]], half, first_order_runs=["a_1"])[0]
    assert rows[0]["abs_diff"] == pytest.approx(0.1)
    assert rows[0]["order"] == 1 and rows[0]["extrapolated"] == pytest.approx(0.8)
    assert rows[0]["margin"] == pytest.approx(0.5) and rows[0]["holds_half"] is True
    assert rows[1]["extrapolated"] is None and rows[1]["abs_diff"] == 0
    other = error_estimates([[measure]], [[dict(measure, value=0.9)]], first_order_runs=[])
    assert other[0][0]["extrapolated"] is None  # with dry friction the order is not known
    assert error_estimates([[measure]])[0][0]["abs_diff"] is None  # no half-step study
    # A margin smaller than the error is said as such, not rounded to "0 × the error".
    within = error_estimates([[dict(measure, value=1.4)]], [[dict(measure, value=1.2)]],
                             first_order_runs=[])[0][0]
    assert _flip(within) == "**0.5 × the error** (within it)"


def test_quantities_are_written_in_the_readers_units():
    assert quantity(1e-4, "m") == "0.100 mm"
    assert quantity(2e-7, "m", error=True) == "< 0.001 mm"
    assert quantity(np.radians(3.0), "rad") == "3.00°"
    assert quantity(0.0123, "fraction") == "1.23 %"
    assert quantity(2, "count") == "2"


def test_every_figure_is_written_without_a_legend_over_data(tmp_path):
    study = study_of(asymmetric_end=0.001)
    written = all_figures(study, TIMELINE, tmp_path, half=nudged(study_of(asymmetric_end=0.001)))
    assert written == FIGURES
    for name in written:
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", name
    # Every claim links figures that are written.
    assert {f for figures in CLAIM_FIGURES.values() for f in figures} <= set(written)


def test_a_legend_over_data_is_found():
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1], label="data")
    ax.legend(loc="center")
    assert legend_overlaps(fig)
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0))
    assert not legend_overlaps(fig)
    plt.close(fig)


def test_report_defines_its_terms_first_and_gives_thresholds_errors_and_figures():
    study = study_of(jammed_returns=True, asymmetric_end=0.002)  # claims 1 and 3 fail
    s, text = made(study, nudged(study_of(jammed_returns=True, asymmetric_end=0.002)))
    json.loads(json.dumps(s, default=float))  # JSON-ready
    terms = text.index("## Sets and cases, and the terms used")
    claims = text.index("## The paper's claims")
    assert terms < claims
    for term in ("**set 1**", "**set 3**", "**case a**", "**case b**", "**phases**",
                 "**places a and b**", "**thresholds**", "**peak / steady**",
                 "**numerical error**"):
        assert term in text[terms:claims], term
    rows = [line for line in text[claims:].splitlines() if line.startswith("| ")][1:7]
    assert len(rows) == 6
    for i, row in enumerate(rows, start=1):
        cells = re.split(r" (?<!\\)\| ", row)
        assert len(cells) == 6, row
        assert "needs " in cells[3], row  # the verdict's number beside its threshold
        assert re.search(r"±|< |count", cells[4]), row  # its numerical error
        assert all(f"[{f}]({f})" in cells[5] for f in CLAIM_FIGURES[i]), row
    assert "(at dt/2: " in rows[0]
    # Load swings say whether they are peaks or steady changes.
    why = text[text.index("## Where the model disagrees"):]
    one = next(line for line in why.splitlines() if line.startswith("- **1."))
    assert " N steady " in one and " N at its peak" in one
    three = next(line for line in why.splitlines() if line.startswith("- **3."))
    assert "steady changes" in three
    # Every number behind a verdict with its error; a first-order one extrapolated.
    numbers = text[text.index("## Every number behind a verdict"):].split("\n## ")[0]
    table = [line for line in numbers.splitlines() if line.startswith("| ")][1:]
    assert len(table) == sum(len(rows) for rows in s["deciding_numbers"])
    assert all(len(re.split(r"(?<!\\)\|", line)) == 11 for line in table)  # 9 cells
    assert any("× the error" in line for line in table)
    extrapolated = [r for rows in s["deciding_numbers"] for r in rows if r["extrapolated"]]
    assert extrapolated and all(set(r["runs"]) <= {"a_1", "b_1"} for r in extrapolated)
    rotation = s["deciding_numbers"][4][0]
    assert rotation["abs_diff"] == pytest.approx(0.001 * rotation["value"], rel=1e-6)


def test_report_without_the_half_step_check_says_so():
    s, text = made(study_of())
    assert "not estimated (--no_verify)" in text
    assert all(r["abs_diff"] is None for rows in s["deciding_numbers"] for r in rows)


DOT = shutil.which("dot")


def test_overview_diagram_draws_the_plant_once_and_the_loggers_as_one_box():
    from pydrake.multibody.plant import AddMultibodyPlantSceneGraph
    from pydrake.systems.framework import DiagramBuilder
    from pydrake.systems.primitives import ConstantVectorSource, LogVectorOutput, Multiplexer
    builder = DiagramBuilder()
    plant, _ = AddMultibodyPlantSceneGraph(builder, time_step=1e-3)
    plant.Finalize()
    LogVectorOutput(plant.get_state_output_port(), builder)
    LogVectorOutput(plant.get_state_output_port(), builder)
    mux = builder.AddSystem(Multiplexer([1, 1]))
    for _ in range(2):
        builder.Connect(builder.AddSystem(ConstantVectorSource([0.0])).get_output_port(),
                        mux.get_input_port(mux.num_input_ports() - 1 - _))
    LogVectorOutput(mux.get_output_port(), builder)
    dot = builder.Build().GetGraphvizString(max_depth=1, options={"plant/split": "I/O"})
    overview = diagram_overview_dot(dot)
    assert overview.count("<B>MultibodyPlant</B>") == 1
    assert overview.count("<B>VectorLogSink</B>") == 1
    assert "<B>Multiplexer</B>" not in overview and "<B>ConstantVectorSource</B>" not in overview
    assert "rankdir=LR" in overview
    assert "WorldModelInstance" not in overview  # only wired ports
    if DOT is not None:
        svg = subprocess.run([DOT, "-Tsvg"], input=overview, capture_output=True, text=True,
                             check=True).stdout
        assert "<svg" in svg


def test_the_report_says_which_claims_changed_against_the_previous_car_and_why():
    from drake_car.study.paper.previous_car import PREVIOUS_CAR, previous_car_section
    now = [{"reproduced": PREVIOUS_CAR[i][0]} for i in range(1, 7)]
    now[0]["reproduced"] = True  # claim 1: no before, yes now (this car)
    now[2]["reproduced"] = True  # claim 3: a change no measurement explains
    rows = [line for line in previous_car_section({"claims": now}) if line.startswith("| ")]
    assert len(rows) == 1 + 6
    assert "pro-lift" in rows[1] and rows[1].count("|") == 6
    assert "not measured for this run's scenes" in rows[3]
    assert rows[2].endswith("| - |")  # claim 2 unchanged
