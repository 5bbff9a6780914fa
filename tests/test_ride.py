"""The ride study's pieces on the car: the seat-point channel against the body's own motion (and
a car file's seat point reaching it), the grid's scenes, the outcomes of a run, the command's
bad input."""

import dataclasses
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose
from pydrake.common.yaml import yaml_dump_typed
from pydrake.math import RollPitchYaw

from drake_car.model.hard_points import HardPointCar, frame_shift_m, from_parameters
from drake_car.model.parameters import CarParameters
from drake_car.sim.simulate import simulate
from drake_car.study.ride.analysis import OUTCOMES, outcomes
from drake_car.study.ride.grid import RideStudy, analysed_from_s, base_scene, ride_scene

ROOT = Path(__file__).resolve().parents[1]


def _short_scene(base=None):
    """Class C at 30 km/h, 0.4 s analysed, dry struts, logged every step with the chassis."""
    study = RideStudy(settle_window_s=0.2, window_s=0.4, road_length_m=60.0)
    scene = ride_scene(study, "C", 30.0, 0.2, base=base)
    timeline = dataclasses.replace(scene.manoeuvre.timeline, settle_s=0.0, speed_up_s=0.8)
    scene = dataclasses.replace(
        scene, manoeuvre=dataclasses.replace(scene.manoeuvre, timeline=timeline),
        logging=dataclasses.replace(scene.logging, record_period_s=scene.time_step_s,
                                    channels=[*scene.logging.channels, "chassis"]))
    return scene, study


@pytest.fixture(scope="module")
def short_run():
    scene, study = _short_scene()
    return scene, study, simulate(scene)


def test_seat_acceleration_is_the_seat_heights_second_difference(short_run):
    """The logged az at the seat point (the plant's body acceleration, a = a_o + α×r +
    ω×(ω×r)) against the second difference of the seat point's height from the logged pose.
    The discrete plant's acceleration at sample n is (v_n - v_{n-1})/dt and its positions
    advance with the new velocity, so the centred second difference at n equals the logged
    value at n+1 up to the rotation's own discretisation: the seat's lever (1.4 m) turns by
    ω dt per step, a relative error of order ω dt, below 1e-3 for the body's rates (< 1 rad/s)
    at 1 ms; the bound is ten times that."""
    scene, _, run = short_run
    h = run.history
    dt = scene.time_step_s
    r = np.asarray(scene.car.seat_point_m)
    assert list(r) == [-1.25, 0.37, 0.50], "the shipped car's seat point"
    height = np.array([z + (RollPitchYaw(a, b, c).ToRotationMatrix().matrix() @ r)[2]
                       for z, a, b, c in zip(h["z_m"], h["roll_rad"], h["pitch_rad"],
                                             h["yaw_rad"])])
    second = (height[2:] - 2 * height[1:-1] + height[:-2]) / dt ** 2
    logged = np.asarray(h["az_seat_mps2"])[2:]
    moving = np.asarray(h["t"])[1:-1] > 0.5
    scale = np.sqrt(np.mean(logged[moving] ** 2))
    assert scale > 0.1, "the road must shake the body"
    assert np.sqrt(np.mean((second[moving] - logged[moving]) ** 2)) < 1e-2 * scale


# How far forward the car file moves the seat point (m).
SEAT_SHIFT_M = 1.0


