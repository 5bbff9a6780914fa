"""Accuracy on demand (``sweep.refine``) on histories whose answer is known: the convergence
classification of an outcome's values at successive halvings, the refinement loop with a cheap
fake simulation (which runs it refines, at which steps, when it stops), and per-run errors in
the claims' maxima over runs (``study.paper.measures``) where mirrored runs swap roles."""

import dataclasses
import math

import pytest

from drake_car.sweep.refine import classify, refine
from drake_car.study.paper.measures import claim_measures
from drake_car.study.paper.outcomes import at_one_step, study_outcomes
from test_study import TIMELINE, study_of

TOL = 1e-3  # an outcome's tolerance in these tests (its unit's)


def test_a_first_order_outcome_converges_with_order_one_and_its_last_difference_as_error():
    h = 1e-3
    values = [2.0 + 0.5 * h / 2 ** k for k in range(3)]  # x(h) = x* + c h, exactly first order
    found = classify(values, TOL)
    assert found["converged"] is True
    assert found["observed_order"] == pytest.approx(1.0)
    # Richardson for p = 1: the error of x(h/4) is |x(h/2) - x(h/4)|, here exactly x - x*.
    assert found["error"] == pytest.approx(values[1] - values[2])
    assert found["value"] - found["error"] == pytest.approx(2.0)


def test_a_jump_between_branches_is_not_converged_and_gives_the_span():
    # b_3's lasting split (% of the corner load) at 1, 0.5, 0.25 ms (issue 19): dt and dt/2
    # agree on the wrong branch, dt/4 leaves it.
    found = classify([6.68, 6.70, 5.00], 0.1)
    assert found["converged"] is False
    assert found["error"] == pytest.approx(1.70)  # the span of the steps, not 0.02
    assert found["value"] == 5.00


def test_two_agreeing_differences_that_do_not_shrink_are_not_convergence():
    # b_3 from 2 ms: 6.70, 6.68, 6.70: within 0.1 twice, but the differences do not shrink
    # (a first-order scheme would halve them) and are not below a tenth of the tolerance.
    assert classify([6.70, 6.68, 6.70], 0.1)["converged"] is False
    # Just after the branch change two steps agree, but the jump before them (1.7) shrunk once
    # at first order (0.85) is beyond the tolerance: two values on a branch are not three.
    found = classify([6.70, 5.00, 4.99], 0.1)
    assert found["converged"] is False and found["error"] == pytest.approx(1.71)
    # One halving later the three finest agree: converged, its error at least half of d1.
    found = classify([6.70, 5.00, 4.99, 4.985], 0.1)
    assert found["converged"] is True and found["error"] == pytest.approx(0.005)
    # a_3 at 1, 0.5, 0.25 ms: -6.70, -5.04, -4.96: not yet; with -4.98 at 0.125 ms the last
    # three shrink (0.08, 0.02) and half of 0.08 is within 0.1: converged, error 0.04.
    assert classify([-6.70, -5.04, -4.96], 0.1)["converged"] is False
    found = classify([-6.70, -5.04, -4.96, -4.98], 0.1)
    assert found["converged"] is True and found["error"] == pytest.approx(0.04)


def test_a_count_converges_only_when_it_stops_changing():
    assert classify([3, 2, 2, 2], 0.0) == {"converged": True, "value": 2.0, "error": 0.0,
                                           "observed_order": None}
    assert classify([3, 2, 2], 0.0)["converged"] is False  # a change, then only two equal
    assert classify([2, 2, 3], 0.0)["converged"] is False
    assert classify([2, 3], 0.0)["converged"] is False  # two steps never suffice


@dataclasses.dataclass
class Plant:
    time_step: float


@dataclasses.dataclass
class FakeScene:
    name: str
    plant: Plant


@dataclasses.dataclass
class FakeRun:
    scene: FakeScene
    wall_s: float


def fake_halve(scene, k):
    return dataclasses.replace(scene, plant=Plant(scene.plant.time_step / 2 ** k))


def smooth(h):
    return 1.0 + 2.0 * h  # converges at first order: |x(h/2) - x(h/4)| = h/2, far below TOL


def jammed(h):
    # One slip more or less: 6.7 at 1 and 0.5 ms, then 5.0 and first order below.
    return 6.7 if h >= 5e-4 else 5.0 + 100.0 * h


def outcomes_of(runs):
    out = {}
    for name, run in runs.items():
        h = run.scene.plant.time_step
        out[(name, "x")] = ((smooth if name == "smooth" else jammed)(h), "m")
    if "smooth" in runs and "jam" in runs:  # an outcome of a pair: needs both at the step
        out[("smooth|jam", "pair")] = (runs["jam"].scene.plant.time_step * 0.0, "m")
    return out


