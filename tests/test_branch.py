"""Shared prefixes: runs that differ only in the lane change's case simulate the prefix once and
branch from its saved context; a branched run equals the run from scratch bit for bit."""

import numpy as np
import pytest

from conftest import paper_scene
from drake_car.sim.branch import branch_point, families, simulate_family
from drake_car.sim.simulate import simulate

# The paper's timeline shortened 20 times: the lane change (the branch) starts at 0.25 s.
# The rack as given (the shipped calibration's profile): none is calibrated for such a timeline.
SHORT = ("manoeuvre: !LaneChange {timeline: {settle_s: 0.04, speed_up_s: 0.15, "
         "straight_s: 0.06, steer_s: 0.12, calm_s: 0.13}, amplitude_m: 0.005908525382359731, "
         "second_lobe: 1.012425560052948}")


@pytest.mark.parametrize("number", [1, 3])
def test_a_branched_run_equals_the_run_from_scratch(number):
    a, b = paper_scene(f"a_{number}", SHORT), paper_scene(f"b_{number}", SHORT)
    branched = simulate_family([a, b])
    for run, scene in zip(branched, (a, b)):
        scratch = simulate(scene)
        assert run.steps == scratch.steps and run.frozen_sap_steps == scratch.frozen_sap_steps
        for column, values in scratch.history.items():
            assert np.array_equal(run.history[column], values) if column != "phase" \
                else run.history[column] == values, (scene.name, column)
        assert run.final["positions"] == scratch.final["positions"], scene.name


def test_families_group_what_agrees_until_the_lane_change():
    scenes = {name: paper_scene(name, SHORT) for name in ("a_1", "a_2", "a_3", "b_1", "b_2",
                                                          "b_3")}
    groups = sorted(sorted(g) for g in families(scenes))
    assert groups == [["a_1", "b_1"], ["a_2", "b_2"], ["a_3", "b_3"]]
    assert branch_point(scenes["a_3"])[1] == pytest.approx(0.25)
    # A run that differs before the branch (another friction law) is not of the family.
    other = paper_scene("b_3", SHORT + "\nfriction: {law: {mu_s: 0.39}}")
    assert branch_point(other)[0] != branch_point(scenes["a_3"])[0]
    with pytest.raises(ValueError, match="do not share a prefix"):
        simulate_family([scenes["a_3"], other])


def test_a_branched_hands_off_run_starts_with_the_rack_held():
    """Hands off: the first run of a family lets go of the rack at its release time (the rack
    servo's gains are plant model values, written by a GainSchedule); the branched run starts
    at the lane change, before the release, so its rack must be held again: it equals the run
    from scratch bit for bit."""
    hands_off = SHORT + "\nsteering: !HandsOff {}"
    a, b = paper_scene("a_2", hands_off), paper_scene("b_2", hands_off)
    branched = simulate_family([a, b])
    scratch = simulate(b)
    for column, values in scratch.history.items():
        if column != "phase":
            assert np.array_equal(branched[1].history[column], values), column
