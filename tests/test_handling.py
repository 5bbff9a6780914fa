"""Handling metrics (ISO 4138 ramp steer, ISO 7401 step steer) on synthetic signals with known
answers; the understeer budget on a short real ramp (its terms sum to the measured gradient,
the named ones within 10 %); the cross-check against CommonRoad's multi-body model runs and
keeps its signs; the handling experiment end to end on a short timeline."""

import dataclasses
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from drake_car.data import resource
from drake_car.law.tyre.magic_formula import MagicFormulaTyre, magic_formula
from drake_car.model.geometry import whole_car_cog_to_front_m
from drake_car.model.loading import tir_path
from drake_car.scene.load import load_scene
from drake_car.sim.simulate import simulate
from drake_car.study.handling import crosscheck
from drake_car.study.handling.measures import (
    DEG_PER_G,
    kinematic_steer_rad,
    single_track,
    single_track_response,
    steady_state,
    step_response,
    step_steer,
)
from drake_car.study.handling.understeer import NAMED, understeer_budget

ROOT = Path(__file__).resolve().parents[1]
TYRE = MagicFormulaTyre.from_file(tir_path("tyres/pacejka2006_205_60R15.tir"))
# A linear rack: 0.46 deg of road-wheel angle per mm, the same both sides.
STEERING = {"rack_m": [-0.07, 0.07], "steer_left_deg": [-32.2, 32.2],
            "steer_right_deg": [-32.2, 32.2]}


def synthetic_ramp(*, speed=16.0, wheelbase=2.4, cog=0.9, k_deg_per_g=1.0, roll=6.0,
                   sideslip=-1.5, rack_force=4000.0, rate=0.25):
    """A history of a perfectly linear ramp: a_y rises at ``rate`` m/s² per s from t = 2 s at
    constant speed, with the given gradients (deg/g, N/g) at the CoG ``cog`` m behind the
    body origin."""
    t = np.arange(0.0, 20.0, 0.01)
    ay = rate * np.clip(t - 2.0, 0.0, None)
    r = ay / speed
    steer = wheelbase * r / speed + k_deg_per_g / DEG_PER_G * ay
    beta_g = sideslip / DEG_PER_G * ay
    vx, vy_o = speed * np.cos(beta_g), speed * np.sin(beta_g) + cog * r
    rdot = np.gradient(r, t)
    return {"t": t, "phase": ["II" if x < 2.0 else "III" for x in t],
            "rack_m": steer / math.radians(32.2) * 0.07,
            "yaw_rate_radps": r, "speed_mps": np.hypot(vx, vy_o),
            "sideslip_rad": np.arctan2(vy_o, vx), "ay_mps2": ay + cog * rdot,
            "roll_rad": roll / DEG_PER_G * ay, "rack_force_N": rack_force / 9.81 * ay,
            "steer_fl_rad": steer, "steer_fr_rad": steer}, steer


def test_steady_state_gradients_of_a_linear_ramp():
    h, steer = synthetic_ramp()
    rack_steer = kinematic_steer_rad(h["rack_m"], STEERING)
    np.testing.assert_allclose(rack_steer, steer, atol=1e-12)
    m = steady_state(h, steer_rad=rack_steer, wheel_steer_rad=steer, wheelbase_m=2.4,
                     cog_offset_m=0.9, ay_range=(0.5, 3.0))
    assert m["understeer_gradient_deg_per_g"] == pytest.approx(1.0, abs=1e-6)
    assert m["understeer_gradient_wheel_deg_per_g"] == pytest.approx(1.0, abs=1e-6)
    assert m["roll_gradient_deg_per_g"] == pytest.approx(6.0, abs=1e-6)
    assert m["sideslip_gradient_deg_per_g"] == pytest.approx(-1.5, abs=1e-4)
    assert m["rack_force_gradient_N_per_g"] == pytest.approx(4000.0, rel=1e-9)
    assert m["speed_mps"] == pytest.approx(16.0, rel=1e-6)
    assert m["ay_range_mps2"] == [0.5, 3.0]
    assert m["t_range_s"][0] == pytest.approx(4.0, abs=0.011)
    # The yaw-rate gain of a car with K = 1 deg/g: V / (L + K V²).
    k = 1.0 / DEG_PER_G
    assert m["yaw_rate_gain_per_s"] == pytest.approx(16.0 / (2.4 + k * 16.0 ** 2), rel=1e-6)


