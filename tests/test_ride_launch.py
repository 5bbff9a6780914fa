"""The ride study's launch follows the car (a newcomer's review: on a car that cannot do the
paper's 0.57 g the ride study used to analyse its "60 km/h" window from 48.5 km/h on, and said
so only mid-paragraph): the launch is the asked 0.57 g where the car follows it, else the
shortest its drive allows that the car holds (``scene.launch.followable_launch``, the paper
study's adaptation); a run that still does not hold its speed over the analysed window is
flagged on its rows, in the Summary, at the report's top and on stderr."""

import dataclasses
import logging
import math
import re
from pathlib import Path

import pytest

from drake_car.scene import launch
from drake_car.scene.manoeuvre_targets import SPEED_TOLERANCE_KPH
from drake_car.sim.simulate import simulate
from drake_car.study.ride.analysis import held_speed, window_speed_kph
from drake_car.study.ride.grid import (
    RideStudy, analysed_from_s, base_scene, ride_scene, ride_timeline, speed_up_s)
from drake_car.study.ride.report import (
    cost_table, outcome_table, speed_flag, summary_text, warn_off_speed)

ROOT = Path(__file__).resolve().parents[1]
# The engineer's car of issue 31 (1500 kg, front drive through the shipped 1740 N m at the
# wheels): its drive allows 3.37 m/s², the asked 0.57 g (5.56 m/s²) is beyond it.
ENGINEER = (ROOT / "scenes" / "engineers_car.yaml", "car")


@pytest.fixture(autouse=True)
def at_the_root(monkeypatch):
    """The engineer's scene names its tyre file from the repository's root."""
    monkeypatch.chdir(ROOT)


def _peak_accel(timeline):
    """The speed profile's peak acceleration (m/s²): v / (T - blend)."""
    return timeline.speed_mps / (timeline.launch_s - launch.BLEND_S)


def test_the_shipped_car_keeps_the_asked_launch_at_60():
    timeline = ride_timeline(RideStudy(), base_scene(), 60.0)
    assert timeline.speed_up_s == speed_up_s(60.0) == 3.0


def test_a_car_that_cannot_do_the_asked_launch_gets_one_it_can_follow():
    study = RideStudy(classes=["B"], speeds_kph=[60.0])
    base = base_scene(scene=ENGINEER)
    limits = launch.launch_limits(base)
    assert limits.max_accel_mps2 < 60 / 3.6 / (speed_up_s(60.0) - launch.BLEND_S)
    scene = ride_scene(study, "B", 60.0, 0.0, base=base)
    timeline = scene.manoeuvre.timeline
    # the shortest launch its drive allows (or longer): the profile within what the car allows
    assert timeline.speed_up_s >= limits.shortest_launch_s(timeline.speed_mps) > 3.0
    assert _peak_accel(timeline) <= limits.max_accel_mps2
    # the analysed window starts the settling after the launch the car runs
    assert analysed_from_s(scene, study) == pytest.approx(
        timeline.settle_s + timeline.speed_up_s + study.settle_window_s)
    # and the road is long enough for the longer launch (the grid refuses a short one)
    assert study.road_m({60.0: timeline.speed_up_s}) >= study.run_distance_m(
        60.0, timeline.speed_up_s)


def test_the_launch_test_holds_the_whole_window():
    """The shipped Escort (4.54 m/s² at its torque limit) at 100 km/h: the asked 5 s launch asks
    5.9 m/s², and the car is predicted still short of its speed when the window starts; the
    launch chosen is held over the window."""
    study, base = RideStudy(), base_scene()
    holds = launch.holds_after_launch(study.settle_window_s)
    t60 = ride_timeline(RideStudy(speeds_kph=[60.0]), base, 60.0)
    assert holds(base, dataclasses.replace(t60, speed_up_s=speed_up_s(60.0)))  # 3 s: held
    t100 = ride_timeline(study, base, 100.0)
    assert not holds(base, dataclasses.replace(t100, speed_up_s=speed_up_s(100.0)))
    assert t100.speed_up_s > speed_up_s(100.0) and holds(base, t100)