class Simulator:
    """A fake ``run_scenes``: records every batch; a run's wall time is its step count."""

    def __init__(self):
        self.batches = []

    def __call__(self, scenes):
        self.batches.append(dict(scenes))
        return {n: FakeRun(s, 1e-3 / s.plant.time_step) for n, s in scenes.items()}


def scenes():
    return {n: FakeScene(n, Plant(1e-3)) for n in ("smooth", "jam")}


def test_refinement_halves_only_the_runs_that_have_not_converged():
    sim = Simulator()
    found = refine(scenes(), outcomes_of, {"x": 0.1, "pair": 0.1}, sim, halve=fake_halve,
                   finest_step_s=1e-5)
    # First round: both at h, h/2, h/4 in one sweep; then only the jammed run, one halving
    # per round, until its last two differences shrink within the tolerance.
    assert len(sim.batches[0]) == 6
    assert all(set(n.split(" at ")[0] for n in b) == {"jam"} for b in sim.batches[1:])
    assert found.steps_s["smooth"] == [1e-3, 5e-4, 2.5e-4]
    jam = found.outcomes[("jam", "x")]
    # 6.7, 6.7 (1, 0.5 ms) agree, 5.025 (0.25 ms) does not: one more halving, 5.0125 at
    # 0.125 ms, still within half the jump of it; one more, 5.00625 at 0.0625 ms: the last
    # three on one branch, their differences shrinking within the tolerance.
    assert [len(b) for b in sim.batches] == [6, 1, 1]
    assert found.steps_s["jam"] == [1e-3, 5e-4, 2.5e-4, 1.25e-4, 6.25e-5]
    assert jam["converged"] is True
    assert jam["value"] == pytest.approx(jammed(jam["step_s"]))
    assert abs(jam["value"] - 5.0) <= jam["error"] + 1e-12  # the converged branch, within it
    assert found.stopped == "every outcome converged"
    assert found.run_wall_s("jam") == pytest.approx(sum(1e-3 / h for h in found.steps_s["jam"]))
    assert found.outcomes[("smooth", "x")]["converged"] is True


def test_three_equal_values_on_one_branch_are_taken_as_converged():
    # The limit of any step-halving test, said in sweep.refine: a branch change that happens
    # only below the steps tried is not seen. 6.7 at 1, 0.5 and 0.25 ms is "converged".
    def late(runs):
        return {(n, "x"): (6.7 if r.scene.plant.time_step >= 2.5e-4 else 5.0, "m")
                for n, r in runs.items()}
    found = refine(scenes(), late, {"x": 0.1}, Simulator(), halve=fake_halve)
    assert found.outcomes[("jam", "x")]["value"] == 6.7
    assert found.outcomes[("jam", "x")]["converged"] is True


def test_refinement_stops_at_the_finest_step_and_says_not_converged_with_every_value():
    def never(runs):  # alternates between branches at every halving
        return {(n, "x"): (float(round(math.log2(1e-3 / r.scene.plant.time_step)) % 2), "m")
                for n, r in runs.items()}
    found = refine(scenes(), never, {"x": 0.1}, Simulator(), halve=fake_halve,
                   finest_step_s=1.25e-4)
    row = found.outcomes[("jam", "x")]
    assert row["converged"] is False and row["error"] == 1.0
    assert row["steps_s"] == [1e-3, 5e-4, 2.5e-4, 1.25e-4] and row["values"] == [0, 1, 0, 1]
    assert "finer than the finest" in found.stopped


def _table(levels, steps=(1e-3, 5e-4, 2.5e-4), tolerances=None):
    """Outcome rows as ``refine`` gives them, from the study's outcomes at each step."""
    from drake_car.sweep.refine import _classified
    values = {}
    for level, vals in enumerate(levels):
        for key, (value, unit) in vals.items():
            values.setdefault(key, {"unit": unit, "by_level": {}})["by_level"][level] = value
    from drake_car.study.paper.outcomes import tolerances as study_tolerances
    scene = FakeScene("", Plant(steps[0]))
    subjects = {k[0].split("|")[0] for k in values}
    return _classified(values, tolerances or study_tolerances(), 1, dict.fromkeys(subjects, scene))