def test_step_response_of_a_first_order_lag():
    """A steer ramp of T = 0.15 s into a first-order lag τ = 0.1 s: 90 % at
    t - t0 = τ ln(10 (τ/T)(e^(T/τ) - 1)), 50 % steer at t0 + T/2, no overshoot."""
    tau, rise, t0 = 0.1, 0.15, 1.0
    t = np.arange(0.0, 4.0, 0.001)
    s = np.clip(t - t0, 0.0, None)
    steer = np.clip(s / rise, 0.0, 1.0)
    during = (s - tau * (1 - np.exp(-s / tau))) / rise
    after = 1 - tau / rise * (np.exp(rise / tau) - 1) * np.exp(-s / tau)
    y = 2.5 * np.where(s < rise, during, after)
    r = step_response(t, 0.04 * steer, y, steady_window_s=0.5)
    expected = tau * math.log(10 * tau / rise * (math.exp(rise / tau) - 1)) - rise / 2
    assert r["response_time_s"] == pytest.approx(expected, abs=1e-5)
    assert r["steer_50pct_s"] == pytest.approx(t0 + rise / 2, abs=1e-9)
    assert r["overshoot_pct"] == 0.0 and r["peak_response_time_s"] is None
    assert r["gain"] == pytest.approx(2.5 / 0.04, rel=1e-6)


def test_step_response_of_an_underdamped_second_order_system():
    """An (almost) ideal step into ζ = 0.5, ω = 10 rad/s: overshoot exp(-πζ/√(1-ζ²)), peak at
    π/ω_d, 90 % where the analytic response crosses it; negative responses work the same."""
    zeta, omega, t0, rise = 0.5, 10.0, 0.5, 0.002
    wd = omega * math.sqrt(1 - zeta ** 2)
    t = np.arange(0.0, 4.0, 0.0005)
    steer = np.clip((t - t0) / rise, 0.0, 1.0)
    s = np.clip(t - (t0 + rise / 2), 0.0, None)
    y = 1 - np.exp(-zeta * omega * s) * (np.cos(wd * s) + zeta / math.sqrt(1 - zeta ** 2)
                                         * np.sin(wd * s))
    fine = np.linspace(0.0, 1.0, 200001)
    y_fine = 1 - np.exp(-zeta * omega * fine) * (
        np.cos(wd * fine) + zeta / math.sqrt(1 - zeta ** 2) * np.sin(wd * fine))
    t90 = fine[np.argmax(y_fine >= 0.9)]
    for sign in (1.0, -1.0):
        r = step_response(t, steer, sign * y, steady_window_s=0.5)
        assert r["overshoot_pct"] == pytest.approx(
            100 * math.exp(-math.pi * zeta / math.sqrt(1 - zeta ** 2)), abs=0.01)
        assert r["peak_response_time_s"] == pytest.approx(math.pi / wd, abs=6e-4)
        assert r["response_time_s"] == pytest.approx(t90, abs=1e-4)
        assert math.copysign(1, r["peak"]) == sign


