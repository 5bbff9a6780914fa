"""Every study on the user's car (issue 31): the design study around a car given by --scene (its
maps' star at the car's values, its answers about that car, --quick said as a smoke test on
every page, the user's change with its error), the ride study on a scene's car, the numbers an
engineer uses (the steering-wheel torque through the car's rack gain, the overall steering
ratio)."""

import dataclasses
import math

import matplotlib.figure
import numpy as np
import pytest

from drake_car.data import resource
from drake_car.law.errors import InputError
from drake_car.scene.load import SceneError, load_scene
from drake_car.study.design import analysis as design_analysis
from drake_car.study.design import compare as design_compare
from drake_car.study.design import jam_cases
from drake_car.study.design import report as design_report
from drake_car.study.design import runs as design_runs
from drake_car.study.design import smoke
from drake_car.study.design.spec import OUTCOMES, load_study
from drake_car.study.handling.analysis import steering_ratio
from drake_car.study.ride.grid import RideStudy, ride_scenes

DESIGN = resource("scenes/studies/design.yaml")
SEDAN = "tests/data/tyres/Sedan_Pac02Tire.tir"
# The engineer's car of issue 31 in today's parameters (the whole car's CoG 1.05 m behind the
# front axle, as the sprung mass's that gives it), with their own timeline.
ENGINEER = f"""
car:
  name: engineers_car
  car:
    mass: {{total_mass_kg: 1500.0, cog_to_front_axle_m: 1.0430618612962186,
           cog_to_rear_axle_m: 1.3499381387037812, sprung_cog_height_m: 0.5859492197054337,
           sprung_inertia_kgm2: [314.63, 1693.24, 1944.51]}}
    front: {{ball_joint_offset_b_m: 0.06, guide_length_l_m: 0.18, wheel_rate_Npm: 28000.0,
            strut_damping_Nspm: 1657.0}}
    tyre: {{unloaded_radius_m: 0.344, width_m: 0.245, radial_stiffness_Npm: 280835.2941,
           radial_damping_Nspm: 2000.0}}
  tyres: !MagicFormula {{tir_file: {SEDAN}}}
  manoeuvre: !LaneChange {{timeline: {{speed_up_s: 6.0, straight_s: 2.0}}}}
straight:
  name: straight
  manoeuvre: !Straight {{}}
"""


@pytest.fixture(scope="module")
def engineer(tmp_path_factory):
    path = tmp_path_factory.mktemp("car") / "engineer.yaml"
    path.write_text(ENGINEER)
    return path


def _rows(study, parts, value=0.02):
    """A table as ``design_analysis.table`` would make it, every run ok with the same made-up
    outcomes (the figures and the report read them; no simulation)."""
    keys = [f.key for f in study.factors] + [line.key for line in study.lines]
    rows = []
    for role, part in parts.items():
        for k, (name, (scene, values)) in enumerate(part.items()):
            row = {"name": name, "role": role, "hash": name, "status": "ok",
                   "step_s": scene.plant.time_step,
                   "sample": values.get("sample", ""), "mitigation": values.get("mitigation", ""),
                   "line": values.get("line", ""), "of": values.get("of", "")}
            for key in dict.fromkeys(keys):
                value_of = scene
                for part_name in key.split("."):
                    value_of = getattr(value_of, part_name)
                row[key] = float(value_of)
            row |= {o: value * (1 + 0.1 * (k % 3)) for o in OUTCOMES}
            row["split_change_N"] = 4000.0 * row["split_change_rel"]
            rows.append(row)
    return rows


