"""Values a user's car runs with that are the shipped car's (issue 40's review on a 1350 kg
hatchback): the drive's torque limit and the tyres' relaxation lengths are stated with their
value and source in every report that states them, warned once on stderr where a car file or a
tyre file has its own; the car's own strut damping is not a friction set's; --no_verify's last
line says what it judged (``scene.borrowed``)."""

import dataclasses
import logging

import pytest

from conftest import paper_scene
from drake_car.model.parameters import CarParameters
from drake_car.scene import borrowed
from drake_car.scene.borrowed import drive_limit
from drake_car.scene.launch import launch_description
from drake_car.scene.load import load_scene
from drake_car.study.car.describe import car_facts, car_lines, own_strut_damping, tyre_words
from drake_car.study.paper.manoeuvre import manoeuvre_section
from drake_car.study.paper.report import verdict_line
from test_study_sets import SEDAN, report_of

CAR_FILE = "cars/bmw_320i.yaml"
SET_DRIVE = 'drive: !OpenDifferential {max_wheel_torque_Nm: ...}'


@pytest.fixture(autouse=True)
def nothing_said_yet():
    borrowed._SAID.clear()
    yield
    borrowed._SAID.clear()


def _said(caplog, what):
    return [r.getMessage() for r in caplog.records if what in r.getMessage()]


# -- A1: the drive's torque limit -------------------------------------------------------------

def test_the_drive_s_torque_limit_is_stated_with_its_source_and_how_to_set_it():
    shipped = borrowed.drive_limit_words(borrowed.drive_limit(paper_scene("a_1")))
    assert "1740 N m" in shipped and "shipped Escort's estimate [EST]" in shipped
    assert SET_DRIVE in shipped
    own = load_scene(base=paper_scene("a_1"),
                     scene_text="drive: !OpenDifferential {max_wheel_torque_Nm: 2170.0}")
    words = borrowed.drive_limit_words(borrowed.drive_limit(own))
    assert "2170 N m" in words and "the scene's `drive.max_wheel_torque_Nm`" in words
    assert "Escort" not in words
    locked = load_scene(base=paper_scene("a_1"), scene_text="drive: !PrescribedRotation {}")
    assert borrowed.drive_limit(locked) is None


def test_the_car_section_and_the_launch_state_the_drive_s_torque():
    scene = load_scene(base=paper_scene("a_1"), scene_text=f"car_file: {CAR_FILE}")
    drive_line = next(line for line in car_lines(car_facts(scene))
                      if line.startswith("- **drive**"))
    assert "its torque limit 1740 N m" in drive_line and SET_DRIVE in drive_line
    launch = launch_description(scene) | {"drive_limit": drive_limit(scene)}
    man = {"launch": launch | {"reached_within_tolerance_after_s": 3.0, "reached_run": "a_1"},
           "profile": {"amplitude_m": None, "second_lobe": None}, "calibration": None,
           "checks": {"a_1": []}, "off": {}}
    text = "\n".join(manoeuvre_section({"manoeuvre": man}))
    assert f"The drive allows {launch['drive_accel_mps2']:.2f} m/s² (its torque limit 1740 N m" \
        in text and SET_DRIVE in text
    assert "This car's drive" not in text


def test_the_ride_report_s_longer_launch_states_the_drive_s_torque():
    from drake_car.study.ride.report import launch_text
    text = launch_text([{"speed_kph": 60.0, "launch_s": 5.0}], paper_scene("a_1"))
    assert "the drive's torque limit 1740 N m" in text and SET_DRIVE in text


