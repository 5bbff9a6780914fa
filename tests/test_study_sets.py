"""The paper's study on any friction sets and on any car (issue 31): two or five sets run and
report, the claims that compare sets name them, a claim about dry friction is not applicable
when no set is dry; every sentence about the car (its struts' damping, its drive, its tyre, the
previous version's car) comes from the scenes that ran."""

import dataclasses
import json

import pytest

from conftest import paper_scene
from drake_car.law.tyre.plausibility import combined_slip_note
from drake_car.model.loading import read_tyre
from drake_car.scene.load import load_scene
from drake_car.study.paper.claims import (
    CASES, FrictionSet, StudyError, StudyRun, check_study_scenes, evaluate_claims)
from drake_car.study.paper.figures import all_figures
from drake_car.study.paper.measures import claim_measures
from drake_car.study.paper.outcomes import at_one_step
from drake_car.study.paper.previous_car import applies
from drake_car.study.paper.report import report, summary
from test_figures import FakeRun, made, roles_of, values_of
from test_study import TIMELINE, synthetic

SEDAN = "tests/data/tyres/Sedan_Pac02Tire.tir"


def sets_study(sets, behaviour):
    """A synthetic study of FrictionSets ``sets``, each run shaped as the paper's set
    ``behaviour[number]`` (1: lubricated, 2 and 3: dry; 3 stays put in phase I)."""
    return {f"{c}_{f.number}": StudyRun(f"{c}_{f.number}", c, f,
                                        synthetic(c, behaviour[f.number]))
            for c in CASES for f in sets}


def scenes_of(sets, text=None):
    """Scenes of the shipped study's cases with the friction sets ``sets`` ((μs, μd, damping)
    each), ``text`` laid over each."""
    scenes = {}
    for k, (mu_s, mu_d, damping) in enumerate(sets, start=1):
        friction = ("friction: null" if mu_s == 0 else
                    f"friction: {{scheme: fast, law: {{mu_s: {mu_s}, mu_d: {mu_d}}}}}")
        for case in CASES:
            scene = paper_scene(f"{case}_1", f"{{{friction}, car: {{front: "
                                             f"{{strut_damping_Nspm: {damping}}}}}}}")
            if text:
                scene = load_scene(base=scene, scene_text=text)
            scenes[f"{case}_{k}"] = dataclasses.replace(scene, name=f"{case}_{k}")
    return scenes


def report_of(study, scenes=None, tmp_path=None):
    runs = {n: FakeRun(n, (scenes or {}).get(n) or paper_scene("a_1")) for n in study}
    claims, shifts = evaluate_claims(study, TIMELINE)
    table = at_one_step(values_of(study), 1e-3)
    figures = all_figures(study, TIMELINE, tmp_path, outcomes=table) if tmp_path else {}
    s = summary(study, claims, shifts, TIMELINE, runs=runs, outcomes=table, figures=figures,
                wall_s=1.0, provenance={"command": "test", "git_commit": "0" * 40,
                                        "drake": "1.58", "created_utc": "now"})
    json.loads(json.dumps(s, default=float))
    return s, report(s)


def test_two_friction_sets_run_and_the_claims_say_which_they_compare(tmp_path):
    sets = [FrictionSet(1, 0.0, 0.0, 1657.0), FrictionSet(2, 0.2, 0.15, 1657.0)]
    study = sets_study(sets, {1: 1, 2: 3})
    claims, _ = evaluate_claims(study, TIMELINE)
    assert [c["reproduced"] for c in claims] == [True] * 6, [c["number"] for c in claims]
    assert "set 2 (μs = 0.2, μd = 0.15)" in claims[0]["claim"]
    assert "with set 1 they do" in claims[0]["claim"]
    assert "set 2: μs = 0.2" in claims[5]["claim"]  # the only dry set is also Fig. 16's
    s, text = report_of(study, tmp_path=tmp_path)
    assert "4 runs: two cases (a, b) × 2 friction sets (1, 2)" in text
    assert (tmp_path / "fig16.png").exists() and (tmp_path / "load_split.png").exists()
    assert "| 6 |" in text