def test_a_car_that_cannot_do_the_asked_launch_holds_its_speed_in_the_window():
    """Simulated (lubricated, class B, 60 km/h, 1 s analysed; ~8 s of simulated time): the
    engineer's car's speed over the analysed window within the study's tolerance (1 km/h). On
    the fixed 0.57 g launch it was at ~49 km/h when the window began."""
    study = RideStudy(classes=["B"], speeds_kph=[60.0], window_s=1.0)
    scene = ride_scene(study, "B", 60.0, 0.0, base=base_scene(scene=ENGINEER))
    history = simulate(scene).history
    low, high = window_speed_kph(history, analysed_from_s(scene, study))
    assert abs(low - 60.0) <= SPEED_TOLERANCE_KPH and abs(high - 60.0) <= SPEED_TOLERANCE_KPH


def _row(mu_s, low, high, strut="damper", name=None):
    row = {"name": name or f"B_60kph_mu{mu_s:.2f}" + ("" if mu_s == 0 else f"_{strut}"),
           "road_class": "B", "speed_kph": 60.0, "strut": "lubricated" if mu_s == 0 else strut,
           "mu_s": mu_s, "launch_s": 3.0, "speed_min_kph": low, "speed_max_kph": high,
           "rig_friction_N": 300.0 * mu_s, "aw_seat_mps2": 0.4 + mu_s, "dlc_front": 0.1 + mu_s,
           "dlc_rear": 0.12}
    row.update({f"err_{k}": 0.001 for k in ("aw_seat_mps2", "dlc_front", "dlc_rear")})
    for key in ("pitch_acc_rms_radps2", "roll_acc_rms_radps2", "stick_left", "stick_right",
                "friction_mean_N", "normal_mean_N"):
        row[key], row[f"err_{key}"] = 0.0, 0.0
    row["held_speed"] = held_speed(row)
    return row


def test_held_speed_is_the_window_within_the_tolerance():
    assert held_speed(_row(0.0, 59.3, 60.0)) and held_speed(_row(0.0, 59.0, 61.0))
    assert not held_speed(_row(0.0, 48.5, 59.8))
    assert not held_speed(_row(0.0, 59.5, 61.2))
    assert not held_speed(_row(0.0, math.nan, math.nan))  # not logged: not shown held


def test_a_run_off_its_speed_is_flagged_loudly(caplog):
    held = [_row(mu, 59.4, 60.1) for mu in (0.0, 0.1, 0.2, 0.3, 0.4)]
    assert speed_flag(held) == [] and "OFF" not in outcome_table(held)
    assert "not at constant speed" not in summary_text(held)
    off = held[:2] + [_row(0.2, 48.5, 59.8)] + held[3:]
    flag = "\n".join(speed_flag(off))
    assert "not at constant speed" in flag and "B_60kph_mu0.20_damper: 48.50-59.80 km/h" in flag
    table = outcome_table(off).splitlines()
    assert [line for line in table if "OFF" in line] == [
        line for line in table if "| 0.20 |" in line]
    assert "60 **OFF: 48.50-59.80 km/h**" in outcome_table(off)
    assert "**not at constant speed**: 1 of 5 runs" in summary_text(off)
    assert "60 **OFF**" in cost_table(off)
    with caplog.at_level(logging.WARNING, logger="drake_car"):
        warn_off_speed(off)
    warned = [r for r in caplog.records if r.levelno == logging.WARNING]
    assert len(warned) == 1 and "B_60kph_mu0.20_damper" in warned[0].getMessage()


