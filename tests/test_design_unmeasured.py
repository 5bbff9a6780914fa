"""The design study's report where a value was not measured (a hands-off run that ended before
the pull distance, a run that failed) and where a test cannot conclude: it says "not measured
(why)" and draws no conclusion from the missing values; no numpy warning. Built from report
inputs made here (the rows of the table as ``analysis.table`` gives them), no simulation."""

import math
import warnings

import pytest

from drake_car.data import resource
from drake_car.study.design import analysis, answers, figures, report, tables
from drake_car.study.design import smoke as design_smoke
from drake_car.study.design.runs import mitigation_baseline
from drake_car.study.design.spec import OUTCOMES, load_study
from drake_car.study.design.unmeasured import why

STUDY, CHANGES = design_smoke.quick(load_study(resource("scenes/studies/design.yaml"), "study"))
SLOW_KPH = 7.1  # the 1900 kg SUV of the review reached this in --quick's 0.6 s speed-up


def _row(name, role, pull=math.nan, split=0.05, status="ok", **extra):
    row = {"name": name, "role": role, "status": status, "hash": name, "step_s": 1e-3,
           "sample": "", "mitigation": "", "line": "", "of": ""}
    row |= {k: 0.0 for k in OUTCOMES} | {"split_change_rel": split, "pull_deg": pull,
                                          "split_change_N": 4000.0 * split,
                                          "speed_a_kph": SLOW_KPH, "speed_asked_kph": 60.0}
    # The errors as jam_cases.apply gives the runs not refined (the noise sample's).
    row |= {"split_change_rel_error": 1e-4, "split_change_rel_converged": "-",
            "pull_deg_error": 0.001 if math.isfinite(pull) else math.nan,
            "pull_deg_converged": "-"}
    if status != "ok":
        row |= {k: math.nan for k in OUTCOMES}
    return row | extra


def _table(pull=math.nan, mitigation_states=2):
    """Every part of the smoke study's table, every hands-off pull ``pull``."""
    rows = []
    for i, spec in enumerate(STUDY.maps):
        rows += [_row(f"map{i}_{k:03d}", "map", pull, 0.02 + 0.01 * k)
                 for k in range(spec.points ** 2)]
    for i, line in enumerate(STUDY.lines):
        rows += [_row(f"line{i}_mu{j}_{k:02d}", "line", pull, 0.05 + 0.01 * k, line=line.key)
                 for j in range(len(STUDY.line_mu_s)) for k in range(len(line.values))]
    rows += [_row(f"sobol_{k:04d}", "sobol", split=0.05 + 0.003 * k % 0.02,
                  rack_force_change_N=float(k * k % 5))
             for k in range(STUDY.sobol_base_samples * (len(STUDY.factors) + 2))]
    rows += [_row(f"mc_{k:04d}", "mc", pull, sample=k) for k in range(4)]
    groups = [mitigation_baseline(STUDY)] + [m.name for m in STUDY.mitigations]
    for j, group in enumerate(groups):
        rows += [_row(f"mitigation{j}_{k:04d}", "mitigation", pull,
                      0.08 - 0.01 * j - 0.001 * k, sample=k, mitigation=group)
                 for k in range(mitigation_states)]
    rows += [_row("noise_map0_000", "noise", pull, 0.0201, of="map0_000"),
             _row("noise_sobol_0000", "noise", of="sobol_0000")]
    return rows


def _answers(rows):
    noise = tables.noise_levels(rows)
    jam = tables.group_summary("jam states", [r for r in rows if r["role"] == "mc"], STUDY)
    mitigations = tables.mitigation_table(STUDY, rows, mitigation_baseline(STUDY))
    lines = tables.line_tables(STUDY, [r for r in rows if r["role"] == "line"])
    return answers.answers(STUDY, rows, None, jam, mitigations, noise, lines)


def test_the_why_names_the_runs_that_ended_before_the_pull_distance_and_their_speed():
    rows = _table()
    text = why(STUDY, [r for r in rows if r["role"] == "mc"], "pull_deg")
    assert text == ("the runs ended before 2 m hands off, their length set for 60 km/h and "
                    "their speed 7.1 km/h")
    mixed = [_row("a", "map", 0.1), _row("b", "map", status="failed"), _row("c", "map")]
    assert why(STUDY, mixed, "pull_deg") == ("1 of 3 runs ended before 2 m hands off, their "
                                             "length set for 60 km/h and their speed 7.1 km/h; "
                                             "1 of 3 runs did not finish")
    assert why(STUDY, mixed[:1], "pull_deg") is None


def test_answers_never_print_nan_nor_conclude_from_a_pull_not_measured():
    text = "\n".join(_answers(_table()))
    assert "nan" not in text.lower(), text
    assert "nowhere in the range" not in text.split("The lasting split")[0]
    for i in range(len(STUDY.maps)):
        assert f"The pull over {answers.factor(STUDY, STUDY.maps[i].x).label}" in text
    assert text.count("not measured (the runs ended before 2 m hands off") >= 5, text
    assert "the pull not measured (the runs ended" in text  # the jam states
    assert "(baseline (μs 0.4): split median 7.95 %, pull not measured (the runs ended" in text
    assert "the pull not measured (no half-step pair has it" in text