def test_the_design_study_around_the_user_s_car_and_quick_says_smoke_test_everywhere(
        engineer, tmp_path, monkeypatch):
    study = load_study(DESIGN, "study", scene=(engineer, "car"))
    assert study.base.car.mass.total_mass_kg == 1500.0
    assert study.base.manoeuvre.timeline.speed_up_s == 6.0  # the user's timeline
    assert study.base.friction.law.mu_s == 0.2  # the study's own values stay
    quick, changes = smoke.quick(study)
    assert "speed-up 6 s" in changes[0] and "speed-up 0.6 s" in changes[0]  # said, not silent
    parts = {"map": design_runs.map_scenes(quick), "line": design_runs.line_scenes(quick),
             "mitigation": design_runs.mitigation_scenes(quick),
             "mc": design_runs.monte_carlo_scenes(quick), "sobol": design_runs.sobol_scenes(quick)}
    rows = jam_cases.apply(_rows(quick, parts), None, {"split_change_rel": 0.001})
    titles, stars = [], []
    original_save = matplotlib.figure.Figure.savefig

    def save(fig, *args, **kwargs):
        titles.extend(t for t in [ax.get_title() for ax in fig.axes]
                      + [fig._suptitle.get_text() if fig._suptitle else ""] if t)
        return original_save(fig, *args, **kwargs)
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", save)
    original_map = design_analysis.figures.heat_map

    def heat_map(*args, **kwargs):
        stars.append((kwargs["paper"], kwargs["star_label"]))
        return original_map(*args, **kwargs)
    monkeypatch.setattr(design_analysis.figures, "heat_map", heat_map)
    s = design_analysis.analyse(quick, rows, tmp_path, {"reused": 0, "wall_s": 1.0}, 1.0,
                                {"split_change_rel": 0.001}, None, smoke=changes)
    # The star at the user's values (b = 0.06 m, μs = 0.2), named as this car.
    b_map = [m for m in quick.maps if m.y == "car.front.ball_joint_offset_b_m"][0]
    assert stars and all(label.startswith("this car") for _, label in stars)
    assert (0.2, 0.06) in [tuple(p) for p, _ in stars], (b_map, stars)
    # Every figure's title says smoke test; the summary and the report too.
    assert titles and all(t.startswith("SMOKE TEST") for t in titles
                          if not t.startswith(("lasting", "heading"))), titles
    assert s["smoke_test"]["changes"] == changes
    s |= {"provenance": {"command": "test", "git_commit": None, "created_utc": "now"},
          "runs": s["runs"], "scene": f"{engineer}:car", "study_file": str(DESIGN)}
    text = design_report.report(s)
    first = text.splitlines()[0]
    assert "SMOKE TEST: not findings" in first
    assert "Its numbers are not findings" in text and "2.8 g" in text
    assert "## The question and the answer (smoke test: not findings)" in text
    assert "the paper's geometry" not in text and "this car: 1500 kg, b = 60 mm" in text
    assert "1657 N s/m in the strut" in text  # the car's damper, as it ran
    assert "| 0.06 |" in text.split("## Factors and ranges")[1]  # this car's b
    assert "calibrated for the shipped car (5.91 mm), not for this one" in text
    assert "not measured on this car" in text


def test_a_base_scene_that_does_not_change_lanes_is_refused(engineer):
    with pytest.raises(SceneError, match="must be !LaneChange, not !Straight"):
        load_study(DESIGN, "study", scene=(engineer, "straight"))