def test_a_launch_that_length_cannot_cure_is_not_lengthened_to_a_minute(caplog):
    """A drive whose speed controller droops (a tenth of the shipped gain) misses the window's
    speed by a steady 0.8 km/h whatever the launch: it was lengthened to MAX_LAUNCH_S (60 s, a
    1038 m road). Now at most MAX_BEYOND_SHORTEST_S beyond the shortest its drive allows, then
    the shortest, said on the log; the shipped car's launches are as before."""
    droop = base_scene(scene_text="drive: !OpenDifferential {speed_gain_Nm_per_mps: 150.0}")
    study = RideStudy(speeds_kph=[60.0])
    with caplog.at_level(logging.WARNING, logger="drake_car"):
        chosen = ride_timeline(study, droop, 60.0)
    shortest = launch.launch_limits(droop).shortest_launch_s(chosen.speed_mps)
    assert chosen.speed_up_s == shortest
    assert any("a steady droop, not the launch" in r.getMessage() for r in caplog.records)
    shipped = base_scene()
    assert [ride_timeline(RideStudy(speeds_kph=[v]), shipped, v).speed_up_s
            for v in (60.0, 100.0, 140.0)] == [3.0, 6.5, 8.9]


@pytest.mark.parametrize("text, key", [
    ("manoeuvre: !Straight {timeline: {speed_up_s: 8.0}}", "speed_up_s"),
    ("manoeuvre: !Straight {timeline: {speed_kph: 80.0}}", "speed_kph"),
    ("manoeuvre: !Straight {timeline: {calm_s: 1.0}}", "calm_s"),
])
def test_a_stated_launch_or_speed_is_refused_not_replaced(text, key, tmp_path):
    """The ride study sets the speed (--speeds), the launch and the window per speed: a user's
    scene that states one of them would have it replaced without a word (it was, before), so
    it is refused, naming the key and what sets it."""
    from drake_car.scene.raw import SceneError
    with pytest.raises(SceneError, match=rf"--scene_text: states manoeuvre\.timeline\.{key}"):
        base_scene(scene_text=text)
    mine = tmp_path / "mine.yaml"
    mine.write_text(f"car: {{{text}}}\n")
    with pytest.raises(SceneError, match=rf"--scene {mine}:car: states manoeuvre\.timeline\.{key}"):
        base_scene(scene=(mine, "car"))


def test_the_time_at_rest_is_taken_from_the_users_scene():
    """settle_s is not set by the study: a stated one runs (the run's first phase)."""
    base = base_scene(scene_text="manoeuvre: !Straight {timeline: {settle_s: 0.5}}")
    assert base.manoeuvre.timeline.settle_s == 0.5
    assert ride_timeline(RideStudy(speeds_kph=[60.0]), base, 60.0).settle_s == 0.5


@pytest.mark.parametrize("text, what", [
    ("road: !CosineBump {}", "road"),
    ("friction: {law: {mu_s: 0.3, mu_d: 0.2}}", "friction.law.mu_s"),
    ("friction: {law: {mu_d: 0.2}}", "friction.law.mu_d"),
    ("friction: null", "friction: null"),
])
def test_a_stated_road_or_friction_coefficient_is_refused_not_replaced(text, what):
    """The ride study lays its road (--classes) and sets μs, μd per run: stated, they would be
    replaced without a word (a review found them dropped), so they are refused."""
    from drake_car.scene.raw import SceneError
    with pytest.raises(SceneError, match=rf"--scene_text: states {re.escape(what)}"):
        base_scene(scene_text=text)


def test_the_friction_laws_other_values_scheme_and_pairs_run():
    """What the study does not set of the friction (a preload, the pairs) runs, at each μs."""
    from drake_car.study.ride.grid import ride_scene
    base = base_scene(scene_text="friction: {pairs: translation, law: {preload_force_N: 50.0}}")
    study = RideStudy(classes=["B"], speeds_kph=[60.0])
    scene = ride_scene(study, "B", 60.0, 0.3, base=base)
    assert scene.friction.pairs == "translation"
    assert scene.friction.law.preload_force_N == 50.0
    assert (scene.friction.law.mu_s, scene.friction.law.mu_d) == (0.3, pytest.approx(0.225))
    assert ride_scene(study, "B", 60.0, 0.0, base=base).friction is None  # the lubricated run