def test_a_car_file_s_seat_point_reaches_the_channel(short_run, tmp_path):
    """The shipped car as a car file (``from_parameters``) whose seat point lies SEAT_SHIFT_M
    ahead of the Escort's: the body moves as the Escort's (the seat point is no part of the
    dynamics), and the seat's vertical acceleration differs by the rigid body's lever Δx
    along the body's x: a_2 - a_1 = Δx (-cos θ cos φ α_y + sin θ (ω_y² + ω_z²)) (θ pitch, φ
    roll, α_y the logged pitch acceleration, ω_y from the logged pitch's centred difference,
    ω_z the yaw rate), up to the terms in sin φ and ω_x (the roll, < 1e-13 rad on this run's
    road) and the difference's O(dt²) error: below 1e-6 of the lever's RMS; the bound is
    1e-4 (the lever's cos θ alone would leave 3e-4: the point must be where the file puts
    it, not merely near)."""
    scene, _, run = short_run
    car = from_parameters(CarParameters())
    car.seat_point_m = list(np.asarray(scene.car.seat_point_m) - frame_shift_m(car)
                            + [SEAT_SHIFT_M, 0.0, 0.0])
    path = tmp_path / "escort_forward_seat.yaml"
    path.write_text(yaml_dump_typed(car, schema=HardPointCar))
    moved, _ = _short_scene(base_scene(scene_text=f"car_file: {path}"))
    assert_allclose(np.asarray(moved.car.seat_point_m) - scene.car.seat_point_m,
                    [SEAT_SHIFT_M, 0.0, 0.0], atol=1e-15)
    h1, h2 = run.history, simulate(moved).history
    assert_allclose(h2["pitch_acc_radps2"], h1["pitch_acc_radps2"], rtol=1e-9, atol=1e-9)
    pitch, roll = np.asarray(h1["pitch_rad"]), np.asarray(h1["roll_rad"])
    pitch_rate = np.gradient(pitch, scene.time_step_s)
    lever = SEAT_SHIFT_M * (-np.cos(pitch) * np.cos(roll) * np.asarray(h1["pitch_acc_radps2"])
                            + np.sin(pitch) * (pitch_rate ** 2
                                               + np.asarray(h1["yaw_rate_radps"]) ** 2))
    change = np.asarray(h2["az_seat_mps2"]) - np.asarray(h1["az_seat_mps2"])
    moving = np.asarray(h1["t"]) > 0.5
    scale = np.sqrt(np.mean(lever[moving] ** 2))
    assert scale > 0.1, "the road must pitch the body"
    assert np.sqrt(np.mean((change - lever)[moving] ** 2)) < 1e-4 * scale


def test_outcomes_of_a_run(short_run):
    scene, study, run = short_run
    out = outcomes(run.history, analysed_from_s(scene, study))
    assert set(out) == set(OUTCOMES)
    assert all(np.isfinite(v) for v in out.values()), out
    assert out["aw_seat_mps2"] > 0 and 0 < out["dlc_front"] < 1, out
    assert 0 <= out["stick_left"] <= 1 and out["friction_mean_N"] > 0, out


def test_grid_scenes_share_the_road_and_differ_in_the_step():
    study = RideStudy(road_length_m=300.0)
    coarse = ride_scene(study, "B", 60.0, 0.0)
    fine = ride_scene(study, "B", 60.0, 0.0, half=True)
    dry = ride_scene(study, "B", 60.0, 0.3)
    assert coarse.road == fine.road == dry.road
    assert_allclose(fine.time_step_s, coarse.time_step_s / 2)
    assert coarse.friction is None and dry.friction.law.mu_d == pytest.approx(0.225)
    assert dry.car.front.strut_damping_Nspm == coarse.car.front.strut_damping_Nspm
    paper = ride_scene(dataclasses.replace(study, strut="paper"), "B", 60.0, 0.3)
    assert paper.car.front.strut_damping_Nspm == 0.0
    c = ride_scene(study, "C", 60.0, 0.0)
    assert_allclose(np.asarray(c.road.z_m), 2 * np.asarray(coarse.road.z_m))  # one shape


@pytest.mark.parametrize("args, names", [(["--classes", "F"], "--classes"),
                                         (["--strut", "oily"], "--strut"),
                                         (["--speeds", "fast"], "--speeds")])
def test_bad_input_is_one_line_and_status_2(tmp_path, args, names):
    out = tmp_path / "out"
    result = subprocess.run([sys.executable, str(ROOT / "experiments" / "ride.py"), "--out",
                             str(out), *args], capture_output=True, text=True,
                            env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    assert result.returncode == 2, result.stderr
    assert len(result.stderr.strip().splitlines()) == 1 and names in result.stderr
    assert not out.exists()


@pytest.mark.slow
def test_the_command_finds_the_sweeps_runs_by_their_keys(tmp_path):
    """The ride command reads back each finished run from the sweep's folder, named by the
    run's key (the scene, the files it reads, the code), not by the scene's hash alone."""
    from drake_car.commands.ride import finished_runs
    from drake_car.sweep.runner import run_sweep
    study = RideStudy(settle_window_s=0.2, window_s=0.2, road_length_m=40.0)
    scene = ride_scene(study, "A", 30.0, 0.0)
    timeline = dataclasses.replace(scene.manoeuvre.timeline, settle_s=0.0, speed_up_s=0.3)
    scene = dataclasses.replace(scene, manoeuvre=dataclasses.replace(scene.manoeuvre,
                                                                     timeline=timeline))
    result = run_sweep({"short": scene}, tmp_path / "sweep", workers=1, progress=False)
    assert result["ok"] == 1, result
    found = finished_runs(tmp_path / "sweep", {"short": scene})
    assert list(found) == ["short"]
    assert found["short"].history["t"][-1] == pytest.approx(scene.end_time_s, abs=0.01)
