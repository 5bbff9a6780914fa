"""Scenes: typed YAML, overrides, errors, the systems each shipped scene builds, a smoke run of
each shipped scene."""

import numpy as np
import pytest
from numpy.testing import assert_allclose

from drake_car.scene import (
    SceneError, dump_scene, load_scene, resolve, shipped_scenes)
from drake_car.scene_run import run_scene, system_names
from drake_car.study import FRICTION_SETS, PAPER_STUDY_SCENES

SCENES = shipped_scenes()
BASE = {"plant", "scene_graph", "tyres"}
PACER = {"sap_pacer_target", "sap_pacer_desired_state"}
DRIVE = {"rack_command_akima", "drive_command", "driveshafts", "applied_forces",
         "desired_state_mux", "desired_state_order"}
FRICTION = {"strut_friction", "actuation_mux",
            "actuation_mux_zeros_0"}


def expected_systems(scene):
    """What a scene calls for, and nothing else."""
    names = set(BASE)
    if scene.simulator.sap_pacer:
        names |= PACER
    drive = scene.manoeuvre.kind != "settle"
    names |= DRIVE if drive else {"rack_hold"}
    if scene.friction.mode != "off":
        names |= FRICTION | ({"actuation_mux_zeros_1"} if drive else set())
        if not drive:
            names |= {"desired_state_mux", "desired_state_order"}
    if drive:  # one logger per channel group asked for (a settle records its own few values)
        channels = set(scene.logging.channels)
        if scene.friction.mode == "off":
            channels.discard("friction")
        names |= {f"log_{group}" for group in channels}
        if channels & {"chassis", "steering", "struts"}:
            names.add("car_channels")
    if scene.visualization.mode != "none":
        names.add("meshcat_visualizer(visualizer)")
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


@pytest.mark.parametrize("channels, columns", [
    ("[chassis]", {"x_m", "y_m", "yaw_rad", "yaw_rate_radps", "speed_mps"}),
    ("[struts, friction]", {"d_left_m", "d_right_m", "rot_left_rad", "rot_right_rad"} | {
        f"friction_{side}_{kind}_{field}" for side in ("left", "right")
        for kind in ("translation", "rotation")
        for field in ("v", "creep", "beta", "mu1", "mu", "phase", "N", "friction")}),
    ("[]", set()),
])
def test_a_channel_not_logged_has_no_logger(channels, columns):
    text = (f"logging: {{channels: {channels}}}\n"
            "friction: {mode: translation_rotation, mu_s: 0.4, mu_d: 0.3}\n"
            "simulator: {end_time_s: 0.05}")
    scene = load_scene(SCENES[0][0].parent / "car.yaml", child="straight", scene_text=text)
    names = set(system_names(scene))
    assert names == expected_systems(scene)
    assert {n for n in names if n.startswith("log_")} == {
        f"log_{g}" for g in scene.logging.channels}
    history = run_scene(scene).history
    assert set(history) == columns | {"t", "phase"}
    assert_allclose(history["t"], np.arange(6) * 0.01, atol=1e-12)


def test_unknown_log_channel_is_named():
    with pytest.raises(SceneError, match="logging.channels: 'wheels' must be one of"):
        load_scene(scene_text="logging: {channels: [chassis, wheels]}")


@pytest.mark.parametrize("mode", ["meshcat_html", "meshcat_live"])
@pytest.mark.parametrize("child", ["settle", "straight"])
def test_visualization_modes(mode, child):
    """A visualiser only when asked for; the replay page comes back with the result; the live
    mode (here unpaced: realtime_rate 0) runs against a local Meshcat server."""
    text = (f"visualization: {{mode: {mode}, realtime_rate: 0.0}}\n"
            "simulator: {end_time_s: 0.05}")
    scene = load_scene(SCENES[0][0].parent / "car.yaml", child=child, scene_text=text)
    assert set(system_names(scene)) == expected_systems(scene)
    result = run_scene(scene)
    if mode == "meshcat_html":
        assert "<html" in result.html.lower() and "meshcat" in result.html.lower()
    else:
        assert result.html is None