def test_a_maximum_over_runs_takes_each_runs_own_error_never_another_runs():
    study = study_of()
    roles = {n: (r.case, r.friction) for n, r in study.items()}
    base = study_outcomes({n: r.columns for n, r in study.items()}, roles, TIMELINE)
    # The lasting splits of issue 19 (fractions): a_3 and b_3 swap which one is largest
    # between 1 and 0.5 ms. Compared across runs (max at dt vs max at dt/2) they differ by
    # 0.0002; each run against itself: a_3 by 0.0166, b_3 by 0.017 (not converged).
    splits = {"a_3": (-0.0670, -0.0504, -0.0496), "b_3": (0.0668, 0.0670, 0.0500)}
    levels = []
    for k in range(3):
        level = dict(base)
        for run, v in splits.items():
            level[(run, "split_change")] = (v[k], "fraction")
        levels.append(level)
    table = _table(levels)
    three = claim_measures(table, roles)[2]
    split = next(m for m in three if m["name"].startswith("largest steady change"))
    assert split["converged"] is False  # b_3 has not converged
    assert split["error"] >= 0.0170 - 1e-12  # b_3's own span, not 0.0002
    # a_3 jumped too (0.0166 between 1 and 0.5 ms): its own span, not another run's.
    assert table[("a_3", "split_change")]["converged"] is False
    assert table[("a_3", "split_change")]["error"] == pytest.approx(0.0174)
    assert table[("a_3", "split_change")]["value"] == pytest.approx(-0.0496)


def test_a_claim_is_undecided_when_its_margin_is_within_the_error():
    study = study_of()
    roles = {n: (r.case, r.friction) for n, r in study.items()}
    base = study_outcomes({n: r.columns for n, r in study.items()}, roles, TIMELINE)
    # Claim 5's rotation converges at first order to just below 3 deg: decided when the
    # margin exceeds the error, undecided when the converged value's error spans 3 deg.
    for limit, decided in ((math.radians(2.9), True), (math.radians(3) - 1.5e-5, False)):
        levels = []
        for k in range(3):
            level = dict(base)
            for n in study:
                level[(n, "rotation_rad")] = (limit + 4e-5 / 2 ** k, "rad")
            levels.append(level)
        five = claim_measures(_table(levels), roles)[4][0]
        # converged to limit + 1e-5 rad with an error of 1e-5 rad: below 3 deg in both cases
        assert five["converged"] is True and five["holds"] is True
        assert five["error"] == pytest.approx(1e-5)
        assert five["decided"] is decided, (five["margin"], five["error"])
    # At one step only: no error, so not decided either way (None).
    assert claim_measures(at_one_step(base), roles)[4][0]["decided"] is None


def test_an_unconverged_number_decides_its_claim_by_more_than_its_spread_and_a_count_does_not():
    study = study_of()
    roles = {n: (r.case, r.friction) for n, r in study.items()}
    base = study_outcomes({n: r.columns for n, r in study.items()}, roles, TIMELINE)
    # Issue 32: b_3's claim-2 shift at the last three steps, differences of 3 µm that do not
    # shrink at first order: not converged, its error the spread (5.5 µm), its margin over the
    # 0.1 mm threshold 1300 times that: decided. The same spread straddling the threshold: not.
    for shifts, decided in (((7.3356e-3, 7.3332e-3, 7.3301e-3), True),
                            ((0.1028e-3, 0.1004e-3, 0.0973e-3), False)):
        levels = []
        for k in range(3):
            level = dict(base)
            for n in study:
                for side in ("left", "right"):
                    if (n, f"shift_{side}_m") in level:
                        level[(n, f"shift_{side}_m")] = (shifts[k], "m")
            levels.append(level)
        two = claim_measures(_table(levels), roles)[1][0]
        assert two["converged"] is False and two["error"] == pytest.approx(5.5e-6)
        assert two["decided"] is decided, (two["margin"], two["error"])
    # A count that has not converged (0, 1, 0) decides nothing, whatever its margin.
    levels = []
    for k, count in enumerate((0.0, 1.0, 0.0)):
        level = dict(base)
        for key in list(level):
            if key[1].startswith("mu1_reaches_"):
                level[key] = (count, "count")
        levels.append(level)
    six = claim_measures(_table(levels), roles)[5]
    assert six and all(m["decided"] is False for m in six if m["decides"])


def test_a_run_that_fails_is_refined_no_further_and_the_others_go_on():
    # A simulator that loses the jammed run from 0.25 ms on (it raised there): the loop must
    # not ask for it again and again, must refine the others, and must say which failed.
    class Losing(Simulator):
        def __call__(self, scenes):
            done = super().__call__(scenes)
            return {n: r for n, r in done.items()
                    if not (n.startswith("jam") and r.scene.plant.time_step < 4e-4)}
    sim = Losing()
    found = refine(scenes(), outcomes_of, {"x": 0.1, "pair": 0.1}, sim, halve=fake_halve,
                   finest_step_s=1e-5)
    assert found.failed == ["jam"]
    assert len(sim.batches) == 1  # nothing left to refine: the smooth run converged
    assert found.steps_s["jam"] == [1e-3, 5e-4]
    row = found.outcomes[("jam", "x")]
    assert row["converged"] is False and row["values"] == [6.7, 6.7]  # two steps: not judged
    assert "failed" in found.stopped