def test_a_car_file_with_the_default_drive_is_warned_once(caplog):
    with caplog.at_level(logging.WARNING, logger="drake_car"):
        for _ in range(3):
            load_scene(base=paper_scene("a_1"), scene_text=f"car_file: {CAR_FILE}")
    (said,) = _said(caplog, "max_wheel_torque_Nm")
    assert "1740 N m, the shipped Escort's estimate [EST]" in said and SET_DRIVE in said
    caplog.clear()
    borrowed._SAID.clear()
    with caplog.at_level(logging.WARNING, logger="drake_car"):
        load_scene(base=paper_scene("a_1"), scene_text=f"{{car_file: {CAR_FILE}, drive: "
                   "!OpenDifferential {max_wheel_torque_Nm: 2500.0}}")
        load_scene()  # the shipped car: its own drive
        # a car at rest (car checks, settle, the strut rig): nothing launches
        load_scene(scene_text=f"{{car_file: {CAR_FILE}, manoeuvre: !Settle {{}}}}")
    assert not _said(caplog, "max_wheel_torque_Nm")


# -- A2: the tyres' relaxation lengths ---------------------------------------------------------

def test_the_relaxation_lengths_that_ran_are_stated_with_their_source():
    scene = load_scene(scene_text=f"tyres: !MagicFormula {{tir_file: {SEDAN}}}")
    r = borrowed.relaxation(scene)
    assert r["source"] == "shipped" and r["used_m"] == [0.15, 0.45]
    assert r["file_source"] == "PTX/PTY" and r["file_m"][0] > 0.3  # the file's σκ, not 0.15
    words = tyre_words(car_facts(scene)["tyres"])
    assert "σκ 0.15 m, σα 0.45 m: the shipped tyre's estimates [EST]" in words
    assert "**the tyre file has its own, not used**" in words
    assert "relaxation_lengths_from_file: true" in words
    used = load_scene(scene_text=f"tyres: !MagicFormula {{tir_file: {SEDAN}, slip: "
                                 "{relaxation_lengths_from_file: true}}")
    words = tyre_words(car_facts(used)["tyres"])
    sk, sa = r["file_m"]
    assert f"σκ {sk:.3g} m, σα {sa:.3g} m: the tyre file's (PTX*/PTY*)" in words
    assert "not used" not in words
    shipped = tyre_words(car_facts(load_scene())["tyres"])  # no relaxation data in the file
    assert "the shipped tyre's estimates [EST]" in shipped and "not used" not in shipped


def test_a_tyre_file_s_unused_relaxation_data_is_warned_once(caplog):
    text = f"tyres: !MagicFormula {{tir_file: {SEDAN}}}"
    with caplog.at_level(logging.WARNING, logger="drake_car"):
        load_scene(scene_text=text)
        load_scene(scene_text=text)
    (said,) = _said(caplog, "relaxation data of its own")
    assert "σκ 0.15 m, σα 0.45 m (the shipped tyre's estimates [EST])" in said
    caplog.clear()
    with caplog.at_level(logging.WARNING, logger="drake_car"):
        load_scene(scene_text=f"tyres: !MagicFormula {{tir_file: {SEDAN}, slip: "
                              "{relaxation_lengths_from_file: true}}")
        load_scene()
    assert not _said(caplog, "relaxation data of its own")


# -- B8: the car's own strut damping ----------------------------------------------------------

def test_the_car_s_strut_damping_is_its_own_not_a_friction_set_s():
    study = __import__("test_study").study_of()
    scenes = {n: load_scene(base=paper_scene(n), scene_text=f"car_file: {CAR_FILE}")
              for n in study}
    s, text = report_of(study, scenes)
    own = s["car_file_strut_damping_Nspm"]
    assert own != 1250.0 and s["car"]["strut_damping_Nspm"] == own
    assert CAR_FILE in s["car"]["strut_damping_source"]
    car = text.split("## The car that ran")[1].split("\n## ")[0]
    assert f"the car's own viscous damping in the strut {own:g} N s/m (the car file" in car
    shipped, _ = report_of(study, {n: paper_scene(n) for n in study})
    # the Escort's own damper (model.parameters), not set 1's 1250 N s/m
    assert shipped["car"]["strut_damping_Nspm"] == CarParameters().front.strut_damping_Nspm
    assert "shipped Escort" in shipped["car"]["strut_damping_source"]
    same = [dataclasses.replace(sc, car=dataclasses.replace(sc.car, front=dataclasses.replace(
        sc.car.front, strut_damping_Nspm=1657.0))) for sc in scenes.values()]
    assert own_strut_damping(same) == (1657.0, "every run's scene")
    # One friction set (every run the same set): its damping is the set's, not the car's own.
    one_set = [dataclasses.replace(sc, friction=same[-1].friction) for sc in same]
    value, source = own_strut_damping(one_set)
    assert source != "every run's scene" and CAR_FILE in source