def test_single_track_model_and_its_response():
    st = single_track(mass_kg=1200.0, wheelbase_m=2.5, cog_to_front_m=1.0,
                      front_stiffness=80e3, rear_stiffness=100e3, speed_mps=20.0)
    k = 1200.0 / 2.5 * (1.5 / 80e3 - 1.0 / 100e3)
    assert st["understeer_gradient_deg_per_g"] == pytest.approx(k * DEG_PER_G)
    assert st["yaw_rate_gain_per_s"] == pytest.approx(20.0 / (2.5 + k * 400.0))
    t = np.arange(0.0, 5.0, 0.005)
    steer = 0.02 * np.clip((t - 0.5) / 0.1, 0.0, 1.0)
    for sigma in (0.0, 0.5):
        r = single_track_response(t, steer, speed_mps=20.0, mass_kg=1200.0,
                                  yaw_inertia_kgm2=1500.0, cog_to_front_m=1.0,
                                  wheelbase_m=2.5, front_stiffness=80e3, rear_stiffness=100e3,
                                  relaxation_length_m=sigma)
        assert r["yaw_rate"][-1] / 0.02 == pytest.approx(st["yaw_rate_gain_per_s"], rel=1e-4)
        assert r["ay"][-1] == pytest.approx(20.0 * r["yaw_rate"][-1], rel=1e-4)


SHORT_RAMP = ("manoeuvre: !RampSteer {rack_m: 0.006, timeline: {settle_s: 0.3, speed_up_s: 4.0,"
              " straight_s: 1.0, steer_s: 6.0, calm_s: 0.0}}\n"
              "logging: {channels: [chassis, steering, tyres]}")


@pytest.fixture(scope="module")
def short_ramp():
    scene = load_scene(resource("scenes/handling.yaml"), child="steady_state",
                       scene_text=SHORT_RAMP)
    return simulate(scene)


def test_understeer_budget_sums_to_the_measured_gradient(short_ramp):
    from drake_car.model.kinematics_sweep import run_kinematics_sweep
    h, car = short_ramp.history, short_ramp.scene.car
    steering = run_kinematics_sweep(car, points=9).steering
    rack_steer = kinematic_steer_rad(h["rack_m"], steering)
    b = understeer_budget(h, car, TYRE, kinematic_steer_rad=rack_steer, ay_range=(0.5, 3.0),
                          max_samples=80)
    total = sum(r["gradient_deg_per_g"] for r in b["rows"])
    assert total == pytest.approx(b["measured_deg_per_g"], abs=1e-9)  # telescoping: exact
    named = sum(r["gradient_deg_per_g"] for r in b["rows"] if r["key"] in NAMED)
    assert named == pytest.approx(b["named_sum_deg_per_g"])
    assert abs(named - b["measured_deg_per_g"]) <= 0.1 * abs(b["measured_deg_per_g"])
    # Against the metric of the whole window: the budget's decimated samples fit the same.
    m = steady_state(h, steer_rad=rack_steer, wheelbase_m=car.wheelbase_m,
                     cog_offset_m=whole_car_cog_to_front_m(car),
                     mass_kg=car.mass.total_mass_kg, ay_range=(0.5, 3.0))
    assert b["measured_deg_per_g"] == pytest.approx(m["understeer_gradient_deg_per_g"],
                                                    rel=0.02)
    # The tyres' term is the single-track model at the static loads.
    g = {r["key"]: r["gradient_deg_per_g"] for r in b["rows"]}
    assert g["tyres"] == pytest.approx(b["single_track_deg_per_g"], rel=1e-6)
    assert g["compliance"] == 0.0
    assert b["measured_deg_per_g"] > 0  # the car understeers
    print(f"budget on the short ramp: measured {b['measured_deg_per_g']:.3f} deg/g, named "
          f"{named:.3f}, remainders {b['remainder_pct']:+.1f} %")


def commonroad_or_skip():
    ok, why = crosscheck.available()
    if not ok:
        if os.environ.get("CI"):
            pytest.fail(f"the cross-check must run in CI: {why}")
        pytest.skip(why)