def test_the_user_s_change_against_the_car_with_its_error():
    study = load_study(DESIGN, "study")
    text = "car: {front: {spring_offset_m: 0.03}}"
    changed = design_compare.with_compare(study, text)
    assert changed.mitigations[-1].name == design_compare.NAME
    scenes = design_compare.compare_scenes(study, text)
    assert len(scenes) == 2 * len(study.line_mu_s)
    base, change = scenes["compare_mu0_base"][0], scenes["compare_mu0_change"][0]
    assert change.car.front.spring_offset_m == 0.03 and base.car.front.spring_offset_m == 0.0
    assert type(base.steering).__name__ == "HandsOff"
    parts = {"compare": scenes}
    assert set(scenes) <= set(jam_cases.jam_scenes(study, parts))  # refined at any μs
    rows = []
    for name, (scene, values) in scenes.items():
        lower = values["compare"] == "change"
        rows.append({"name": name, "role": "compare", "status": "ok",
                     "split_change_rel": 0.02 if lower else 0.05,
                     "split_change_N": 80.0 if lower else 200.0,
                     "split_change_rel_error": 0.001, "split_change_rel_converged": "yes",
                     "pull_deg": 0.30, "pull_deg_error": 0.05, "pull_deg_converged": "yes",
                     "wheel_torque_change_Nm": 0.1 if lower else 0.3})
    c = design_compare.compare_summary(study, rows, text, {"wheel_torque_change_Nm": 0.01})
    first = c["by_mu_s"][0]
    assert first["difference"]["split_rel"]["value"] == pytest.approx(-3.0)
    assert first["difference"]["split_rel"]["error"] == pytest.approx(0.2)
    assert first["difference"]["split_rel"]["verdict"] == "lower"
    assert first["difference"]["pull_deg"]["verdict"] == "within the errors"
    assert first["base"]["split_N"]["value"] == pytest.approx(200.0)
    assert first["base"]["split_N"]["error"] == pytest.approx(4.0)  # 0.1 % of 4000 N
    lines = design_compare.compare_lines(c)
    assert any("-3.00 ± 0.20: lower" in line for line in lines)
    with pytest.raises(SceneError, match="--compare"):
        design_compare.with_compare(study, "car: {front: {spring_ofset_m: 0.03}}")


def test_the_ride_study_runs_on_the_scene_s_car(engineer):
    study = RideStudy(classes=["B"], speeds_kph=[60.0], mu_s=[0.0, 0.2])
    scenes = ride_scenes(study, scene=(engineer, "straight"),
                         scene_text="car: {mass: {total_mass_kg: 1400.0}}")
    assert {s.car.mass.total_mass_kg for s in scenes.values()} == {1400.0}
    scenes = ride_scenes(study, scene=(engineer, "car"), scene_text="manoeuvre: !Straight {}")
    assert {s.car.front.ball_joint_offset_b_m for s in scenes.values()} == {0.06}
    assert all(s.tyres.tir_file == SEDAN for s in scenes.values())
    with pytest.raises(SceneError, match="must be !Straight"):
        ride_scenes(study, scene=(engineer, "car"))


def test_the_overall_steering_ratio_is_the_wheel_angle_per_road_wheel_angle():
    rack = np.linspace(-0.05, 0.05, 11)
    table = {"rack_m": rack, "steer_left_deg": np.degrees(10.0 * rack),
             "steer_right_deg": np.degrees(10.0 * rack)}  # 10 rad of road wheel per m of rack
    assert steering_ratio(table, 0.008) == pytest.approx(1 / (0.008 * 10.0))


def test_the_rack_gain_is_the_car_s_one_value():
    scene = load_scene(scene_text="steering: !HandsOff {}")
    assert scene.car.front.rack_gain_m_per_rad == 0.008
    with pytest.raises(SceneError, match="rack_gain_m_per_rad"):
        load_scene(scene_text="steering: !HandsOff {rack_gain_m_per_rad: 0.01}")
    with pytest.raises(SceneError, match=r"rack_gain_m_per_rad.*\[0.002, 0.05\]"):
        load_scene(scene_text="car: {front: {rack_gain_m_per_rad: 0.1}}")


def test_the_steering_wheel_torque_is_the_rack_force_through_the_rack_gain():
    from conftest import paper_scene
    from drake_car.sim.simulate import simulate
    # A lane change shortened 20 times (test_experiments' SHORT), the shipped Escort's rack as
    # given (too short a lane change to calibrate one for): the rack is loaded.
    text = ("{manoeuvre: !LaneChange {timeline: {settle_s: 0.04, speed_up_s: 0.15, "
            "straight_s: 0.06, steer_s: 0.12, calm_s: 0.13}, amplitude_m: 0.005908525382359731, "
            "second_lobe: 1.012425560052948}, logging: {channels: [steering]}}")
    run = simulate(paper_scene("a_1", text))
    h = run.history
    np.testing.assert_allclose(h["steering_wheel_torque_Nm"], 0.008 * h["rack_force_N"],
                               rtol=1e-12, atol=0, err_msg="T = c F")
    assert np.max(np.abs(h["rack_force_N"])) > 1.0  # the lane change loads the rack
    other = simulate(load_scene(base=paper_scene("a_1", text),
                                scene_text="car: {front: {rack_gain_m_per_rad: 0.012}}"))
    np.testing.assert_array_equal(other.history["rack_force_N"], h["rack_force_N"])
    assert not math.isclose(float(np.max(np.abs(other.history["steering_wheel_torque_Nm"]))),
                            float(np.max(np.abs(h["steering_wheel_torque_Nm"]))))
    assert dataclasses.is_dataclass(run.scene)


