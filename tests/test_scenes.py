"""Scenes: typed YAML, overrides, errors, the systems each shipped scene builds, a smoke run of
each shipped scene."""

import numpy as np
import pytest

from drake_car.scene import (
    SceneError, dump_scene, load_scene, resolve, shipped_scenes)
from drake_car.scene_run import run_scene, system_names
from drake_car.study import FRICTION_SETS, PAPER_STUDY_SCENES

SCENES = shipped_scenes()
BASE = {"plant", "scene_graph", "tyres"}
DRIVE = {"rack_command_akima", "drive_command", "driveshafts", "applied_forces",
         "desired_state_mux", "desired_state_order"}
FRICTION = {"strut_friction_left", "strut_friction_right", "actuation_mux",
            "actuation_mux_zeros_0"}


def expected_systems(scene):
    """What a scene calls for, and nothing else."""
    names = set(BASE)
    drive = scene.manoeuvre.kind != "settle"
    names |= DRIVE if drive else {"rack_hold"}
    if scene.friction.mode != "off":
        names |= FRICTION | ({"actuation_mux_zeros_1"} if drive else set())
        if not drive:
            names |= {"desired_state_mux", "desired_state_order"}
    return names


def test_scenes_are_shipped():
    names = {child for _, child in SCENES}
    assert {"a_1", "a_2", "a_3", "b_1", "b_2", "b_3", "settle", "straight", "bump"} <= names


@pytest.mark.parametrize("path, child", SCENES, ids=[c for _, c in SCENES])
def test_scene_builds_only_what_it_calls_for(path, child):
    scene = load_scene(path, child=child)
    assert set(system_names(scene)) == expected_systems(scene)


@pytest.mark.parametrize("path, child", SCENES, ids=[c for _, c in SCENES])
def test_scene_smoke(path, child):
    scene = load_scene(path, child=child, scene_text="simulator: {end_time_s: 0.2}")
    result = run_scene(scene)
    for name, values in result.history.items():
        if name != "phase":
            assert np.all(np.isfinite(values)), (child, name)


def test_paper_study_scenes_match_the_friction_sets():
    for case in ("a", "b"):
        for number, (mu_s, mu_d) in FRICTION_SETS.items():
            scene = load_scene(PAPER_STUDY_SCENES, child=f"{case}_{number}")
            assert scene.manoeuvre.case == case
            if mu_s == 0:
                assert scene.friction.mode == "off" and scene.car.strut_damping_Nspm == 1250.0
            else:
                assert (scene.friction.mu_s, scene.friction.mu_d) == (mu_s, mu_d)
                assert scene.car.strut_damping_Nspm == 0.0


def test_scene_text_overrides_and_round_trip(tmp_path):
    scene = load_scene(PAPER_STUDY_SCENES, child="a_3",
                       scene_text="friction: {mu_s: 0.5, mu_d: 0.3}\ncar: {ball_joint_offset_b_m: 0.06}")
    assert scene.friction.mu_s == 0.5 and scene.friction.mode == "translation_rotation"
    assert resolve(scene).params.front.ball_joint_offset_b_m == 0.06
    path = tmp_path / "copy.yaml"
    path.write_text("copy:\n" + "\n".join("  " + line for line in dump_scene(scene).splitlines()))
    assert load_scene(path, child="copy") == scene


@pytest.mark.parametrize("text, match", [
    ("frictoin: {mode: 'off'}", "frictoin"),
    ("friction: {mu_z: 0.2}", "mu_z"),
    ("friction: {mode: dry}", "friction.mode"),
    ("tyres: {model: brush}", "tyres.model"),
    ("simulator: {time_step_s: -1.0}", "simulator.time_step_s"),
    ("friction: {mode: translation, mu_s: 0.1, mu_d: 0.2}", "mu_s"),
    ("road: {profile: bump, length_m: 0.0}", "length_m"),
])
def test_bad_scenes_name_the_key(text, match):
    with pytest.raises(SceneError, match=match):
        resolve(load_scene(scene_text=text))


def test_missing_scene_file(tmp_path):
    with pytest.raises(SceneError, match="nowhere.yaml: scene file not found"):
        load_scene(tmp_path / "nowhere.yaml")


def test_timeline_from_a_scene():
    scene = load_scene(scene_text="manoeuvre: {timeline: {straight_s: 2.0, speed_kph: 50.0}}")
    timeline = resolve(scene).timeline
    assert timeline.straight_s == 2.0 and timeline.speed_mps == pytest.approx(50 / 3.6)
    with pytest.raises(SceneError, match="speed_up_s"):
        resolve(load_scene(scene_text="manoeuvre: {timeline: {speed_up_s: 0.0}}"))
