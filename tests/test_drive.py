"""The car drives: straight, the paper's lane change (cases a and b), steady cornering."""

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from conftest import car_scene, paper_scene
from drake_car.data import resource
from drake_car.law.magic_formula import MagicFormulaTyre, magic_formula
from drake_car.model.parameters import GRAVITY_MPS2, CarParameters
from drake_car.scene.manoeuvres import Timeline
from drake_car.sim.simulate import simulate
from drake_car.study.calibration import lane_change_metrics

TIMELINE = Timeline()
TARGET_MPS = 60 / 3.6


def test_straight_run_keeps_its_line_and_speed():
    run = simulate(car_scene("straight", "logging: {record_period_s: 0.05}"))
    h = run.history
    assert np.all(np.isfinite(h["y_m"])) and h["t"][-1] == pytest.approx(10.0)
    assert np.max(np.abs(h["y_m"])) < 0.05
    assert np.max(np.abs(np.degrees(h["yaw_rad"]))) < 0.5
    # 60 km/h reached 3 s after the speed-up began and held; the prescribed wheel speed is
    # reached up to the tyre's longitudinal slip at cruise (rolling resistance over the slip
    # stiffness, ~0.1 %) and the effective rolling radius estimate (R0 - δ/3): 1 %.
    reached = h["t"] >= TIMELINE.settle_s + TIMELINE.speed_up_s + 0.5
    assert_allclose(h["speed_mps"][reached], TARGET_MPS, rtol=0.01)
    # Cruising near a balance is where SAP would return its guess (about 300 steps after
    # 9.2 s at 1 ms without the pacer, systems/sap_pacer.py): with it, none.
    assert run.steps >= 9999 and run.frozen_sap_steps == 0


@pytest.fixture(scope="module")
def lane_changes():
    end = TIMELINE.boundaries()[2] + 0.6
    text = f"simulator: {{end_time_s: {end}}}\nlogging: {{record_period_s: 0.02}}"
    return {case: simulate(paper_scene(f"{case}_1", text)).history for case in ("a", "b")}


def test_lane_change_shifts_the_track_and_ends_parallel(lane_changes):
    m = lane_change_metrics(lane_changes["a"], TIMELINE)
    assert m["shift_m"] == pytest.approx(3.7, abs=0.05)
    assert abs(m["heading_change_deg"]) < 0.5


def test_cases_a_and_b_mirror_each_other(lane_changes):
    a, b = lane_changes["a"], lane_changes["b"]
    assert_allclose(a["y_m"], -b["y_m"], atol=0.02 * 3.7)
    assert_allclose(np.degrees(a["yaw_rad"]), -np.degrees(b["yaw_rad"]), atol=0.5)
    assert lane_change_metrics(b, TIMELINE)["shift_m"] == pytest.approx(-3.7, abs=0.05)


def test_steady_cornering_understeer_gradient():
    """A slow rack ramp at 60 km/h (!RampSteer); K = d(δ - L r / V)/d a_y over
    a_y = 0.5 ... 2.5 m/s², δ the road wheels' mean angle to the body.

    Expected sign: understeer (K > 0). The tyres alone (bicycle model with the Magic Formula's
    cornering stiffness at the static corner loads) give
        K_tyre = m_f / (2 C_f) - m_r / (2 C_r) ≈ 0.5 deg/g > 0
    for this front-heavy car (62 % on the front axle, the tyre's load sensitivity). Expected
    size: production front-drive cars are tuned to understeer by a few deg/g; K must lie
    between K_tyre and 8 deg/g."""
    scene = paper_scene("a_1", "manoeuvre: !RampSteer {rack_m: 0.005, timeline: "
                               "{straight_s: 0.5, steer_s: 5.0, calm_s: 0.0}}\n"
                               "logging: {record_period_s: 0.02}")
    h = simulate(scene).history
    start = scene.manoeuvre.timeline.boundaries()[1]
    params = CarParameters()
    speed, rate = h["speed_mps"], h["yaw_rate_radps"]
    lateral = speed * rate
    steer = np.radians(0.5 * (h["steer_fl_deg"] + h["steer_fr_deg"]))
    use = (h["t"] > start) & (lateral > 0.5) & (lateral < 2.5)
    assert use.sum() > 50
    speed, rate, lateral, steer = speed[use], rate[use], lateral[use], steer[use]
    gradient = np.polyfit(lateral, steer - params.wheelbase_m * rate / speed, 1)[0]
    loads = params.design_axle_loads_N()
    tyre = MagicFormulaTyre.from_file(str(resource("urdf/tyres/pacejka2006_205_60R15.tir")))
    c_front = abs(magic_formula(tyre, loads["front"] / 2, 0, 0, 0, 16.7).cornering_stiffness)
    c_rear = abs(magic_formula(tyre, loads["rear"] / 2, 0, 0, 0, 16.7).cornering_stiffness)
    tyre_only = (loads["front"] / GRAVITY_MPS2 / (2 * c_front)
                 - loads["rear"] / GRAVITY_MPS2 / (2 * c_rear))
    to_deg_per_g = math.degrees(1.0) * GRAVITY_MPS2
    print(f"understeer gradient {gradient * to_deg_per_g:.2f} deg/g "
          f"(tyres alone {tyre_only * to_deg_per_g:.2f} deg/g)")
    assert tyre_only > 0
    assert tyre_only < gradient < math.radians(8.0) / GRAVITY_MPS2