def test_claim_6_s_count_is_decided_only_when_its_peak_is_clear_of_mu_s_by_its_error():
    study = study_of()
    roles = {n: (r.case, r.friction) for n, r in study.items()}
    base = study_outcomes({n: r.columns for n, r in study.items()}, roles, TIMELINE)
    a2 = next(n for n, (c, f) in roles.items() if (c, f.number) == ("a", 2))
    # The count (0: μ1 never reaches μs) agrees at every step; the left peak μ1/μs is 0.974
    # at the finest step. With its steps 0.96 / 0.99 / 0.974 (span 0.03, more than its 0.026
    # of margin) the count is undecided; with 0.970 / 0.972 / 0.973 (error 0.001) decided.
    for peaks, decided in (((0.96, 0.99, 0.974), False), ((0.970, 0.972, 0.973), True)):
        levels = []
        for peak in peaks:
            level = dict(base)
            level[(a2, "mu1_reaches_left")] = (0.0, "count")
            level[(a2, "mu1_peak_left")] = (peak, "ratio")
            levels.append(level)
        six = claim_measures(_table(levels), roles)[5]
        count = next(m for m in six if m["outcomes"] == ["mu1_reaches_left"])
        assert count["converged"] is True and count["value"] == 0.0
        assert count["decided"] is decided
    # Where μ1 does reach μs the peak is 1 exactly (the law caps it): a count of 2 at every
    # step is decided by the count alone, its peak's zero margin notwithstanding.
    levels = []
    for _ in range(3):
        level = dict(base)
        level[(a2, "mu1_reaches_left")] = (2.0, "count")
        level[(a2, "mu1_peak_left")] = (1.0, "ratio")
        levels.append(level)
    count = next(m for m in claim_measures(_table(levels), roles)[5]
                 if m["outcomes"] == ["mu1_reaches_left"])
    assert count["holds"] is True and count["decided"] is True


def test_a_floor_of_the_solver_s_size_need_not_shrink():
    """Issue 32's claim 2 (b_3's rod from place a, mm): 7.355 / 7.352 / 7.348 at the last three
    steps, a 3-4 µm wobble that does not shrink: not converged on the step alone (tolerance
    0.02 mm); converged when the solver axis moves it by 5 µm (the differences are within what
    the solver alone does), not when it moves it by 1 µm."""
    values = [7.358, 7.355, 7.352, 7.348]
    assert classify(values, 0.02)["converged"] is False
    found = classify(values, 0.02, floor=0.005)
    assert found["converged"] is True and found["error"] == pytest.approx(0.004)
    assert classify(values, 0.02, floor=0.001)["converged"] is False


def test_the_solver_twins_run_at_the_finest_step_and_floor_the_verdict():
    """Runs whose outcome wobbles by 3e-3 at every halving (never shrinking) are not converged
    on the step alone; twins at their finest step that move it by 4e-3 (SAP's tolerance
    loosened twice) put that wobble within the solver's floor: converged, the budget limited
    by the solver. Twins that move it by 1e-3 do not."""
    def twin(scene):
        return dataclasses.replace(scene, name=scene.name + " twin")

    def wobbly(shift):
        def outcomes(runs):
            out = {}
            for name, run in runs.items():
                k = round(math.log2(1e-3 / run.scene.plant.time_step))
                x = 1.0 + 3e-3 * (k % 2) + (shift if run.scene.name.endswith("twin") else 0.0)
                out[(name, "x")] = (x, "m")
            return out
        return outcomes
    plain = refine(scenes(), wobbly(4e-3), {"x": 1e-3}, Simulator(), halve=fake_halve,
                   finest_step_s=1.25e-4)
    assert plain.outcomes[("jam", "x")]["converged"] is False
    assert plain.outcomes[("jam", "x")]["solver_error"] is None
    sim = Simulator()
    found = refine(scenes(), wobbly(4e-3), {"x": 1e-3}, sim, halve=fake_halve,
                   finest_step_s=1.25e-4, solver_twin=twin)
    assert [len(b) for b in sim.batches] == [6, 2, 2]  # the twins last, at 0.125 ms
    assert all(s.plant.time_step == 1.25e-4 and s.name.endswith("twin")
               for s in sim.batches[-1].values())
    assert found.rounds[-1]["solver_twins"] is True
    row = found.outcomes[("jam", "x")]
    assert row["converged"] is True and row["error"] == pytest.approx(3e-3)
    assert row["solver_error"] == pytest.approx(4e-3) and row["limited_by"] == "solver"
    small = refine(scenes(), wobbly(1e-3), {"x": 1e-3}, Simulator(), halve=fake_halve,
                   finest_step_s=1.25e-4, solver_twin=twin)
    assert small.outcomes[("jam", "x")]["converged"] is False
    assert small.outcomes[("jam", "x")]["solver_error"] == pytest.approx(1e-3)
