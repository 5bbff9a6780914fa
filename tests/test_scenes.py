"""Scenes: the shipped scenes run; a Diagram holds a system if and only if the scene calls for
its effect; every value a scene states changes the run; the saved scene reruns bit for bit."""

import dataclasses

import numpy as np
import pytest

from conftest import assert_finite, car_scene, paper_scene
from drake_car.scene.load import (
    SceneError, dump_scene, dump_scene_file, load_scene, scene_hash, shipped_scenes)
from drake_car.scene.scene import MeshcatReplay, PrescribedRotation
from drake_car.sim.build import build_diagram
from drake_car.results.files import read_csv, write_csv
from drake_car.sim.simulate import simulate
from drake_car.systems.sap_pacer import PACER_MASS_KG
from drake_car.systems.strut_friction import StrutFriction
from drake_car.systems.tyre import TyreSystem

SCENES = shipped_scenes()


def systems_of(scene):
    return list(build_diagram(scene).diagram.GetSystems())


def test_scenes_are_shipped():
    names = {child for _, child in SCENES}
    assert {"a_1", "a_2", "a_3", "b_1", "b_2", "b_3", "settle", "straight", "bump"} <= names


@pytest.mark.parametrize("path, child", SCENES, ids=[c for _, c in SCENES])
def test_a_system_is_there_if_and_only_if_its_effect_is_on(path, child):
    scene = load_scene(path, child=child)
    systems = systems_of(scene)
    kinds = {type(s) for s in systems}
    assert (StrutFriction in kinds) == (scene.friction is not None)
    assert TyreSystem in kinds
    drives_through_body = scene.manoeuvre.drives and not (
        isinstance(scene.drive, PrescribedRotation) and scene.drive.reaction == "knuckle")
    tyres = next(s for s in systems if isinstance(s, TyreSystem))  # reacts the drive torque
    assert tyres.HasInputPort("net_actuation") == drives_through_body
    names = {s.get_name() for s in systems}
    assert ("sap_pacer_target" in names) == scene.simulator.sap_pacer
    loggers = {n[len("log_"):] for n in names if n.startswith("log_")}
    from drake_car.scene.load import channels_of
    assert loggers == set(channels_of(scene))
    assert not any("meshcat" in n for n in names), "no visualiser unless asked for"


@pytest.mark.parametrize("path, child", SCENES, ids=[c for _, c in SCENES])
def test_scene_smoke(path, child):
    scene = load_scene(path, child=child, scene_text="simulator: {end_time_s: 0.2}")
    run = simulate(scene)
    assert_finite(run.history)
    assert run.history["t"][-1] == pytest.approx(0.2)


def test_a_channel_not_logged_has_no_logger_and_no_column():
    scene = car_scene("straight", "logging: {channels: [chassis]}\n"
                                  "simulator: {end_time_s: 0.05}")
    history = simulate(scene).history
    assert set(history) == {"t", "phase", "x_m", "y_m", "z_m", "roll_rad", "pitch_rad",
                            "yaw_rad", "yaw_rate_radps", "speed_mps", "sideslip_rad",
                            "ax_mps2", "ay_mps2"}


def test_visualiser_only_when_asked_for_and_the_replay_comes_back():
    scene = dataclasses.replace(car_scene("settle", "simulator: {end_time_s: 0.05}"),
                                visualization=MeshcatReplay())
    run = simulate(scene)
    assert "<html" in run.replay_html.lower() and "meshcat" in run.replay_html.lower()