def test_a_map_row_with_a_cell_not_measured_draws_no_boundary_through_it():
    spec = STUDY.maps[0]
    rows = [_row("map0_000", "map", 0.1), _row("map0_001", "map"),  # y0: 0.1, not measured
            _row("map0_002", "map", 0.1), _row("map0_003", "map", 0.2)]
    text = answers.boundary_lines(STUDY, spec, rows, "pull_deg", 1.0, 0.5, "The pull")
    fx, xs = answers.factor(STUDY, spec.x), tables.map_grid(STUDY, spec, rows, "pull_deg")[0]
    assert (f"nowhere among the measured cells (not measured at {fx.label} = {xs[1]:.3g})"
            in text), text
    assert text.count("nowhere in the range") == 1  # the row measured throughout
    assert "Cells not measured: 1 of 4 runs ended before 2 m hands off" in text


def test_a_sign_test_over_too_few_states_is_said_not_to_conclude():
    # Every mitigation lower in both of 2 states, beyond the errors: the sign test's smallest p
    # over 2 states is 0.5, so it cannot say "lower", nor "none is lower".
    rows = _table(pull=0.01)
    (text,) = [a for a in _answers(rows) if a.startswith("Mitigations")]
    assert "lower beyond the runs' errors in 100 % of the states: 2 of 2" in text
    assert "Lower than the baseline: none" not in text and "None lowers" not in text
    assert ("No mitigation is judged lower or higher than the baseline: over 2 states a sign "
            "test at 5 % cannot conclude (even all 2 states one way give p = 0.50; it needs 6 "
            "states or more)") in text
    assert answers.SIGN_TEST_STATES == 6 and 2 / 2 ** 6 < 0.05 <= 2 / 2 ** 5
    (six,) = [a for a in _answers(_table(pull=0.01, mitigation_states=6))
              if a.startswith("Mitigations")]
    assert "cannot conclude" not in six and "Lower than the baseline: " in six
    assert "Lower than the baseline: none" not in six
    # One group a state short (a run failed): it alone is not judged, and said so.
    rows = _table(pull=0.01, mitigation_states=6)
    short = next(r for r in rows if r["name"] == "mitigation1_0005")
    short |= _row(short["name"], "mitigation", status="failed", sample=5,
                  mitigation=short["mitigation"])
    (text,) = [a for a in _answers(rows) if a.startswith("Mitigations")]
    assert (f"Not judged against the baseline (over 5 states a sign test at 5 % cannot "
            f"conclude (even all 5 states one way give p = 0.06; it needs 6 states or more)): "
            f"{short['mitigation']}.") in text, text
    assert "Lower than the baseline: " in text


def test_a_heat_map_of_values_not_measured_draws_without_numpy_warnings(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # numpy's
        figures.heat_map([0.05, 0.5], [0.04, 0.11], [[math.nan] * 2] * 2, x_label="μs",
                         y_label="b", paper=(0.2, 0.06), threshold=0.5, title="pull",
                         path=tmp_path / "all.png", noise=[[math.nan] * 2] * 2,
                         missing="the runs ended before 2 m hands off")
        figures.heat_map([0.05, 0.5], [0.04, 0.11], [[0.1, math.nan], [0.2, 0.9]],
                         x_label="μs", y_label="b", paper=(0.2, 0.06), threshold=0.5,
                         title="pull", path=tmp_path / "some.png")
    assert (tmp_path / "all.png").stat().st_size > 0 and (tmp_path / "some.png").stat().st_size


def test_the_report_of_a_study_without_a_pull_says_not_measured_everywhere(tmp_path,
                                                                          monkeypatch):
    monkeypatch.setattr(analysis, "provenance", lambda: {
        "command": "drake-car-design --quick", "git_commit": "0" * 40,
        "created_utc": "now", "dirty": False})
    rows = _table()
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # numpy's
        s = analysis.analyse(STUDY, rows, tmp_path, {"reused": 0, "wall_s": 1.0}, 2.0,
                             tables.noise_levels(rows), smoke=CHANGES)
    text = report.report(s, "study/")
    assert "nan" not in text.lower().replace("nano", ""), [
        line for line in text.splitlines() if "nan" in line.lower()]
    assert "hands off [deg] over μs × ball-joint offset b [m]: not measured (the runs ended " \
        "before 2 m hands off" in text  # the maps' captions
    assert "n/a: the pull not measured (the runs ended before 2 m" in text
    assert "n/a: not measured (the runs ended before 2 m hands off" in text  # the lines
    assert "- pull_deg: not measured (no half-step pair has it" in text


@pytest.mark.parametrize("pull", [0.01])
def test_a_measured_pull_reads_as_before(pull):
    text = "\n".join(_answers(_table(pull=pull)))
    assert "not measured" not in text and "nan" not in text.lower()
    assert "the pull is 0.01 deg (median)" in text


def test_a_crossing_across_a_cell_not_measured_is_said_to_lie_between_its_neighbours():
    # A row of three cells, the middle not measured, the threshold crossed between the two
    # measured ones: the crossing is not drawn at an interpolated x inside the gap.
    import dataclasses
    spec = dataclasses.replace(STUDY.maps[0], points=3)
    study = dataclasses.replace(STUDY, maps=[spec])
    pulls = [0.1, math.nan, 0.9] + [0.1, 0.2, 0.3] * 2
    rows = [_row(f"map0_{k:03d}", "map", p) for k, p in enumerate(pulls)]
    text = answers.boundary_lines(study, spec, rows, "pull_deg", 1.0, 0.5, "The pull")
    fx, xs = answers.factor(study, spec.x), tables.map_grid(study, spec, rows, "pull_deg")[0]
    assert f"{fx.label} between {xs[0]:.3g} and {xs[2]:.3g} (not measured between)" in text, text
    assert "≈" not in text.split(";")[0]
