"""The hands-off steering column: the wheel's inertia as the rack's reflected inertia (the
default) against the coupler form it replaced (``model.steering``)."""

import dataclasses
import math

import numpy as np
import pytest

from drake_car.data import resource
from drake_car.model.steering import COLUMN_LAW
from drake_car.scene.load import hands_off_release_s
from drake_car.scene.scene import HeldRack
from drake_car.sim.build import build_diagram
from drake_car.sim.simulate import SceneRunner
from drake_car.study.design.runs import hands_off
from drake_car.study.design.spec import load_study, outcomes


def _hands_off_scene():
    study = load_study(resource("scenes/studies/design.yaml"), "study")
    return study, hands_off(study, study.base)


def _rack_mass_matrix_entry(scene, form="reflected"):
    built = build_diagram(scene, column_form=form)
    plant = built.plant
    context = plant.CreateDefaultContext()
    k = built.car.joint("rack_slide").velocity_start()
    return plant.CalcMassMatrix(context)[k, k]


def test_the_rack_carries_the_wheels_reflected_inertia():
    """Hands off, the rack's diagonal entry of the mass matrix is the held car's plus I/c²
    (Drake's reflected inertia ρ²·I with ρ = 1/c), with the column's friction pair on the
    rack joint (two actuators: Drake 1.51 reads the rotor of the last one) and without it."""
    _, off = _hands_off_scene()
    held = dataclasses.replace(off, steering=HeldRack())
    s = off.steering
    expected = _rack_mass_matrix_entry(held) + s.steering_wheel_inertia_kgm2 / (
        off.car.front.rack_gain_m_per_rad ** 2)
    frictionless = dataclasses.replace(off, steering=dataclasses.replace(s, friction_torque_Nm=0))
    for scene in (off, frictionless):
        np.testing.assert_allclose(_rack_mass_matrix_entry(scene), expected, rtol=1e-12,
                                   err_msg=f"friction {scene.steering.friction_torque_Nm} N·m")


@pytest.mark.slow
def test_reflected_column_pulls_as_the_coupled_one():
    """The design study's hands-off run (lubricated struts, so that only the column differs)
    in both forms. Where they may differ: the coupler form also feels the chassis's roll
    through the column's axis and its SAP constraint is compliant; the column's friction then
    sets where the rack stops only to within its creep scale at the rack, δq = c·Δmax_θ
    (8 µm). Bounds: the rack's positions within δq; the pull (heading change over the study's
    distance L after the release) within the kinematic yaw of a steer offset G·δq,
    L·G·δq/wheelbase (G = the front wheels' steer per rack travel, measured in the run; the
    car's understeer only makes the real difference smaller)."""
    study, scene = _hands_off_scene()
    scene = dataclasses.replace(scene, friction=None, logging=dataclasses.replace(
        scene.logging, channels=["chassis", "steering", "struts", "tyres"]))
    histories = {}
    for form in ("coupler", "reflected"):
        runner = SceneRunner(scene, built=build_diagram(scene, column_form=form))
        runner.start()
        runner.advance_to(scene.end_time_s)
        histories[form] = runner.finish().history
    c, r = histories["coupler"], histories["reflected"]
    dq = scene.car.front.rack_gain_m_per_rad * COLUMN_LAW.dmax_rotation_rad
    rack_diff = np.max(np.abs(c["rack_m"] - r["rack_m"]))
    assert rack_diff <= dq, f"rack positions differ by {rack_diff:.3g} m > δq = {dq:.3g} m"
    held = c["t"] < hands_off_release_s(scene)
    steer_per_rack = (np.max(np.abs(c["steer_fl_rad"][held] - c["steer_fl_rad"][0]))
                      / np.max(np.abs(c["rack_m"][held] - c["rack_m"][0])))
    bound = math.degrees(study.pull_distance_m * steer_per_rack * dq / scene.car.wheelbase_m)
    pull = {form: outcomes(h, scene, study)["pull_deg"] for form, h in histories.items()}
    assert all(math.isfinite(p) for p in pull.values()), pull
    assert abs(pull["coupler"] - pull["reflected"]) <= bound, (
        f"pulls {pull} differ by more than {bound:.3g} deg")