def test_five_friction_sets_run_the_highest_judged_against_the_others():
    mus = [(0.0, 0.0, 1250.0), (0.1, 0.075, 0.0), (0.2, 0.15, 0.0), (0.3, 0.225, 0.0),
           (0.5, 0.375, 0.0)]
    sets = [FrictionSet(k, *m) for k, m in enumerate(mus, start=1)]
    study = sets_study(sets, {1: 1, 2: 2, 3: 2, 4: 2, 5: 3})
    claims, _ = evaluate_claims(study, TIMELINE)
    assert "set 5 (μs = 0.5" in claims[0]["claim"] and "sets 1, 2, 3, 4" in claims[0]["claim"]
    assert "set 3: μs = 0.2" in claims[5]["claim"]  # the dry set nearest the paper's 0.2
    measures = claim_measures(at_one_step(values_of(study)), roles_of(study))
    assert measures[0][0]["runs"] in (["a_5"], ["b_5"])
    assert len(measures[3]) == 1 and len(measures[3][0]["runs"]) == 2  # one pair of five
    _, text = report_of(study)
    assert "10 runs: two cases (a, b) × 5 friction sets" in text


def test_without_a_dry_set_the_dry_friction_claims_are_not_applicable(tmp_path):
    study = sets_study([FrictionSet(1, 0.0, 0.0, 1250.0)], {1: 1})
    claims, _ = evaluate_claims(study, TIMELINE)
    assert [c["reproduced"] for c in claims] == [None, None, True, True, True, None]
    s, text = report_of(study, tmp_path=tmp_path)
    assert [c["reproduced"] for c in s["claims"]][::5] == [None, None]
    assert text.count("not applicable (no friction set is dry") == 3
    assert not (tmp_path / "fig16.png").exists() and "fig16.png" not in s["figures"]


def test_the_study_scenes_take_any_number_of_sets_each_in_both_cases():
    two = scenes_of([(0.0, 0.0, 1250.0), (0.3, 0.22, 0.0)])
    roles = check_study_scenes(two)
    assert {n: (c, f.number) for n, (c, f) in roles.items()} == {
        "a_1": ("a", 1), "b_1": ("b", 1), "a_2": ("a", 2), "b_2": ("b", 2)}
    del two["b_2"]
    with pytest.raises(StudyError, match="each set once in each case"):
        check_study_scenes(two)


def test_a_dry_set_with_the_car_s_damper_is_not_said_to_have_no_damping():
    """The engineer's car laid over the paper's scenes keeps its 1657 N s/m in every set: the
    report says so for each set, never "no viscous damping"."""
    sets = [FrictionSet(1, 0.0, 0.0, 1657.0), FrictionSet(2, 0.2, 0.15, 1657.0),
            FrictionSet(3, 0.4, 0.3, 1657.0)]
    _, text = report_of(sets_study(sets, {1: 1, 2: 2, 3: 3}))
    assert "no viscous damping" not in text
    assert "- **set 2**: dry strut: static μs = 0.2, kinetic μd = 0.15, 1657 N s/m of viscous " \
           "damping" in text
    assert "the paper's dry struts are undamped" in text
    # and the paper's own sets still say it
    _, paper = made(__import__("test_study").study_of())
    assert "μd = 0.15, no viscous damping" in paper


def test_a_car_file_s_damper_replaced_by_the_sets_is_said():
    """A car file laid over the paper's scenes (--scene_text "car_file: ..."): each set runs
    with the set's damping (1250 N s/m lubricated, none dry), not the file's; the report says
    so, not only "set 1: ... 1250 N s/m" (a newcomer's 2600 N s/m damper ran as 1250 and 0)."""
    study = __import__("test_study").study_of()
    scenes = {n: load_scene(base=paper_scene(n), scene_text="car_file: cars/bmw_320i.yaml")
              for n in study}
    s, text = report_of(study, scenes)
    own = s["car_file_strut_damping_Nspm"]
    assert own and own != 1250.0
    assert f"the car file gives {own:g} N s/m of viscous damping in the strut; each set ran " \
           "with its own damping" in text
    _, shipped = report_of(study, {n: paper_scene(n) for n in study})
    assert "the car file gives" not in shipped  # the paper's scenes name no car file


