"""What the study's reader gets, on synthetic histories (``test_study``): the claims' deciding
numbers, their numerical error from the same runs at finer steps (``outcomes.csv``), the figures (each written, no legend
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
from drake_car.study.paper.claims import evaluate_claims, place_values
from drake_car.study.paper.measures import claim_measures, holds
from drake_car.study.paper.outcomes import (
    at_one_step, read_outcomes, study_outcomes, write_outcomes)
from drake_car.study.paper.report import CLAIM_FIGURES, flip, quantity, report, summary
from conftest import paper_scene
from test_refine import _table
from test_study import TIMELINE, study_of

VARIANTS = ({}, {"jammed_returns": True}, {"stays_put": True}, {"asymmetric_end": 0.002},
            {"rotation": 0.06}, {"mu1_peaks": 3})


class FakeRun:
    """What ``summary`` reads of a sim Run: its record and its scene (the shipped study's run
    of the same name, or ``scene``)."""

    def __init__(self, name, scene=None):
        self.scene = scene or paper_scene(name)

    def record(self):
        return {"wall_s": 1.0, "real_time_factor": 10.0, "frozen_sap_steps": 0,
                "scene_hash": "0123456789abcdef"}


def roles_of(study):
    return {n: (r.case, r.friction) for n, r in study.items()}


def values_of(study):
    return study_outcomes({n: r.columns for n, r in study.items()}, roles_of(study), TIMELINE)


def made(study, finer=(), figures=None, tmp_path=None):
    """summary and report of a synthetic study: its outcomes at the step, and at finer steps
    from the studies ``finer`` (as accuracy on demand would give them), through outcomes.csv
    when ``tmp_path`` is given; at one step only without ``finer``."""
    claims, shifts = evaluate_claims(study, TIMELINE)
    levels = [values_of(study)] + [values_of(f) for f in finer]
    table = _table(levels) if finer else at_one_step(levels[0], 1e-3)
    if tmp_path is not None:
        write_outcomes(tmp_path / "outcomes.csv", table)
        table = read_outcomes(tmp_path / "outcomes.csv")
    refinement = {"rounds": [], "wall_s": 12.0, "stopped": "every outcome converged",
                  "finest_step_s": 2.5e-4} if finer else None
    s = summary(study, claims, shifts, TIMELINE, runs={n: FakeRun(n) for n in study},
                outcomes=table, refinement=refinement,
                figures=dict(FIGURES) if figures is None else figures, wall_s=3.0,
                provenance={"command": "test", "git_commit": "0" * 40, "drake": "1.51",
                            "created_utc": "now"})
    return s, report(s)


def nudged(study, by=2e-5, factor=1.001):
    """``study`` as if run at a finer step: every rod position moved by ``by`` (m) late in
    the run on one side, the rotation scaled by ``factor``, so the numbers change a little."""
    for r in study.values():
        t = r.columns["t"]
        r.columns["dd_left_m"] = r.columns["dd_left_m"] + np.where(t > 9.0, by, 0.0)
        r.columns["rot_left_rad"] = r.columns["rot_left_rad"] * factor
    return study


def converging(**variant):
    """The study at h/2 and h/4, converging at first order (differences halve)."""
    return (nudged(study_of(**variant), 2e-5, 1.001), nudged(study_of(**variant), 3e-5, 1.0015))


@pytest.mark.parametrize("variant", VARIANTS)
def test_measures_decide_as_the_claims(variant):
    study = study_of(**variant)
    claims, _ = evaluate_claims(study, TIMELINE)
    measures = claim_measures(at_one_step(values_of(study)), roles_of(study))
    assert len(measures) == len(claims)
    for claim, rows in zip(claims, measures):
        assert any(m["decides"] for m in rows)
        assert all(holds(m) for m in rows if m["decides"]) == claim["reproduced"], claim["claim"]


def test_claim_two_carries_what_the_car_does_between_the_places_without_friction():
    # Its context row: set 1's largest |Δd(b) - Δd(a)|, from its rods' place values.
    study = study_of()
    table = at_one_step(values_of(study))
    two = claim_measures(table, roles_of(study))[1]
    alone = [m for m in two if m["name"].startswith("the same without dry friction")]
    assert len(alone) == 1 and not alone[0]["decides"]
    expected = max(abs(table[(n, f"dd_{s}_b_m")]["value"] - table[(n, f"dd_{s}_a_m")]["value"])
                   for n in ("a_1", "b_1") for s in ("left", "right"))
    assert alone[0]["value"] == pytest.approx(expected)


def test_place_windows_are_what_place_values_averages():
    h = study_of()["a_2"].columns
    windows = place_windows(h, TIMELINE)
    for (a, b), value in zip(windows.values(), place_values(h, TIMELINE, "dd_left_m")):
        inside = (h["t"] >= a) & ((h["t"] < b) if b < h["t"][-1] else (h["t"] <= b))
        assert np.mean(h["dd_left_m"][inside]) == pytest.approx(value)


def test_a_margin_within_the_error_is_said_as_such():
    row = {"margin": 0.2, "error": 0.4, "converged": True, "unit": "m"}
    assert flip(row) == "**0.5 × the error** (within it)"
    assert flip(dict(row, error=0.01)) == "20 × the error"
    assert flip(dict(row, converged=False)) == "**not converged**"


def test_quantities_are_written_in_the_readers_units():
    assert quantity(1e-4, "m") == "0.100 mm"
    assert quantity(2e-7, "m", error=True) == "< 0.001 mm"
    assert quantity(np.radians(3.0), "rad") == "3.00°"
    assert quantity(0.0123, "fraction") == "1.23 %"
    assert quantity(2, "count") == "2"


def test_every_figure_is_written_without_a_legend_over_data(tmp_path):
    study = study_of(asymmetric_end=0.001)
    table = _table([values_of(study)] + [values_of(f) for f in converging(asymmetric_end=0.001)])
    written = all_figures(study, TIMELINE, tmp_path, outcomes=table)
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


def test_report_defines_its_terms_first_and_gives_thresholds_errors_and_figures(tmp_path):
    variant = {"jammed_returns": True, "asymmetric_end": 0.002}  # claims 1 and 3 fail
    s, text = made(study_of(**variant), converging(**variant), tmp_path=tmp_path)
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
        assert re.search(r"±|< |converged", cells[4]), row  # its numerical error
        assert all(f"[{f}]({f})" in cells[5] for f in CLAIM_FIGURES[i]), row
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
    assert all(len(re.split(r"(?<!\\)\|", line)) == 10 for line in table)  # 8 cells
    assert any("× the error" in line for line in table)
    # The rotation converges at first order: its error is the same runs' last difference.
    rotation = s["deciding_numbers"][4][0]
    assert rotation["converged"] is True
    assert rotation["error"] == pytest.approx(0.0005 / 1.0015 * rotation["value"], rel=1e-6)
    assert rotation["values"] == pytest.approx(
        [rotation["value"] / 1.0015 * f for f in (1, 1.001, 1.0015)])


def test_an_undecided_claim_says_so_with_the_finest_step_and_the_values():
    # Claim 3's rods: 4 mm left-right at a 0.1 mm threshold, but 0.04 mm at the step between:
    # not converged, and its spread straddles the threshold, so undecided, with every step's
    # value. (Values that jump but stay on one side by more than their spread decide it:
    # tests/test_refine.py.)
    variant = {"asymmetric_end": 0.002}
    finer = (study_of(asymmetric_end=0.00002), study_of(asymmetric_end=0.002))
    s, text = made(study_of(**variant), finer)
    assert s["claims"][2]["decided"] is False
    row = next(line for line in text.splitlines() if line.startswith("| 3 |"))
    assert "undecided at the finest step tried (0.25 ms, 12 s of wall)" in row
    assert "not converged: " in row and " at 0.5 ms" in row


def test_report_without_the_half_step_check_says_so():
    s, text = made(study_of())
    assert "not estimated (--no_verify" in text
    assert all(r["error"] is None for rows in s["deciding_numbers"] for r in rows)


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
    rows = [line for line in previous_car_section({"claims": now, "paper_car": True})
            if line.startswith("| ")]
    assert len(rows) == 1 + 6
    assert "pro-lift" in rows[1] and rows[1].count("|") == 6
    assert "not measured for this run's scenes" in rows[3]
    assert rows[2].endswith("| - |")  # claim 2 unchanged