def test_the_design_study_keeps_the_shipped_car_s_manoeuvre_and_a_rack_the_user_gives(engineer):
    from drake_car.study.design import base_car
    shipped = load_study(DESIGN, "study")
    assert base_car.adapted_base(shipped) == (shipped, [])  # the Escort: as the spec gives it
    given = load_study(DESIGN, "study", scene=(engineer, "car"), scene_text=(
        "manoeuvre: !LaneChange {amplitude_m: 0.007, second_lobe: 1.0}"))
    study, words = base_car.adapted_base(given, stated={"speed_up_s", "amplitude_m",
                                                        "second_lobe"})
    assert study.base.manoeuvre == given.base.manoeuvre  # run as given
    # Said: the severity's range follows the stated rack (tests/test_design_severity.py).
    assert len(words) == 1 and words[0].startswith("the severity range")


def test_the_report_states_the_severity_range_of_the_user_s_rack(engineer, tmp_path):
    # A newcomer's report gave their car's 9.08 mm rack "(outside the range)" of 3 ... 9 mm and
    # said the range was half to one and a half times the lane change: true of the Escort only.
    from drake_car.study.design import base_car
    given = load_study(DESIGN, "study", scene=(engineer, "car"), scene_text=(
        "manoeuvre: !LaneChange {amplitude_m: 0.0084, second_lobe: 1.0}"))
    study, words = base_car.adapted_base(given, stated={"speed_up_s", "amplitude_m"})
    quick, changes = smoke.quick(study)
    parts = {"map": design_runs.map_scenes(quick), "sobol": design_runs.sobol_scenes(quick),
             "mc": design_runs.monte_carlo_scenes(quick)}
    rows = jam_cases.apply(_rows(quick, parts), None, {"split_change_rel": 0.001})
    s = design_analysis.analyse(quick, rows, tmp_path, {"reused": 0, "wall_s": 1.0}, 1.0,
                                {"split_change_rel": 0.001}, None, smoke=changes,
                                adapted=words)
    s |= {"provenance": {"command": "test", "git_commit": None, "created_utc": "now"},
          "scene": f"{engineer}:car", "study_file": str(DESIGN)}
    text = design_report.report(s)
    row = [r for r in text.split("## Factors and ranges")[1].splitlines()
           if "`manoeuvre.amplitude_m`" in r][0]
    low, high = 0.003 * 0.0084 / 0.005908525382359731, 0.009 * 0.0084 / 0.005908525382359731
    assert f"| {low:g} ... {high:g} | 0.0084 |" in row and "outside" not in row
    assert "4.27 ... 12.80 mm on this car: 0.51 ... 1.52 times the rack amplitude its scene " \
        "gives (8.40 mm)" in row
    assert "4.27 ... 12.80 mm: 0.51 ... 1.52 times this one" in text.split("## How it was")[1]