def test_the_previous_car_section_only_for_the_paper_s_car():
    from drake_car.data import resource
    from drake_car.scene.load import load_scene_file
    shipped = load_scene_file(resource("scenes/paper_study.yaml"))
    assert applies(shipped.values())
    other = {"b": "car: {front: {ball_joint_offset_b_m: 0.06}}",
             "tyre": f"tyres: !MagicFormula {{tir_file: {SEDAN}}}",
             "drive": "drive: !PrescribedRotation {}",
             "timeline": "manoeuvre: !LaneChange {timeline: {speed_up_s: 4.0}}"}
    for what, text in other.items():
        changed = [load_scene(base=s, scene_text=text) for s in shipped.values()]
        assert not applies(changed), what
    assert not applies([s for n, s in shipped.items() if not n.endswith("_3")])  # two sets
    study = __import__("test_study").study_of()
    scenes = {n: load_scene(base=paper_scene(n), scene_text=other["b"]) for n in study}
    _, text = report_of(study, scenes)
    assert "previous version" not in text and "pro-lift" not in text
    assert "about 2.5 deg/g" not in text
    _, shipped_text = report_of(study, {n: paper_scene(n) for n in study})
    assert "## Against the previous version's car" in shipped_text


def test_the_car_that_ran_is_described_from_its_scene():
    study = __import__("test_study").study_of()
    text = ("{car: {mass: {total_mass_kg: 1500.0}, front: {ball_joint_offset_b_m: 0.06, "
            f"guide_length_l_m: 0.18}}}}, tyres: !MagicFormula {{tir_file: {SEDAN}}}}}")
    scenes = {n: load_scene(base=paper_scene(n), scene_text=text) for n in study}
    s, report_text = report_of(study, scenes)
    car = report_text.split("## The car that ran")[1].split("\n## ")[0]
    assert "not the shipped car" in car and "1500 kg" in car
    assert "b = 60.0 mm" in car and "l = 180 mm" in car
    assert "Sedan_Pac02Tire.tir" in car and "PAC2002" in car
    # the file has no combined-slip fit: said where it runs
    assert "no combined-slip fit for Fx or Fy" in car
    assert "open differential on the front axle" in car


def test_a_tyre_file_without_a_combined_slip_fit_is_said_at_scene_load(caplog):
    note = combined_slip_note(read_tyre(SEDAN))
    assert "RBX1 (absent)" in note and "RBY1 (absent)" in note
    assert "aligning moment" in note
    assert combined_slip_note(read_tyre("tyres/pacejka2006_205_60R15.tir")) is None
    from drake_car.scene import limits
    limits._SAID.clear()
    with caplog.at_level("INFO", logger="drake_car"):
        load_scene(scene_text=f"tyres: !MagicFormula {{tir_file: {SEDAN}}}")
    said = [r for r in caplog.records if "no combined-slip fit" in r.getMessage()]
    # information, not a warning: the run is what the file says; the line says what it means
    # for the results and what to do about it (the review's C4)
    assert [r.levelname for r in said] == ["INFO"], said
    assert "tyres.tir_file" in said[0].getMessage()
    assert "overstated" in said[0].getMessage() and "add the tyre's" in said[0].getMessage()
    caplog.clear()
    limits._SAID.clear()
    with caplog.at_level("INFO", logger="drake_car"):
        load_scene(scene_text=f"tyres: !MagicFormula {{tir_file: {SEDAN}, "
                              "combined_slip: false}")
    assert not any("combined-slip" in r.getMessage() for r in caplog.records)