# -- B4: --no_verify's last line -------------------------------------------------------------

def test_no_verify_s_last_line_says_no_error_was_estimated():
    claims = [{"reproduced": True, "decided": None}, {"reproduced": False, "decided": None},
              {"reproduced": None}]
    line = verdict_line(claims, verified=False, steps_s=[1e-3])
    assert line == ("1 of 2 claims reproduced at the runs' step (1 ms), no numerical error "
                    "estimated (--no_verify), 1 not applicable to these friction sets")
    claims[0]["decided"] = False
    assert verdict_line(claims, verified=True, steps_s=[1e-3]).startswith(
        "1 of 2 claims reproduced, 1 undecided at the finest step tried")


# -- The driver's seat point (a VW Vanagon's review: the Escort's point ran for a van) ----------

def test_a_car_file_without_its_seat_point_rides_at_a_named_estimate(caplog, tmp_path):
    """A car file that states no seat_point_m runs the ride at an estimate from its size [EST]:
    warned once on stderr where the ride is logged (not in a scene that does not log it),
    named in the ride report's words with how to state it; the shipped car's point is the
    Escort's; a car file's own point is its own, and a scene's over it the scene's."""
    from drake_car.model.hard_points import HardPointCar
    from drake_car.model.seat import STATE_SEAT, estimated_seat_point_m
    from drake_car.scene.car_file import read_car_file
    from drake_car.study.ride.grid import base_scene
    from drake_car.study.ride.report import seat_flag
    from pydrake.common.yaml import yaml_dump_typed
    with caplog.at_level(logging.WARNING, logger="drake_car"):
        load_scene(base=paper_scene("a_1"), scene_text=f"car_file: {CAR_FILE}")  # no ride
        assert not _said(caplog, "seat_point_m")
        for _ in range(2):
            scene = base_scene(scene_text=f"car_file: {CAR_FILE}")
    (said,) = _said(caplog, "seat_point_m")
    assert f"car_file {CAR_FILE} states no seat_point_m" in said and "[EST]" in said
    assert STATE_SEAT in said and "forward-control van" in said
    seat = borrowed.seat_point(scene)
    assert seat["source"] == "estimated"
    escort = CarParameters()
    assert seat["seat_point_m"] == estimated_seat_point_m(scene.car, escort) != escort.seat_point_m
    words = borrowed.seat_point_words(seat)
    assert "**estimated** [EST]" in words and STATE_SEAT in words and CAR_FILE in words
    assert "estimate [EST], not this car's" in seat_flag(seat)[0]
    shipped = borrowed.seat_point(base_scene())
    assert shipped["source"] == "shipped" and shipped["seat_point_m"] == [-1.25, 0.37, 0.5]
    assert "the shipped Escort's [EST]" in borrowed.seat_point_words(shipped)
    assert seat_flag(shipped) == []
    car = read_car_file(CAR_FILE)
    car.seat_point_m = [-0.10, 0.40, 0.90]
    path = tmp_path / "van.yaml"
    path.write_text(yaml_dump_typed(car, schema=HardPointCar))
    caplog.clear()
    with caplog.at_level(logging.WARNING, logger="drake_car"):
        own = borrowed.seat_point(base_scene(scene_text=f"car_file: {path}"))
    assert not _said(caplog, "seat_point_m") and own["source"] == "car_file"
    assert f"the car file's `seat_point_m` (`{path}`)" in borrowed.seat_point_words(own)
    over = base_scene(scene_text=f"{{car_file: {path}, car: {{seat_point_m: [-0.2, 0.4, 0.9]}}}}")
    assert borrowed.seat_point(over)["source"] == "scene"
