"""Manoeuvres defined by a path: ISO 3888-2's lanes and the centre line through them, the
circle, the footprint against the lanes (pure geometry); the scene's refusals; the shipped
double lane change and constant-radius turn driven by the path follower, judged by what they
ask."""

import math

import numpy as np
import pytest

from drake_car.data import resource
from drake_car.law.road.centre_line import (
    circle_line, footprint_corners, iso3888_2_lanes, lane_excursion_m, lane_line)
from drake_car.scene.load import SceneError, load_scene
from drake_car.sim.simulate import simulate

DRIVER_SCENES = resource("scenes/driver.yaml")


def test_iso3888_2_lanes_follow_the_vehicle_width():
    w = 1.69
    lane1, lane3, lane5 = iso3888_2_lanes(w, entry_m=10.0)
    assert (lane1.start_m, lane1.end_m, lane3.start_m, lane3.end_m, lane5.start_m,
            lane5.end_m) == pytest.approx((10.0, 22.0, 35.5, 46.5, 59.0, 71.0))
    assert lane5.end_m - lane1.start_m == pytest.approx(61.0), "the course is 61 m long"
    assert lane1.width_m == pytest.approx(1.1 * w + 0.25) and lane1.centre_m == 0.0
    assert lane3.width_m == pytest.approx(w + 1.0)
    assert lane3.right_m - lane1.left_m == pytest.approx(1.0), "lane 3 is 1 m beyond lane 1"
    assert lane5.width_m == pytest.approx(3.0), "1.3 w + 0.25 = 2.45 m, floored at 3 m"
    assert lane5.right_m == lane1.right_m
    wide = iso3888_2_lanes(2.2)[2]
    assert wide.width_m == pytest.approx(1.3 * 2.2 + 0.25)


def test_the_lane_line_runs_on_the_lane_centres_and_turns_smoothly():
    lanes = iso3888_2_lanes(1.69, entry_m=0.0)
    line = lane_line(lanes, -20.0, 100.0)
    for lane in lanes:
        inside = (line.x >= lane.start_m) & (line.x <= lane.end_m)
        np.testing.assert_allclose(line.y[inside], lane.centre_m, atol=1e-12)
        np.testing.assert_allclose(line.curvature[inside], 0.0, atol=1e-12)
    # heading and curvature are the derivatives of the sampled points (no step anywhere)
    slope = np.gradient(line.y, line.x)
    np.testing.assert_allclose(np.tan(line.heading), slope, atol=2e-3)
    # continuous: from sample to sample (0.1 m) it changes by under a tenth of its largest
    # value (2π Δx / L = 0.047 for the 13.5 m gap; a step, as a cosine transition has at its
    # ends, would be all of it)
    assert np.max(np.abs(np.diff(line.curvature))) < 0.1 * np.max(np.abs(line.curvature))
    gap = lanes[1].start_m - lanes[0].end_m
    rise = lanes[1].centre_m - lanes[0].centre_m
    # y'' peaks at 2πΔy/L² a quarter across, where the slope Δy/L lowers the curvature by
    # (1 + (Δy/L)²)^1.5
    peak = 2 * math.pi * rise / gap ** 2
    assert peak / (1 + (rise / gap) ** 2) ** 1.5 <= np.max(line.curvature) <= peak


def test_circle_line_and_where_a_point_lies():
    line = circle_line(entry_m=30.0, radius_m=40.0, left=True, length_m=300.0)
    # a point 1 m inside the circle, a quarter turn on
    station, offset, heading, curvature = line.locate(70.0 - 1.0, 40.0)
    assert station == pytest.approx(50.0 + 40.0 * math.pi / 2, abs=0.05)  # 50 m approach
    assert offset == pytest.approx(1.0, abs=1e-3) and heading == pytest.approx(math.pi / 2,
                                                                               abs=1e-3)
    assert curvature == pytest.approx(1 / 40.0)
    right = circle_line(30.0, 40.0, False, 300.0)
    assert right.locate(70.0, -40.0)[3] == pytest.approx(-1 / 40.0)


def test_a_footprint_out_of_a_lane_is_measured():
    lanes = iso3888_2_lanes(1.69)
    x = np.array([6.0])
    inside = footprint_corners(x, np.array([0.0]), np.array([0.0]), 1.69, 0.8, 3.0)
    worst, lane = lane_excursion_m(lanes, *inside)
    assert worst == pytest.approx(1.69 / 2 - lanes[0].left_m) and lane == 0
    out = footprint_corners(x, np.array([0.3]), np.array([0.0]), 1.69, 0.8, 3.0)
    assert lane_excursion_m(lanes, *out)[0] == pytest.approx(0.3 + 1.69 / 2 - lanes[0].left_m)


REFUSED = {
    "a path follower on a manoeuvre without a path": (
        "steering: !PathFollower {}", "needs a manoeuvre defined by a path"),
    "a path manoeuvre held on a rack profile": (
        "manoeuvre: !DoubleLaneChange {}", "cannot drive !DoubleLaneChange"),
    "its outcome not logged": (
        "manoeuvre: !ConstantRadius {}\nsteering: !PathFollower {}\n"
        "logging: {channels: [struts]}", "must hold chassis"),
    "a course longer than phase III": (
        "manoeuvre: !DoubleLaneChange {timeline: {speed_kph: 60.0, steer_s: 3.0}}\n"
        "steering: !PathFollower {}", "must cover the 61 m course"),
    "a driver slower than the step": (
        "manoeuvre: !ConstantRadius {}\nsteering: !PathFollower {period_s: 0.0005}",
        "must be >= plant.time_step"),
    "a body narrower than the wheels": (
        "manoeuvre: !DoubleLaneChange {vehicle_width_m: 1.4}\nsteering: !PathFollower {}",
        "width over its tyres"),
    "a tolerance as wide as the circle": (
        "manoeuvre: !ConstantRadius {radius_m: 20.0, tolerance_m: 3.0}\n"
        "steering: !PathFollower {}", "a tenth of radius_m"),
}