# Each override must change the run (its history) and the saved scene. The base is a_3 for
# 1.2 s (settled, then 0.4 s of the speed-up), so each effect has acted.
BASE_TEXT = "simulator: {end_time_s: 1.2}"
OVERRIDES = {
    "friction scheme": "friction: {scheme: reference}\nplant: {time_step: 5.0e-6}\n"
                       "simulator: {end_time_s: 0.02}",
    "tyres linear": "tyres: !LinearTyre {}",
    "tyres pure slip": "tyres: !MagicFormula {combined_slip: false}",
    "tyres no relaxation": "tyres: !MagicFormula {slip: {relaxation: false}}",
    "time step": "plant: {time_step: 0.0005}",
    "sap pacer off": "simulator: {sap_pacer: false}",
    "sap tolerance loosened": "simulator: {sap_tolerance_factor: 2.0}",
    "start at design": "simulator: {start: design}",
    "ball-joint offset b": "car: {front: {ball_joint_offset_b_m: 0.06}}",
    "friction law": "friction: {law: {mu_s: 0.3}}",
    "friction pairs": "friction: {pairs: translation}",
    "no friction": "friction: null",
    "road": "road: !CosineBump {start_x_m: -0.5, length_m: 1.5, height_m: 0.02}",
    "drive reaction": "drive: !PrescribedRotation {reaction: knuckle}",
    "the paper's drive": "drive: !PrescribedRotation {}",
    "speed-up": "manoeuvre: !LaneChange {timeline: {speed_up_s: 2.0}}",
    "equilibrium settle time": "simulator: {equilibrium_settle_s: 3.0}",
    "equilibrium step": "simulator: {equilibrium_time_step_s: 0.0005}",
    "hands off": "steering: !HandsOff {release_s: 1.0}",
    "strut lean back": "car: {front: {strut_caster_deg: 5.0}}",
    "spring seats fore-aft": "car: {front: {spring_offset_fore_aft_m: 0.03}}",
    "rear drive": "car: {driven_axle: rear}",
    "car file": "car_file: cars/engineers_car.yaml",
}


@pytest.fixture(scope="module")
def base_run():
    return simulate(paper_scene("a_3", BASE_TEXT))


def layered(child, *texts):
    """The paper scene with each text laid over the last (a key given twice in one text is
    refused, scene.guard)."""
    scene = paper_scene(child, texts[0])
    for text in texts[1:]:
        scene = load_scene(base=scene, scene_text=text)
    return scene


@pytest.mark.parametrize("label", list(OVERRIDES))
def test_every_scene_value_changes_the_run(label, base_run):
    scene = layered("a_3", BASE_TEXT, OVERRIDES[label])
    assert dump_scene(scene) != dump_scene(base_run.scene), "the saved scene must differ"
    run = simulate(scene)
    base, other = base_run.history, run.history
    n = min(len(base["t"]), len(other["t"]))
    changed = any(not np.array_equal(base[c][:n], other[c][:n])
                  for c in base if c != "phase" and c in other)
    assert changed, f"{label}: the run did not change"


def test_the_friction_scheme_alone_changes_the_run():
    """The scheme override above also needs a smaller step; here only the scheme differs."""
    common = "plant: {time_step: 5.0e-6}\nsimulator: {end_time_s: 0.02}"
    fast = simulate(layered("a_3", common, "friction: {scheme: fast}"))
    reference = simulate(layered("a_3", common, "friction: {scheme: reference}"))
    assert fast.scene.friction.scheme == "fast" and reference.scene.friction.scheme == "reference"
    assert any(not np.array_equal(fast.history[c], reference.history[c])
               for c in fast.history if c != "phase")


def test_saved_scene_reruns_bit_for_bit(tmp_path, base_run):
    path = tmp_path / "scene.yaml"
    path.write_text(dump_scene_file(base_run.scene))
    again = simulate(load_scene(path))
    assert scene_hash(again.scene) == scene_hash(base_run.scene)
    write_csv(tmp_path / "first.csv", base_run.history)
    write_csv(tmp_path / "again.csv", again.history)
    assert (tmp_path / "first.csv").read_bytes() == (tmp_path / "again.csv").read_bytes()
    # ...and the CSV carries the bits: read back, it equals the history exactly.
    read = read_csv(tmp_path / "first.csv")
    assert all(np.array_equal(read[c], base_run.history[c]) for c in read if c != "phase")


def test_the_diagram_picture_is_the_run_s_own():
    with_friction = simulate(paper_scene("a_3", "simulator: {end_time_s: 0.05}"))
    without = simulate(paper_scene("a_3", "simulator: {end_time_s: 0.05}\nfriction: null"))
    assert "strut_friction" in with_friction.diagram_dot
    assert "strut_friction" not in without.diagram_dot


def test_the_pacer_is_decoupled_and_light():
    # The energy channel leaves the pacer's body out (a 1 kg body, decoupled from the car).
    assert PACER_MASS_KG == 1.0


def test_content_hash_ignores_the_name_only():
    a = paper_scene("a_3")
    assert scene_hash(a) == scene_hash(dataclasses.replace(a, name="other"))
    assert scene_hash(a) != scene_hash(paper_scene("a_3", "friction: {law: {mu_s: 0.39}}"))


def test_missing_entry_is_named(tmp_path):
    with pytest.raises(SceneError, match=r"no scene 'zz'; it holds a_1, a_2"):
        paper_scene("zz")
