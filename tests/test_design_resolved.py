"""The design study's default accuracy on demand, the local route (``study.design.resolved_runs``):
which runs resolve their events (the jam cases, Sobol's included), which speak for the others
(the noise sample, drawn from the runs at the study's step), and how each row says what made
its error and what it cost. The whole route on --quick: tests/test_design.py."""

import dataclasses
import math

import pytest

from drake_car.data import resource
from drake_car.scene.load import scene_hash
from drake_car.study.design import jam_cases
from drake_car.study.design import resolved_runs
from drake_car.study.design import runs as design_runs
from drake_car.study.design import smoke as design_smoke
from drake_car.study.design.spec import load_study

STUDY = load_study(resource("scenes/studies/design.yaml"), "study")


def _parts(study):
    return {"map": {n: (design_runs.hands_off(study, s), v)
                    for n, (s, v) in design_runs.map_scenes(study).items()},
            "line": design_runs.line_scenes(study), "sobol": design_runs.sobol_scenes(study),
            "mc": design_runs.monte_carlo_scenes(study),
            "mitigation": design_runs.mitigation_scenes(study)}


def test_the_jam_cases_sobol_s_included_resolve_their_events_and_no_other_run_does():
    study = design_smoke.quick(STUDY)[0]
    parts = _parts(study)
    jam = jam_cases.jam_scenes(study, parts)
    # Sobol's sample is a refined part by default (issue 32: its jam points were not refined).
    assert "sobol" in study.accuracy.parts
    expected = {n for role in ("map", "line", "sobol", "mitigation")
                for n, (s, _) in parts[role].items() if s.friction.law.mu_s >= 0.3}
    assert any(n.startswith("sobol_") for n in expected)
    assert set(jam) == expected
    resolved = resolved_runs.resolving_parts(study, parts, set(jam))
    for role, part in parts.items():
        for name, (scene, _) in part.items():
            events = resolved[role][name][0].simulator.resolve_events
            if name in jam:
                assert events == resolved_runs.resolve_events(study)
                assert events.finest_step_s == study.accuracy.finest_step_s
            else:  # the same scene, so the same run (hash) as without accuracy on demand
                assert events is None
                assert scene_hash(resolved[role][name][0]) == scene_hash(scene)
    # μs 0 down to the jam μs: every dry run of the parts resolves.
    every = dataclasses.replace(study, accuracy=dataclasses.replace(study.accuracy,
                                                                    jam_mu_s=1e-9))
    assert set(jam_cases.jam_scenes(every, parts)) == {
        n for role in study.accuracy.parts for n in parts[role]}


def _row(name, **values):
    row = {"name": name, "role": name.split("_")[0].rstrip("0123456789"), "hash": name, "status": "ok",
           "step_s": 1e-3, "split_change_rel": -0.05, "pull_deg": 0.2, "windows": 0,
           "windows_resolved": 0, "window_finest_step_s": math.nan, "resolution_cpu_s": math.nan,
           "run_cpu_s": 4.0, **{f"rest_error_{s}_{p}_m": math.nan for s in ("left", "right")
                                for p in "ab"},
           "dd_left_a_m": -0.010, "dd_right_a_m": -0.010, "dd_left_b_m": -0.012,
           "dd_right_b_m": -0.008}
    return row | values


def test_a_resolved_row_carries_its_windows_error_and_says_what_they_do_not_cover():
    study = STUDY
    noise = {"split_change_rel": 4e-4, "pull_deg": 0.004}
    windows = _row("map0_001", windows=2, windows_resolved=2, window_finest_step_s=1.25e-4,
                   resolution_cpu_s=6.0, rest_error_left_a_m=1e-6, rest_error_left_b_m=3e-6,
                   rest_error_right_a_m=1e-6, rest_error_right_b_m=3e-6)
    open_window = _row("map0_003", windows=2, windows_resolved=1, window_finest_step_s=1.25e-4,
                       resolution_cpu_s=9.0, **{f"rest_error_{s}_{p}_m": 1e-6
                                                for s in ("left", "right") for p in "ab"})
    none = _row("mitigation0_0000")
    other = _row("mc_0000")
    rows = [windows, open_window, none, other]
    resolved_runs.apply(rows, study, noise, {"map0_001", "map0_003", "mitigation0_0000"})
    # The left-right change of the rest positions from a to b: (-0.012 + 0.008) - 0 = -4 mm;
    # the split per change 0.05 / 4 mm; the change errs by both struts' errors at a and b (8 µm).
    assert windows["split_change_rel_error"] == pytest.approx(0.05 / 0.004 * 8e-6)
    assert windows["split_change_rel_error_from"] == "windows"
    assert windows["split_change_rel_converged"] == "yes"  # 1e-4 <= the 1e-3 tolerance
    assert windows["split_change_rel_step_s"] == 1.25e-4
    assert windows["resolved_by"] == "windows"
    # A window that did not resolve at the finest step leaves the split open, however small
    # its last change.
    assert open_window["split_change_rel_converged"] == "no"
    # What the windows do not cover keeps the noise sample's level, and says so.
    assert windows["pull_deg_error"] == 0.004
    assert windows["pull_deg_error_from"] == "noise sample (not carried from the windows)"
    assert none["resolved_by"] == "windows" and none["split_change_rel_error"] == 4e-4
    assert none["split_change_rel_error_from"] == "noise sample (no window opened)"
    assert none["split_change_rel_converged"] == "-"
    assert other["resolved_by"] == "-" and other["split_change_rel_error_from"] == "noise sample"
    # A tolerance the windows' error exceeds is not converged.
    tight = dataclasses.replace(study, accuracy=dataclasses.replace(study.accuracy,
                                                                    split_tolerance=5e-5))
    again = resolved_runs.apply([dict(windows)], tight, noise, {"map0_001"})[0]
    assert again["split_change_rel_converged"] == "no"
    # A window whose branch its twins found unsettled (sim.twins: an infinite rest error)
    # leaves the split's error unknown, not the noise sample's, and the report says so.
    unknown = resolved_runs.apply([dict(windows, rest_error_left_b_m=math.inf)], study, noise,
                                  {"map0_001"})[0]
    assert unknown["split_change_rel_error"] == math.inf
    assert unknown["split_change_rel_error_from"] == "windows"
    assert unknown["split_change_rel_converged"] == "no"
    assert resolved_runs._error(math.inf).startswith("error unknown")