@pytest.mark.parametrize("label", list(REFUSED))
def test_refused_at_load(label):
    text, message = REFUSED[label]
    with pytest.raises(SceneError, match=message):
        load_scene(scene_text=text)


def test_the_shipped_double_lane_change_stays_in_its_lanes():
    """ISO 3888-2 at 45 km/h with the path follower: the footprint inside every lane (by
    about 0.1 m on this car, measured), the course completed, the entry speed held."""
    scene = load_scene(DRIVER_SCENES, child="double_lane_change")
    run = simulate(scene)
    outcome = run.final["manoeuvre_outcome"]
    assert outcome["course_completed"] and outcome["inside"], outcome
    speed = run.history["speed_mps"][run.history["x_m"] >= scene.manoeuvre.lanes()[0].start_m]
    assert np.all(np.abs(speed - scene.manoeuvre.timeline.speed_mps) < 0.05 *
                  scene.manoeuvre.timeline.speed_mps), "the drive holds the entry speed"


# The understeer gradient bound of tests/test_driver.py (rad of road-wheel angle per g).
MAX_UNDERSTEER_RAD_PER_G = 0.1


def test_the_constant_radius_turn_holds_its_circle():
    """The car on a 40 m circle at 40 km/h: past a quarter turn its reference point stays on
    the circle within the residual offset the driver leaves, K a_y / (g k) (the feedback
    supplies the understeer's extra steer K a_y / g through the gain k = 4 l / L²), with K
    bounded above; far inside the manoeuvre's own tolerance."""
    scene = load_scene(DRIVER_SCENES, child="constant_radius",
                       scene_text="manoeuvre: !ConstantRadius {timeline: {steer_s: 8.0}}")
    outcome = simulate(scene).final["manoeuvre_outcome"]
    assert outcome["quarter_turn_reached"] and outcome["within"], outcome
    m = scene.manoeuvre
    k = 4 * scene.car.wheelbase_m / scene.steering.preview_m ** 2
    a_y = m.timeline.speed_mps ** 2 / m.radius_m
    bound = MAX_UNDERSTEER_RAD_PER_G * a_y / 9.81 / k
    assert outcome["radius_error_m"] <= bound, (outcome, bound)


def test_every_path_scene_value_changes_what_runs_or_how_it_is_judged():
    """Each value of !PathFollower changes the driver built from it; each of the manoeuvres'
    changes the path, the lanes or the verdict on one and the same history."""
    from drake_car.sim.build import build_diagram
    from drake_car.sim.driver_wiring import steering_law

    base = load_scene(DRIVER_SCENES, child="double_lane_change")
    law = steering_law(base.car, base.steering)
    for text in ("preview_m: 12.0", "damping_ratio: 0.8"):
        other = load_scene(base=base, scene_text=f"steering: !PathFollower {{{text}}}")
        assert steering_law(other.car, other.steering) != law, text
    slower = load_scene(base=base, scene_text="steering: !PathFollower {period_s: 0.02}")
    periodic = build_diagram(slower).driver.GetUniquePeriodicDiscreteUpdateAttribute()
    assert periodic.period_sec() == 0.02

    # along the path, nose 0.05 rad left (the rear corners swing out most), stopping 1 m
    # short of the course's end (a longer front overhang reaches it)
    line = base.manoeuvre.centre_line()
    x = np.linspace(0.0, base.manoeuvre.lanes()[-1].end_m - 1.0, 600)
    history = {"x_m": x, "y_m": np.interp(x, line.x, line.y), "yaw_rad": np.full_like(x, 0.05)}
    judged = base.manoeuvre.outcome(base, history)
    for text in ("direction: right", "vehicle_width_m: 1.8", "front_overhang_m: 1.2",
                 "rear_overhang_m: 1.1"):
        other = load_scene(base=base, scene_text=f"manoeuvre: !DoubleLaneChange {{{text}}}")
        assert other.manoeuvre.outcome(other, history) != judged, text
    assert load_scene(base=base, scene_text="manoeuvre: !DoubleLaneChange {vehicle_width_m: "
                      "1.8}").manoeuvre.centre_line().y.max() != base.manoeuvre.centre_line(
                      ).y.max()

    circle = load_scene(DRIVER_SCENES, child="constant_radius")
    m = circle.manoeuvre
    angle = np.linspace(-0.5, 3.0, 400)
    r = m.radius_m + 0.3
    ring = {"x_m": m.entry_m() + r * np.sin(angle), "y_m": m.radius_m - r * np.cos(angle)}
    verdict = m.outcome(circle, ring)
    assert verdict["within"] and verdict["radius_error_m"] == pytest.approx(0.3, abs=1e-3)
    for text, key in (("tolerance_m: 0.2", "within"), ("radius_m: 41.0", "radius_error_m"),
                      ("direction: right", "quarter_turn_reached")):
        other = load_scene(base=circle, scene_text=f"manoeuvre: !ConstantRadius {{{text}}}")
        assert other.manoeuvre.outcome(other, ring)[key] != verdict[key], text
