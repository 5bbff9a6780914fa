"""What the reports say of the car that ran (a newcomer's review on their own car): the hard-point
table marks what the scene's car: values changed against the car file's, the car checks compare
the ride height with the car file's drawing and say the jammed run's strut damping, the strut
rig names the car and its strut, and the handling study says when the shipped tyre it reruns on
is not the car's size."""

import types

import numpy as np
import pytest

from conftest import car_scene
from drake_car.data import resource
from drake_car.model.hard_point_table import hard_point_table
from drake_car.model.parameters import CarParameters
from drake_car.scene.car_file import car_of_file, read_car_file
from drake_car.scene.load import load_scene, load_scene_file

ENGINEER = "cars/engineers_car.yaml"  # b = 0.06 m, drawn with its wheel centre at z 0.330 m
SEDAN_TIR = "tests/data/tyres/Sedan_Pac02Tire.tir"  # UNLOADED_RADIUS 0.344 m


def _rows(scene):
    given = read_car_file(scene.car_file)
    return {r.quantity: r for r in hard_point_table(scene.car, given,
                                                    base=car_of_file(scene.car_file))}


def test_the_hard_point_table_marks_the_points_the_scene_s_car_values_moved():
    """b = 0.08 m over the engineer's file (b = 0.06 m): the ball joint, the strut's mounts
    and the spring's seats move 20 mm inboard and are no longer "as entered"; the wheel centre,
    the arm's pivots and the tie rod's ends stay as entered; b itself is the scene's."""
    from drake_car.study.car.report import overrides_sentence
    scene = load_scene(scene_text=f"{{car_file: {ENGINEER}, "
                                  "car: {front: {ball_joint_offset_b_m: 0.08}}}")
    file_points = read_car_file(ENGINEER).front
    rows = _rows(scene)
    why = "front.ball_joint_offset_b_m = 0.08 (the car file's 0.06)"
    for label, name in (("ball joint", "ball_joint_m"), ("strut top mount", "strut_top_mount_m"),
                        ("strut lower mount", "strut_lower_mount_m"),
                        ("spring upper seat", "spring_upper_seat_m"),
                        ("spring lower seat", "spring_lower_seat_m")):
        row = rows[label]
        assert row.kind == "moved (scene)", (label, row)
        assert why in row.how and "not as entered" in row.how, (label, row.how)
        # 20 mm inboard of the file's point (the frame's shift is in x and z only).
        assert row.value[1] == pytest.approx(getattr(file_points, name)[1] - 0.02, abs=1e-9)
    for label in ("wheel centre", "lower arm front pivot", "lower arm rear pivot",
                  "tie rod inner end", "tie rod outer end"):
        assert rows[label].kind == "input" and "as entered" in rows[label].how, rows[label]
    b = rows["ball-joint offset b"]
    assert b.kind == "input (scene)" and "front.ball_joint_offset_b_m" in b.how, b
    assert "the car file's: 0.06" in b.how
    # A derived value the change moved says the file's beside; one it kept says nothing.
    assert "the car file's" in rows["scrub radius"].how
    assert rows["kingpin inclination"].kind == "derived"
    assert "the car file's" not in rows["kingpin inclination"].how
    assert "`front.ball_joint_offset_b_m` = 0.08 (the car file's 0.06)" in \
        overrides_sentence(scene)
    # The file alone: nothing marked, nothing said.
    plain = load_scene(scene_text=f"car_file: {ENGINEER}")
    assert not [r for r in _rows(plain).values() if "scene" in r.kind]
    assert overrides_sentence(plain) == ""


def test_the_shipped_car_s_table_marks_what_the_scene_set_against_the_shipped_values():
    scene = load_scene(scene_text="car: {mass: {total_mass_kg: 1300.0}}")
    rows = {r.quantity: r for r in hard_point_table(scene.car, base=CarParameters())}
    assert rows["total mass"].kind == "input (scene)"
    assert "the shipped car's" in rows["total mass"].how
    assert "the shipped car's" in rows["axle loads at rest, front / rear"].how
    assert rows["kingpin inclination"].kind == "input"


def _fake_runs(settle_scene, jammed_scene, ride_m):
    """The car checks' three results, as ``write_report`` reads them, with given ride heights
    (no simulation: the report's words are under test, not the runs)."""
    final = {"corner_loads_N": {"fl": 4000.0, "fr": 4000.0, "rl": 2500.0, "rr": 2500.0},
             "design_axle_loads_N": {"front": 8000.0, "rear": 5000.0},
             "total_mass_kg": settle_scene.car.mass.total_mass_kg,
             "ride_height_m": {"front": ride_m[0], "rear": ride_m[1]},
             "strut_overlap_m": {"left": 0.16, "right": 0.16}, "loop_closure_error_m": 1e-7}
    settled = types.SimpleNamespace(final=final, scene=settle_scene)
    names = ("camber_deg", "toe_deg", "caster_deg", "kingpin_deg", "strut_length_m",
             "overlap_m")
    sweep = types.SimpleNamespace(kinematics={"side": ["left", "left"], "closure_error_m":
                                              [0.0, 0.0], **{n: [0.0, 1.0] for n in names}})
    t = np.linspace(0.0, 3.0, 31)
    stuck = types.SimpleNamespace(scene=jammed_scene, history={
        "t": t, "d_left_m": np.full_like(t, 0.16), "d_right_m": np.full_like(t, 0.16)})
    return settled, sweep, stuck