def test_crosscheck_runs_in_our_signs():
    """A left-turn step of 1 deg at 60 km/h: CommonRoad's MB turns left in our (ISO) signs,
    rolls out of the turn (right side down, positive), follows the steer and holds the speed,
    and its yaw-rate gain is near its own single-track model's."""
    commonroad_or_skip()
    p = crosscheck.parameters()
    t = np.arange(0.0, 3.0, 0.002)
    steer = math.radians(1.0) * np.clip((t - 0.2) / 0.15, 0.0, 1.0)
    mb = crosscheck.simulate_mb(t, steer, 16.667, p=p)
    for key in ("yaw_rate_radps", "ay_mps2", "roll_rad", "sideslip_rad", "speed_mps"):
        assert np.all(np.isfinite(mb[key])), key
    assert np.max(np.abs(mb["steer_rad"] - steer)) < math.radians(0.01)
    end = t >= 2.5
    r, ay, roll = (float(np.mean(mb[k][end])) for k in ("yaw_rate_radps", "ay_mps2", "roll_rad"))
    assert r > 0 and ay > 0 and roll > 0
    assert ay == pytest.approx(16.667 * r, rel=0.01)
    assert np.max(np.abs(mb["speed_mps"][end] - 16.667)) < 0.05
    gain = crosscheck.mb_single_track(p, 16.667)["yaw_rate_gain_per_s"]
    assert r / math.radians(1.0) == pytest.approx(gain, rel=0.05)
    metrics = step_steer(mb | {"phase": ["II" if x < 0.2 else "III" for x in t]},
                         steer_rad=mb["steer_rad"], cog_offset_m=0.0)
    assert 0.1 < metrics["yaw_rate"]["response_time_s"] < 0.3
    # Its roll model by hand reproduces its roll in the step within 10 %.
    assert math.degrees(roll) / (ay / 9.81) == pytest.approx(
        crosscheck.roll_model(p)["roll_gradient_deg_per_g"], rel=0.1)


def test_a_car_of_commonroad_s_third_set_is_cross_checked_against_it():
    """A newcomer's VW Vanagon (CommonRoad's set 3, its mass and front track) was told
    CommonRoad had no parameter set of their car."""
    import dataclasses

    from drake_car.model.parameters import CarParameters
    commonroad_or_skip()
    p = crosscheck.parameters(3)
    car = CarParameters()
    car = dataclasses.replace(car, mass=dataclasses.replace(car.mass, total_mass_kg=float(p.m)),
                              front=dataclasses.replace(car.front, track_m=float(p.T_f)))
    assert crosscheck.parameter_set_of(car) == (3, "VW Vanagon")
    assert crosscheck.parameter_set_of(CarParameters()) == (1, "Ford Escort")


def test_understeer_reconciliation_columns_sum_to_each_gradient():
    rows = [{"key": k, "gradient_deg_per_g": v} for k, v in (
        ("load_transfer", 0.1), ("aligning", 0.3), ("camber", -0.01), ("drive_yaw", 0.05),
        ("drive_lateral", -0.01), ("drive_combined", -0.01), ("steer_projection", 0.02))]
    chain = [{"understeer_gradient_deg_per_g": k} for k in (0.155, 0.0, 0.51, 0.52, 0.52, 0.52)]
    rec = crosscheck.understeer_reconciliation(ours_wheel_k=1.02, budget_rows=rows, mb_k=0.27,
                                               mb_k_no_camber=0.17, chain=chain)
    assert sum(r["ours"] for r in rec) == pytest.approx(1.02)
    assert sum(r["mb"] or 0.0 for r in rec) == pytest.approx(0.27)


SHORT_SCENES = """
_timeline: &timeline {settle_s: 0.3, speed_up_s: 4.0, straight_s: 1.0, speed_kph: 60.0}
steady_state:
  name: steady_state
  manoeuvre: !RampSteer {rack_m: 0.005, timeline: {<<: *timeline, steer_s: 5.0, calm_s: 0.2}}
step_steer:
  name: step_steer
  manoeuvre: !StepSteer {rack_m: 0.004, rise_s: 0.15,
                         timeline: {<<: *timeline, steer_s: 2.0, calm_s: 0.0}}
  logging: {record_period_s: 0.005}
"""


