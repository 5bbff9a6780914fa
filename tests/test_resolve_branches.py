"""A looser tolerance does not hand a run another branch (issue 32): a window's twins judge
branches, not only rest positions (``sim.twins._branches``: a strut at full creep whose reserve
the last window's error moves is resolved together with that window), and three levels agree
only within the default tolerance's band (``sim.window.agreement_band``)."""

import math

import pytest

from conftest import paper_scene
from drake_car.data import resource
from drake_car.sim.simulate import simulate
from drake_car.study.design import resolved_runs
from drake_car.study.design import runs as design_runs
from drake_car.study.design import smoke as design_smoke
from drake_car.study.design.spec import load_study

RESOLVE = "\nsimulator: {resolve_events: {%s}}"  # as the paper's job resolves its runs
LOOSE = RESOLVE % "position_tolerance_m: 2.0e-4"


def _rests(run):
    """Each rod's rest position after the run's last window (m; every strut static from there
    to the end) and its error (the windows' summed)."""
    r = run.resolution
    last = r["windows"][-1]["levels"][-1]["positions"]
    return {pair: (last[pair], r["position_errors"][pair]) for pair in last}


def _rest_within_both_errors(loose, default):
    """Each rod rests where the default tolerance's run's does, within both runs' errors."""
    for pair, (x, error) in _rests(loose).items():
        y, reference_error = _rests(default)[pair]
        assert math.isfinite(error) and math.isfinite(reference_error), pair
        assert abs(x - y) <= error + reference_error, (pair, x, y, error, reference_error)


@pytest.mark.slow
def test_a_looser_tolerance_keeps_a_3s_late_break_away():
    # a_3 (the paper's car, set 3): its right strut sits at full creep at 7.85 s with about
    # 4e-4 of its capacity left and breaks away, or not, by what the window from 7.10 s left.
    # At 2e-4 m the 7.10 s window ended at 7.81 s resolved at 0.25 ms, the next one did not
    # break away at 1, 0.5, 0.25 ms (reserve 3.9e-4, 3.7e-4, 3.8e-4), and the right rod rested
    # 3.5 mm from where the default tolerance's run rests, with an error of 37 µm. Its
    # inheritance twin (level 0 from the 7.10 s window's 0.5 ms end) moves that reserve: the
    # two windows are resolved as one, and the rods rest where the default run's do, within
    # both runs' errors (each the sum of its windows' convergence, inheritance and gap errors).
    _rest_within_both_errors(simulate(paper_scene("a_3", LOOSE)),
                             simulate(paper_scene("a_3", RESOLVE % "")))


@pytest.mark.slow
def test_a_looser_tolerance_keeps_a_2s_return_on_its_branch():
    # a_2 (set 2): its return window (4.41 s) rests at 6.4769 / 6.4736 / 6.4791 mm at 1 / 0.5
    # / 0.25 ms and stops once fewer from 0.125 ms on (5.979 mm). At 2e-4 m those three agreed
    # within a tenth of the tolerance and were taken as converged, 500 µm off with a stated
    # error of 16.5 µm. Within both runs' errors of the default's rest now.
    loose = simulate(paper_scene("a_2", LOOSE))
    default = simulate(paper_scene("a_2", RESOLVE % ""))
    return_window = [w for w in loose.resolution["windows"] if w["start_s"] < 4.5 < w["end_s"]]
    assert return_window and return_window[0]["step_s"] < 0.25e-3, "resolved below 0.25 ms"
    _rest_within_both_errors(loose, default)


@pytest.mark.slow
def test_a_gap_whose_step_changes_a_branch_is_resolved_with_its_window():
    # The design study's --quick Sobol point sobol_0000 (its local route, finest step 0.25 ms):
    # the window from 1.07 s did not resolve, and the gap before it (0.39-1.07 s, run at 1 ms),
    # run again at 0.5 ms, changed the left strut's slips: its error was unknown (infinite).
    # The window is now run again from the gap's start, the gap resolved with it: every error
    # is known (the span of its last three levels where it does not converge).
    study = design_smoke.quick(load_study(resource("scenes/studies/design.yaml"), "study"))[0]
    scene, _ = design_runs.sobol_scenes(study)["sobol_0000"]
    windows = simulate(resolved_runs.resolving(study, scene)).resolution["windows"]
    for w in windows:
        assert all(math.isfinite(e) for e in w["position_errors"].values()), w["start_s"]
    gaps = [k for k, w in enumerate(windows) if w["merged"]["gaps"]]
    # (the premise is this chaotic run's path at drake 1.58; tests/test_resolve_restart.py
    # checks the restart itself with stubbed levels, on any machine)
    assert gaps, "the case this test is about: a gap's twin changed a branch"
    for k in gaps:  # such a window starts where the last one ended (or at the run's start)
        assert k == 0 or windows[k]["start_s"] == pytest.approx(windows[k - 1]["end_s"])
