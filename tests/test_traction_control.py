"""The open differential's clamp within the tyres' grip (``OpenDifferential.torque_within_grip``):
a launch the tyres' grip limits runs at the speed it was planned for, the wheels below the
tyre's peak slip; without it a lagging speed controller spins them up without bound. The car: a made-up 1500 kg
rear-drive sedan (tests/data/rwd_sedan.yaml) with a 3500 N m drive [EST] on Chrono's
Generic_Pac02Tire (its grip falls from 0.97 at κ 0.116 to 0.52 sliding), a newcomer's case."""

import dataclasses

import numpy as np
import pytest

from drake_car.law.tyre.magic_formula import MagicFormulaTyre
from drake_car.model.loading import tir_path
from drake_car.scene.launch import drive_torque_limit_Nm, launch_limits, peak
from drake_car.scene.load import load_scene
from drake_car.scene.raw import SceneError
from drake_car.scene.manoeuvre_targets import SPEED_TOLERANCE_KPH, speed_at_place_a_mps
from drake_car.sim.simulate import simulate

SEDAN = ("{name: sedan, car_file: tests/data/rwd_sedan.yaml, "
         "tyres: !MagicFormula {tir_file: tests/data/tyres/Generic_Pac02Tire.tir}, "
         "drive: !OpenDifferential {max_wheel_torque_Nm: 3500.0%s}, "
         "manoeuvre: !Straight {}, simulator: {end_time_s: 5.0}}")


def _run(extra=""):
    scene = load_scene(scene_text=SEDAN % extra)
    run = simulate(scene)
    h = run.history
    kappa = np.maximum(h["kappa_rl"], h["kappa_rr"])
    speed = speed_at_place_a_mps(h, scene.manoeuvre.timeline)
    return scene, float(np.max(kappa)), 3.6 * speed


def test_a_grip_limited_launch_runs_at_its_speed_below_the_peak_slip():
    scene, kappa, speed_kph = _run()
    limits = launch_limits(scene)
    assert limits.limited_by == "the rear tyres' grip"
    assert scene.manoeuvre.timeline.speed_up_s == 3.0  # planned followable at that grip
    # The clamp at 0.9 of the tyres' peak grip (scene.launch.TRACTION_MARGIN) keeps the wheels
    # short of the peak slip; the speed within the manoeuvre's own tolerance.
    tyre = MagicFormulaTyre.from_file(tir_path(scene.tyres.tir_file))
    assert kappa < peak(tyre, limits.driven_load_N / 2)[0], kappa
    assert abs(speed_kph - 60.0) <= SPEED_TOLERANCE_KPH, speed_kph


def test_without_it_the_wheels_spin_up_and_the_car_misses_its_speed():
    scene, kappa, speed_kph = _run(", torque_within_grip: false")
    assert drive_torque_limit_Nm(scene) == 3500.0
    # Past the peak the tyre pushes its sliding force only, below the clamp: κ runs away (1:
    # the wheel turns twice as fast as it rolls) and the launch falls far short.
    assert kappa > 1.0, kappa
    assert speed_kph < 60.0 - 5 * SPEED_TOLERANCE_KPH, speed_kph


def test_the_clamp_is_the_drive_s_or_the_tyres_whichever_is_less():
    escort = load_scene("scenes/paper_study.yaml", child="a_3")
    # The Escort's launch is limited by its drive (1740 N m < its tyres' 1952 N m): unchanged.
    assert launch_limits(escort).limited_by == "the drive's torque"
    assert drive_torque_limit_Nm(escort) == escort.drive.max_wheel_torque_Nm == 1740.0
    sedan = load_scene(scene_text=SEDAN % "")
    limits = launch_limits(sedan)
    grip = limits.traction_accel_mps2 * limits.controller_mass_kg * limits.rolling_radius_m
    assert drive_torque_limit_Nm(sedan) == pytest.approx(grip) and grip < 3500.0


def test_a_rev_limit_unstable_at_the_step_is_refused():
    # 4 I / K with I = 1.0 kg m²: a governor gain of 5000 N m s/rad is stable below 0.8 ms;
    # the step is 1 ms.
    with pytest.raises(SceneError) as found:
        load_scene(scene_text=SEDAN % ", governor_gain_Nm_per_radps: 5000.0")
    text = str(found.value)
    assert "drive.governor_gain_Nm_per_radps" in text and "4 I / K" in text, text
    assert "a gain of at most 4000 N m s/rad" in text, text


def test_a_failed_calibration_says_the_speed_it_ran_at():
    # What a calibration that could not converge reports (its last run's numbers as the
    # sedan without the clamp made them: 38.9 km/h at place a, spinning its rear wheels).
    from drake_car.sim.lane_change_calibration import _last_words, calibration_scene
    scene = load_scene("scenes/paper_study.yaml", child="a_1")
    calibrating = calibration_scene(scene)
    last = {"amplitude_m": 0.00875, "second_lobe": 2.0, "shift_m": 4.46,
            "heading_change_deg": 7.67, "speed_at_place_a_kph": 38.9}
    text = _last_words(last, calibrating)
    assert "4.46 m sideways (asked 3.7 m)" in text and "+7.67 deg" in text, text
    assert "at 38.9 km/h at place a (asked 60 km/h): the car did not reach its speed" in text
    assert "drive.torque_within_grip" in text
    at_speed = _last_words(dict(last, speed_at_place_a_kph=59.6), calibrating)
    assert "did not reach" not in at_speed and "at 59.6 km/h" in at_speed, at_speed


def test_every_report_says_a_drive_clamped_to_the_tyres_grip():
    from drake_car.scene.borrowed import drive_limit, drive_limit_words
    sedan = load_scene(scene_text=SEDAN % "")
    words = drive_limit_words(drive_limit(sedan))
    assert f"clamped to {drive_torque_limit_Nm(sedan):.0f} N m" in words, words
    assert "drive.torque_within_grip" in words
    escort = load_scene("scenes/paper_study.yaml", child="a_3")
    assert "clamped" not in drive_limit_words(drive_limit(escort))