@pytest.mark.slow
def test_handling_experiment_end_to_end(tmp_path):
    scenes = tmp_path / "short.yaml"
    scenes.write_text(SHORT_SCENES)
    out = tmp_path / "handling"
    result = subprocess.run(
        [sys.executable, "experiments/handling.py", "--out", str(out), "--scene", str(scenes),
         "--ay_range", "0.5,2.5"], cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr[-3000:]
    for name in ("report.md", "summary.json", "budget.csv", "budget.png",
                 "steady_state/steady_state.csv", "steady_state/steady_state.png",
                 "steady_state/history.csv", "step_steer/step_steer.json",
                 "step_steer/step_steer.png"):
        assert (out / name).stat().st_size > 0, name
    summary = json.loads((out / "summary.json").read_text())
    budget = summary["budget"]
    assert abs(budget["remainder_pct"]) <= 10
    assert summary["steady_state"]["metrics"]["ay_range_mps2"] == [0.5, 2.5]
    report = (out / "report.md").read_text()
    assert "## Understeer budget" in report and "## Step steer (ISO 7401)" in report
    if crosscheck.available()[0]:
        assert (out / "crosscheck" / "crosscheck_ramp.png").stat().st_size > 0
        assert "CommonRoad MB" in report


SEDAN_TIR = ROOT / "tests" / "data" / "tyres" / "Sedan_Pac02Tire.tir"


def test_the_shipped_tyre_s_scenes_differ_only_in_the_tyre_file():
    from pydrake.common.yaml import yaml_dump_typed

    from drake_car.scene.load import load_scene_file
    from drake_car.scene.scene import DEFAULT_TIR, Scene
    from drake_car.study.handling import tyre_section
    scenes = load_scene_file(resource("scenes/handling.yaml"),
                             f"{{tyres: !MagicFormula {{tir_file: {SEDAN_TIR}, "
                             "slip: {relaxation_lengths_from_file: true}}}")
    assert not tyre_section.is_shipped(scenes["steady_state"])
    shipped, note = tyre_section.shipped_scenes(scenes)
    for name, scene in shipped.items():
        assert tyre_section.is_shipped(scene)
        assert scene.tyres.tir_file == DEFAULT_TIR
        # The book's file has no relaxation data: the shipped runs take tyres.slip's lengths.
        assert not scene.tyres.slip.relaxation_lengths_from_file
        back = dataclasses.replace(scene, tyres=scenes[name].tyres)
        assert yaml_dump_typed(back, schema=Scene) == yaml_dump_typed(scenes[name], schema=Scene)
    assert "no relaxation data" in note and "0.15 m, 0.45 m" in note


@pytest.mark.slow
def test_handling_on_a_chrono_tyre_reports_the_tyre_and_what_changed(tmp_path):
    """The handling command on Chrono's sedan tyre (PAC2002): its tyre's files and section, the
    shipped tyre's runs and the comparison, whose numbers are the analysis' own."""
    scenes = tmp_path / "short.yaml"
    scenes.write_text(SHORT_SCENES)
    out = tmp_path / "sedan"
    result = subprocess.run(
        [sys.executable, "-m", "drake_car.commands.handling", "--out", str(out), "--scene",
         str(scenes), "--ay_range", "0.5,2.5", "--no_crosscheck", "--scene_text",
         f"{{tyres: !MagicFormula {{tir_file: {SEDAN_TIR}}}}}"],
        cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr[-3000:]
    for name in ("tyre/curves.csv", "tyre/summary.txt", "tyre/fy_alpha.png",
                 "tyre/stiffness_load.png", "shipped_tyre/steady_state/history.csv",
                 "shipped_tyre/step_steer/scene.yaml"):
        assert (out / name).stat().st_size > 0, name
    assert "pacejka2006_205_60R15.tir" in (out / "shipped_tyre/steady_state/scene.yaml").read_text()
    assert "Sedan_Pac02Tire.tir" in (out / "steady_state/scene.yaml").read_text()
    report = (out / "report.md").read_text()
    assert "## The tyre the car runs on" in report and "**PAC2002**" in report
    assert "## What changed against the shipped tyre" in report
    summary = json.loads((out / "summary.json").read_text())
    tyre, rows = summary["tyre"], {r["quantity"]: r for r in summary["tyre_change"]["rows"]}
    ss = summary["steady_state"]
    # "this tyre" is this run's analysis; the single track's C_f is two tyres at the static
    # front wheel load of the tyre section.
    k = rows["understeer gradient, δ from the rack"]
    assert k["this"] == ss["metrics"]["understeer_gradient_deg_per_g"]
    assert k["difference"] == pytest.approx(k["this"] - k["shipped"], abs=1e-12)
    c_f = rows["single track: front axle C_f"]["this"]
    assert c_f == pytest.approx(-2 * tyre["at"]["front"]["cornering_stiffness_N_per_rad"],
                                rel=1e-12)
    sedan = MagicFormulaTyre.from_file(SEDAN_TIR)
    assert rows["single track: front axle C_f"]["shipped"] == pytest.approx(
        -2 * magic_formula(TYRE, tyre["at"]["front"]["fz_N"], 0, 0, 0, 16.7).cornering_stiffness,
        rel=1e-12)
    assert tyre["at"]["FNOMIN"]["fz_N"] == sedan.FNOMIN
    assert tyre["load_note"] is None and not tyre["shipped"]
    for r in rows.values():
        assert r["shipped"] is None or math.isfinite(r["shipped"]), r


def test_commonroad_s_model_breaking_down_ends_its_series_not_the_study(monkeypatch):
    """CommonRoad's MB divides a wheel's slip by its speed, zero when the wheel rolls backwards
    (the car spun in it): on a VW Vanagon's ramp steer it raised ZeroDivisionError at 33.7 s
    and the handling command ended in a traceback. Now its series stops there (NaN after, as
    far as it ran kept) and the study goes on; the report says where."""
    commonroad_or_skip()
    import vehiclemodels.vehicle_dynamics_mb as mb_module
    from drake_car.study.handling import report as handling_report
    real, dt, speed = mb_module.vehicle_dynamics_mb, 1e-3, 16.667
    where = speed * (4.0 + 0.5)  # its x after simulate_mb's 4 s of settling and 0.5 s more

    def breaking(x, u, p):  # its own model, until the car has driven that far
        if x[0] > where:
            raise ZeroDivisionError("float division by zero")
        return real(x, u, p)
    monkeypatch.setattr(mb_module, "vehicle_dynamics_mb", breaking)
    t = np.linspace(0.0, 1.0, 101)
    mb = crosscheck.simulate_mb(t, np.radians(1.0) * (t > 0.2), np.full_like(t, speed),
                                p=crosscheck.parameters(3), dt=dt)
    assert mb["broke_down_s"] == pytest.approx(0.5, abs=0.01)  # its speed held within 2 %
    ran = t <= mb["broke_down_s"]
    for channel in ("yaw_rate_radps", "ay_mps2", "roll_rad", "speed_mps"):
        assert np.all(np.isfinite(mb[channel][ran])) and np.all(np.isnan(mb[channel][~ran]))
    assert mb["broke_down_why"].startswith("ZeroDivisionError")
    said = handling_report._broke_down_lines({"broke_down": {"steady_state": {
        "t_s": 33.68, "steer_deg": 5.18, "ay_mps2": 5.75, "why": mb["broke_down_why"]}}})
    assert "could not go on** in the ramp steer at 33.68 s" in said[0]
    assert "the car spun in it" in said[0]
    assert handling_report._diff(1.0, float("nan")) is None
    # A step steer it did not finish has no characteristics, not a 0 % overshoot.
    from drake_car.study.handling.measures import step_response
    tail = np.where(t > 0.5, np.nan, np.radians(1.0) * (t > 0.2))
    stopped = step_response(t, np.radians(1.0) * (t > 0.2), tail)
    assert math.isnan(stopped["overshoot_pct"]) and math.isnan(stopped["steady"])