def test_the_route_s_summary_counts_equal_runs_once_and_says_what_the_windows_cost():
    rows = [_row("map0_001", windows=1, windows_resolved=1, window_finest_step_s=2.5e-4,
                 resolution_cpu_s=3.0, run_cpu_s=7.0),
            _row("mitigation0_0000", run_cpu_s=5.0),
            _row("mc_0000", run_cpu_s=4.0),
            _row("mitigation1_0000", hash="mc_0000", run_cpu_s=4.0)]  # the MC's run
    resolved = {"map0_001", "mitigation0_0000"}
    resolved_runs.apply(rows, STUDY, {"split_change_rel": 4e-4, "pull_deg": 0.004}, resolved)
    s = resolved_runs.summary(rows, STUDY, resolved)
    assert s["runs"] == 2 and s["no_window"] == ["mitigation0_0000"]
    assert s["totals"] == {"run_cpu_s": 16.0, "resolution_cpu_s": 3.0}
    assert s["by_part"]["mitigation"]["runs"] == 2  # both rows, one of them the MC's run
    assert s["by_part"]["mitigation"]["run_cpu_s"] == 5.0
    assert s["by_part"]["map"]["finest_step_s"] == 2.5e-4
    text = "\n".join(resolved_runs.report_lines(s))
    assert "took 3 s of CPU, 19 % of the 16 s" in text
    assert "opened no window" in text and "mitigation0_0000" in text


def test_a_rest_position_carries_the_windows_before_its_place_and_none_after_the_release():
    @dataclasses.dataclass
    class Run:  # what resolution_fields reads of a Run
        scene: object
        resolution: dict
        cpu_s: float = 5.0
    study = design_smoke.quick(STUDY)[0]
    scene = design_runs.hands_off(study, study.base)
    a_end, b_end = resolved_runs.place_ends_s(scene)
    assert a_end == scene.manoeuvre.timeline.boundaries()[1] < b_end == scene.steering.release_s
    assert b_end < scene.manoeuvre.timeline.duration_s  # the pull is taken after place b

    def window(start, end, left, right):
        return {"start_s": start, "end_s": end, "resolved": True, "step_s": 2.5e-4,
                "position_errors": {"left_translation": left, "right_translation": right}}
    windows = [window(0.0, a_end - 0.2, 1e-6, 2e-6),  # the speed-up: places a and b
               window(a_end + 0.1, b_end - 0.3, 4e-6, 8e-6),  # the lane change: b only
               window(b_end + 0.1, b_end + 0.3, 1.0, 1.0)]  # hands off: neither
    run = Run(scene, {"window_count": 3, "windows": windows, "finest_step_s": 2.5e-4,
                      "window_steps": 100, "cpu_s": 2.0})
    f = resolved_runs.resolution_fields(run)
    assert f["windows"] == 3 and f["resolution_cpu_s"] == 2.0 and f["run_cpu_s"] == 5.0
    assert (f["rest_error_left_a_m"], f["rest_error_right_a_m"]) == (1e-6, 2e-6)
    assert f["rest_error_left_b_m"] == pytest.approx(5e-6)
    assert f["rest_error_right_b_m"] == pytest.approx(1e-5)
    # Hands on, place b ends with the run: every window counts there.
    on = Run(study.base, run.resolution)
    assert resolved_runs.resolution_fields(on)["rest_error_left_b_m"] == pytest.approx(1.000005)
    none = resolved_runs.resolution_fields(Run(scene, {}))
    assert none["windows"] == 0 and math.isnan(none["rest_error_left_a_m"])