def test_the_paper_s_car_column_gives_the_paper_s_car_not_the_user_s(engineer):
    # A newcomer's design report put their car's calibrated rack (6.557 mm) in "the paper's
    # car" column: a factor without a value of its own fell back to the base scene's, theirs.
    from drake_car.study.design.report import factor_rows
    study = load_study(DESIGN, "study", scene=(engineer, "car"),
                       scene_text="manoeuvre: !LaneChange {amplitude_m: 0.0066}")
    rows = {r["key"]: r for r in factor_rows(study)}
    shipped = load_study(DESIGN, "study").base.manoeuvre.amplitude_m
    assert rows["manoeuvre.amplitude_m"]["car"] == 0.0066
    assert rows["manoeuvre.amplitude_m"]["paper"] == shipped
    assert rows["car.front.guide_length_l_m"]["paper"] == 0.14  # the paper's, as the spec gives


@pytest.mark.slow
def test_the_design_study_on_the_user_s_car_calibrates_its_rack_once(engineer):
    """The engineer's car (their 6 s launch stated) in the design study: the shipped Escort's
    5.91 mm rack would not move this car 3.7 m; the base's rack is calibrated for it (within
    the calibration's 2 mm of shift, lane_change_calibration.SHIFT_RESIDUAL_M) and the report's
    method says so."""
    from drake_car.sim.lane_change_calibration import SHIFT_RESIDUAL_M
    from drake_car.study.design import answers, base_car
    study = load_study(DESIGN, "study", scene=(engineer, "car"))
    adapted, words = base_car.adapted_base(study, stated={"speed_up_s"})
    m = adapted.base.manoeuvre
    assert m.timeline.speed_up_s == 6.0  # the user's launch, as stated
    assert (m.amplitude_m, m.second_lobe) != base_car.shipped_profile()
    # the calibrated rack, and the severity range scaled by it (study.design.base_car)
    assert len(words) == 2 and words[0].startswith("the rack calibrated for this car"), words
    assert words[1].startswith("the severity range") and "times its rack calibrated" in words[1]
    from drake_car.sim import lane_change_cache
    from drake_car.sim.lane_change_calibration import calibration_scene
    found = lane_change_cache.find(lane_change_cache.content_sha256(calibration_scene(
        adapted.base)))
    assert abs(found["residual"]["shift_error_m"]) <= SHIFT_RESIDUAL_M
    text = " ".join(answers.method(adapted, words, base_car.shipped_profile()))
    assert "calibrated for this car" in text and "not for this one" not in text


def test_a_car_file_named_as_a_shipped_one_is_refused_not_replaced_by_it(tmp_path, monkeypatch):
    # A newcomer's cars/engineers_car.yaml in the working folder ran as the shipped engineer's
    # car (1500 kg) with nothing said: the package's urdf/ was looked in first.
    from pathlib import Path

    from drake_car.scene.car_file import car_of_file
    shipped = Path(str(resource("urdf/cars/engineers_car.yaml")))
    mine = tmp_path / "cars" / "engineers_car.yaml"
    mine.parent.mkdir()
    mine.write_text(Path(str(resource("urdf/cars/bmw_320i.yaml"))).read_text())
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SceneError, match="car_file cars/engineers_car.yaml: names both a shipped "
                                         "file .* give yours by its absolute path"):
        car_of_file("cars/engineers_car.yaml")
    assert car_of_file(str(mine)).mass.total_mass_kg != car_of_file(str(shipped)).mass.total_mass_kg
    mine.write_bytes(shipped.read_bytes())  # the same file twice: no doubt which ran
    assert car_of_file("cars/engineers_car.yaml").mass.total_mass_kg == \
        car_of_file(str(shipped)).mass.total_mass_kg
    with pytest.raises(SceneError, match="cars/vanagon.yaml: car file not found \\(looked in "
                                         "the working folder"):
        car_of_file("cars/vanagon.yaml")
    # The same for a tyre file, the shipped scene's default one included.
    tyre = tmp_path / "tyres" / "pacejka2006_205_60R15.tir"
    tyre.parent.mkdir()
    tyre.write_text((Path(__file__).parent / "data" / "tyres" / "Sedan_Pac02Tire.tir").read_text())
    with pytest.raises(InputError, match="tyres/pacejka2006_205_60R15.tir: names both a shipped "
                                         "file .* move or rename the working folder's copy"):
        load_scene()