def test_the_car_checks_compare_the_ride_height_with_the_drawing_and_say_the_jammed_damping(
        tmp_path):
    from drake_car.study.car.report import write_report
    text = f"car_file: {ENGINEER}"
    settle, jammed = car_scene("settle", text), car_scene("settle_jammed", text)
    r0 = settle.car.tyre.unloaded_radius_m
    path = tmp_path / "report.md"
    write_report(path, *_fake_runs(settle, jammed, (0.3298, 0.3348)), 1.0)
    report = path.read_text()
    row = next(line for line in report.splitlines() if line.startswith("| ride height"))
    # The car file draws the car at ride height, its wheel centre at z 0.330 m: the settled
    # car is compared with that, and R0 is named as what it is (the unloaded design position).
    assert "as drawn in the car file: 0.3300 m" in row and "-0.2 / +4.8 mm" in row, row
    assert f"unloaded design position (tyres touching, unloaded: R0) {r0:.4f} m" in row, row
    assert f"sank {1e3 * (r0 - 0.3298):.1f} / {1e3 * (r0 - 0.3348):.1f} mm" in row, row
    assert "design 0.344" not in row
    # settle_jammed sets the strut's damping to 0 (scenes/car.yaml): the report says so.
    assert jammed.car.front.strut_damping_Nspm == 0.0
    assert (f"sets the front struts' viscous damping to 0 (the lubricated run above: "
            f"{settle.car.front.strut_damping_Nspm:g} N s/m)") in report
    assert "## Jammed struts (μs = 0.4, μd = 0.3)" in report
    # A scene that keeps damping in the jammed run is told as it ran.
    kept = car_scene("settle_jammed", "car: {front: {strut_damping_Nspm: 500.0}}")
    write_report(path, *_fake_runs(car_scene("settle"), kept, (0.30, 0.30)), 1.0)
    report = path.read_text()
    assert "keeps 500 N s/m of viscous damping" in report
    assert "no ride height as drawn in the car's data" in report


def test_the_strut_rig_report_names_the_car_and_its_strut():
    from drake_car.study.rig.report import report, strut_facts
    scene = car_scene("settle", f"{{car_file: {ENGINEER}, "
                                "car: {front: {guide_length_l_m: 0.15}}}")
    facts = strut_facts(scene)
    at_rest = {"side": "left", "corner_load_N": 4321.0, "car_normal_N": 1000.0,
               "transverse_force_N": 500.0, "shares_N": {"tyre": 500.0},
               "rig_side_force_N": 500.0, "rig_side_force_point_below_top_m": 0.0,
               "rig_normal_N": 1000.0, "rig_difference_bound_N": 1.0,
               "corner_side_force_N": 400.0, "corner_side_force_normal_N": 800.0}
    fit = types.SimpleNamespace(line=lambda: "μs = 0.3", apparent_mu_s=0.3, residual_rms_N=1.0,
                                dmax_resolved=False, dv_resolved=False)
    prov = {"command": "drake-car-strut-rig", "git_commit": "x", "dirty": False,
            "drake": "1", "created_utc": "now"}
    text = report(car=facts, at_rest=at_rest, rows=[], fit=fit, prov=prov,
                  law=types.SimpleNamespace(mu_s=0.3, mu_d=0.22),
                  runs={"runs": 0, "cpu_s": 0.0})
    title = text.splitlines()[0]
    assert f"`{ENGINEER}`" in title and "front.guide_length_l_m = 0.15" in title, title
    f = scene.car.front
    assert f"b = {1e3 * f.ball_joint_offset_b_m:.1f} mm" in text
    assert "l = 150.0 mm" in text and f"r = {1e3 * f.rod_radius_r_m:.1f} mm" in text
    assert f"{scene.car.mass.total_mass_kg:g} kg" in text
    assert "4321.0 N" in text and "`scene.yaml`" in text
    shipped = report(car=strut_facts(car_scene("settle")), at_rest=at_rest, rows=[], fit=fit,
                     prov=prov, law=types.SimpleNamespace(mu_s=0.3, mu_d=0.22),
                     runs={"runs": 0, "cpu_s": 0.0})
    assert "the shipped car" in shipped.splitlines()[0]


def test_the_shipped_tyre_s_rerun_on_a_car_of_another_tyre_size_is_said(caplog):
    """The engineer's car rolls on 0.344 m tyres; the shipped file's UNLOADED_RADIUS is
    0.313 m: the handling study's rerun on it says so, on stderr and in the report."""
    from drake_car.scene import limits
    from drake_car.study.handling import tyre_section
    scenes = load_scene_file(resource("scenes/handling.yaml"),
                             f"{{car_file: {ENGINEER}, tyres: !MagicFormula "
                             f"{{tir_file: {SEDAN_TIR}}}}}")
    limits._SAID.clear()
    with caplog.at_level("WARNING", logger="drake_car"):
        _, note = tyre_section.shipped_scenes(scenes)
    said = "UNLOADED_RADIUS 0.313 m, the car's tyre.unloaded_radius_m 0.344 m"
    assert note is not None and said in note, note
    assert any(said in r.getMessage() for r in caplog.records)
    lines = tyre_section.section({"tyre": tyre_section.facts(scenes["steady_state"]),
                                  "tyre_change": {"rows": [], "note": note}})
    assert any(said in line and "not this car's size" in line for line in lines)
    # The shipped car on the shipped tyre's size: nothing said.
    escort = load_scene_file(resource("scenes/handling.yaml"),
                             f"{{tyres: !MagicFormula {{tir_file: {SEDAN_TIR}}}}}")
    assert "UNLOADED_RADIUS" not in (tyre_section.shipped_scenes(escort)[1] or "")