def test_a_tyre_file_of_another_radius_than_the_car_s_is_said_at_scene_load(caplog):
    # The Sedan file's R0 0.344 m on the shipped car (0.313 m): 9.9 %, each used somewhere.
    from drake_car.scene import limits
    limits._SAID.clear()
    with caplog.at_level("WARNING", logger="drake_car"):
        load_scene(scene_text=f"tyres: !MagicFormula {{tir_file: {SEDAN}}}")
    said = [r.getMessage() for r in caplog.records if "UNLOADED_RADIUS" in r.getMessage()]
    assert said and "UNLOADED_RADIUS 0.344 m, the car's tyre.unloaded_radius_m 0.313 m" in said[0]
    caplog.clear()
    with caplog.at_level("WARNING", logger="drake_car"):
        load_scene(scene_text="{car: {tyre: {unloaded_radius_m: 0.344}}, tyres: !MagicFormula "
                              f"{{tir_file: {SEDAN}}}}}")
        load_scene()  # the shipped car on its shipped tyre: one radius
    assert not any("UNLOADED_RADIUS" in r.getMessage() for r in caplog.records)


# A user's two sets, the car's damper in both, on a lane change shortened 20 times.
# A timeline shortened 20 times, the shipped Escort's rack as given (too short a lane change to
# calibrate one for).
SHORT = ("timeline: {settle_s: 0.04, speed_up_s: 0.15, straight_s: 0.06, steer_s: 0.12, "
         "calm_s: 0.13}, amplitude_m: 0.005908525382359731, second_lobe: 1.012425560052948")
TWO_SETS = f"""
_base: &base
  tyres: !MagicFormula {{combined_slip: true}}
  plant: {{time_step: 0.001}}
  logging: {{record_period_s: 0.01}}
_dry: &dry
  friction: {{scheme: fast, law: {{mu_s: 0.3, mu_d: 0.22}}}}
  car: {{front: {{strut_damping_Nspm: 1657.0}}}}
_wet: &wet
  friction: null
  car: {{front: {{strut_damping_Nspm: 1657.0}}}}
a_wet: {{<<: [*base, *wet], name: a_wet, manoeuvre: !LaneChange {{case: a, {SHORT}}}}}
b_wet: {{<<: [*base, *wet], name: b_wet, manoeuvre: !LaneChange {{case: b, {SHORT}}}}}
a_dry: {{<<: [*base, *dry], name: a_dry, manoeuvre: !LaneChange {{case: a, {SHORT}}}}}
b_dry: {{<<: [*base, *dry], name: b_dry, manoeuvre: !LaneChange {{case: b, {SHORT}}}}}
"""


@pytest.mark.slow
def test_the_paper_command_runs_two_friction_sets(tmp_path):
    """A user's two sets (``TWO_SETS``) through drake-car-paper: every claim judged, the dry set
    said with its damper, no comparison with the previous version's car."""
    import subprocess
    import sys
    from pathlib import Path
    scenes = tmp_path / "two.yaml"
    scenes.write_text(TWO_SETS)
    out = tmp_path / "paper"
    root = Path(__file__).resolve().parents[1]
    result = subprocess.run([sys.executable, "-m", "drake_car.commands.paper", "--scene",
                             str(scenes), "--out", str(out), "--no_verify", "--no_html",
                             "--workers", "1"], cwd=root, capture_output=True, text=True,
                            timeout=1800)
    assert result.returncode == 0, result.stderr[-3000:]
    s = json.loads((out / "summary.json").read_text())
    assert sorted(s["friction_sets"]) == ["1", "2"] and s["set_roles"]["high"] == 2
    assert len(s["claims"]) == 6 and all(c["reproduced"] in (True, False) for c in s["claims"])
    text = (out / "report.md").read_text()
    assert "4 runs: two cases (a, b) × 2 friction sets (1, 2)" in text
    assert "dry strut: static μs = 0.3, kinetic μd = 0.22, 1657 N s/m of viscous damping" in text
    assert "## Against the previous version's car" not in text
    assert (out / "fig16.png").exists() and (out / "a_dry.csv").exists()
    assert "claims reproduced" in result.stdout

