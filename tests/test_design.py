"""The design study: scenes from factor values, outcomes from runs (on synthetic and real
histories), Sobol indices on a function with known indices, and the whole study as a smoke run
(--quick)."""

import csv
import dataclasses
import json
import math
import subprocess
import sys
import types
from pathlib import Path

import numpy as np
import pytest

from drake_car.data import resource
from drake_car.law.road.profiles import CosineBump
from drake_car.scene.load import SceneError, scene_hash
from drake_car.study.design import jam_cases
from drake_car.study.design import answers as design_answers
from drake_car.study.design import report as design_report
from drake_car.study.design import runs as design_runs
from drake_car.study.design import smoke as design_smoke
from drake_car.study.design import tables
from drake_car.study.design.spec import (
    OUTCOMES, Accuracy, Mitigation, load_study, outcomes, paper_value, rough_road, with_value)
from drake_car.study.design.sensitivity import sobol_indices, sobol_points

ROOT = Path(__file__).resolve().parents[1]
STUDY = load_study(resource("scenes/studies/design.yaml"), "study")


def test_factor_values_set_the_scene_and_mu_d_follows_mu_s():
    scene = with_value(STUDY, {"friction.law.mu_s": 0.4,
                               "car.front.ball_joint_offset_b_m": 0.05}, name="x")
    assert scene.friction.law.mu_s == 0.4
    assert scene.friction.law.mu_d == pytest.approx(0.75 * 0.4)
    assert scene.car.front.ball_joint_offset_b_m == 0.05 and scene.name == "x"
    with pytest.raises(SceneError, match="ball_joint_offset_b_m"):
        with_value(STUDY, {"car.front.ball_joint_offset_b_m": 10.0})
    with pytest.raises(SceneError, match="no field 'nonsense'"):
        with_value(STUDY, {"car.front.nonsense": 1.0})


def test_every_factor_range_makes_valid_scenes_and_the_paper_values_are_stated():
    for f in STUDY.factors:
        assert f.reason, f.key
        assert f.low < paper_value(STUDY, f) < f.high or math.isclose(
            paper_value(STUDY, f), f.low) or math.isclose(paper_value(STUDY, f), f.high), f.key


def test_rough_roads_are_seeded_two_tracks_and_flat_where_the_car_rests_and_turns(tmp_path):
    mc = STUDY.monte_carlo
    road, again, other = rough_road(STUDY, 3), rough_road(STUDY, 3), rough_road(STUDY, 4)
    assert road == again and other.z_m != road.z_m
    assert road.z_m != road.z_right_m  # the tracks are independent: left/right jam states
    heights = np.array([road.z_m, road.z_right_m])
    assert np.max(np.abs(heights)) <= mc.roughness_m and np.max(np.abs(heights)) > 0
    x = np.array(road.x_m)
    assert np.all(heights[:, x <= mc.start_m] == 0.0) and np.all(heights[:, x >= mc.length_m] == 0)
    # The rear wheels leave the rough stretch before place a, at the commanded speed (the car
    # lags it, which adds margin); a longer stretch is refused when the study is loaded.
    timeline = STUDY.base.manoeuvre.timeline
    from drake_car.scene.manoeuvres import speed_profile
    _, front, _ = speed_profile(np.array([timeline.boundaries()[1] - 0.3]), timeline)
    assert front[0] - STUDY.base.car.wheelbase_m > mc.length_m
    text = (ROOT / "scenes/studies/design.yaml").read_text().replace(
        "length_m: 25.0", "length_m: 40.0")
    spec = tmp_path / "design_long_road.yaml"
    spec.write_text(text)
    with pytest.raises(SceneError, match="monte_carlo.length_m = 40.0 m: the rear wheels"):
        load_study(spec, "study")


def test_a_road_flat_under_the_resting_car_gives_the_flat_road_s_equilibrium_bit_for_bit():
    """The equilibrium's cache serves every rough road that starts ahead of the car: the
    settling scene takes the flat road, and settling on the rough road itself gives the same
    positions to the last bit (the tyres touch only z = 0 there)."""
    from drake_car.law.road.profiles import Flat
    from drake_car.scene.load import load_scene
    from drake_car.sim.equilibrium import equilibrium_scene
    from drake_car.sim.simulate import simulate
    rough = design_runs.monte_carlo_scenes(STUDY, samples=1)["mc_0000"][0]
    settle = equilibrium_scene(rough)
    assert isinstance(settle.road, Flat)
    assert isinstance(equilibrium_scene(load_scene(
        scene_text="road: !CosineBump {start_x_m: 0.5}")).road, CosineBump)
    short = "manoeuvre: !Settle {duration_s: 0.3}"
    on_flat = simulate(load_scene(scene_text=short, base=settle))
    on_rough = simulate(load_scene(scene_text=short, base=dataclasses.replace(
        settle, road=rough.road)))
    assert on_flat.final["positions"] == on_rough.final["positions"]


def test_outcomes_of_a_synthetic_history():
    """A lasting split of 40 N (1 % of a 4 kN corner) after the lane change, one rod stuck
    throughout and one half of the time, the rack force changed by 30 N."""
    scene = STUDY.base
    timeline = scene.manoeuvre.timeline
    t = np.arange(0.0, timeline.duration_s + 1e-9, 0.01)
    after = t >= timeline.boundaries()[2]
    h = {"t": t, "Fz_fl_N": 4000.0 + 20.0 * after, "Fz_fr_N": 4000.0 - 20.0 * after,
         "d_left_m": 0.14 + 0.002 * after, "d_right_m": np.full_like(t, 0.14),
         "rack_force_N": 30.0 * after, "yaw_rad": np.zeros_like(t), "y_m": np.zeros_like(t),
         "speed_mps": np.full_like(t, 16.7),
         "friction_left_translation_phase": np.zeros_like(t),
         "friction_right_translation_phase": (t > t[-1] / 2).astype(float)}
    out = outcomes(h, scene, STUDY)
    assert out["split_change_N"] == pytest.approx(40.0)
    assert out["split_change_rel"] == pytest.approx(0.01)
    assert out["rack_force_change_N"] == pytest.approx(30.0)
    assert out["dd_left_b_m"] - out["dd_left_a_m"] == pytest.approx(0.002)
    assert out["stuck_left"] == 1.0 and 0.4 < out["stuck_right"] < 0.6
    assert math.isnan(out["pull_deg"])  # hands on: no pull
    assert out["speed_a_kph"] == pytest.approx(3.6 * 16.7) and out["speed_asked_kph"] == 60.0


def test_runs_that_did_not_reach_their_speed_are_counted_and_said():
    # A newcomer's weaker car could not follow the speed-up line's 3 s launch: its lane change
    # ran slower, and nothing said so. Within 1 km/h (scene.manoeuvre_targets) a run ran it.
    rows = [{"name": n, "role": role, "status": "ok", "speed_a_kph": v}
            for n, role, v in (("map0_000", "map", 60.4), ("line2_mu0_00", "line", 52.1),
                               ("line2_mu0_01", "line", 58.7), ("sobol_0001", "sobol", 59.2))]
    rows.append({"name": "x", "role": "map", "status": "failed", "speed_a_kph": math.nan})
    m = tables.manoeuvre_summary(STUDY, rows)
    assert (m["runs"], m["off"], m["off_by_role"]) == (4, 2, {"line": 2})
    assert m["slowest"] == {"name": "line2_mu0_00", "speed_a_kph": 52.1}
    text = "\n".join(design_report._manoeuvre_lines(m))
    assert "2 of 4 runs did not reach 60 ± 1 km/h at place a" in text and "52.1 km/h" in text
    rows[1]["speed_asked_kph"] = 52.0  # a run asked another speed is judged by its own
    assert tables.manoeuvre_summary(STUDY, rows)["off"] == 1
    m = tables.manoeuvre_summary(STUDY, rows[:1])
    assert design_report._manoeuvre_lines(m)[0].startswith("Every run ran its manoeuvre's speed")


def test_sobol_indices_of_a_known_function():
    """Y = x1 + 0.2 x2 over uniform factors: x1 carries var 1/12, x2 0.04/12: S1 ≈ ST ≈ 0.96
    and 0.04, the rest 0. With the study's 64 base samples each estimate lies within its 95 %
    bootstrap interval plus a slack for the one case in twenty that an interval misses (0.05
    on the large index, 0.02 and 0.01 on the small ones: a few times the estimators' spread of
    about 1/√N·√(ST(1-ST)) at N = 64)."""
    points = sobol_points(STUDY)
    keys = [f.key for f in STUDY.factors]
    lows = {f.key: f.low for f in STUDY.factors}
    spans = {f.key: f.high - f.low for f in STUDY.factors}
    unit = [{k: (p[k] - lows[k]) / spans[k] for k in keys} for p in points]
    y = [u[keys[0]] + 0.2 * u[keys[1]] for u in unit]
    rows = {r["factor"]: r for r in sobol_indices(STUDY, y)}
    assert rows[keys[0]]["ST"] == pytest.approx(1 / 1.04, abs=rows[keys[0]]["ST_conf"] + 0.05)
    assert rows[keys[1]]["ST"] == pytest.approx(0.04 / 1.04, abs=rows[keys[1]]["ST_conf"] + 0.02)
    for k in keys[2:]:
        assert abs(rows[k]["ST"]) <= rows[k]["ST_conf"] + 0.01
    assert len(points) == STUDY.sobol_base_samples * (len(keys) + 2)


def test_mitigations_are_ranked_state_by_state_and_only_beyond_the_noise():
    def rows(name, splits_pct):
        return [{"role": "mitigation", "mitigation": name, "sample": k, "status": "ok",
                 "split_change_rel": v / 100, "pull_deg": 0.1}
                for k, v in enumerate(splits_pct)]
    study = dataclasses.replace(STUDY, mitigations=[Mitigation(name=n) for n in "abc"])
    base = [5.0, 1.0, 3.0, 8.0, 2.0, 6.0, 4.0, 7.0]  # 8 states: a sign test needs 7 of 8
    a = [x - 0.9 for x in base]
    b = [x - 0.85 for x in base]  # 0.05 % above a in every state
    c = [x + 0.5 for x in base]
    table = tables.mitigation_table(study, rows("baseline", base) + rows("a", a) + rows("b", b)
                                    + rows("c", c), "baseline")
    assert [m["mitigation"] for m in table] == ["baseline", "a", "b", "c"]
    assert table[1]["paired"]["median"] == pytest.approx(-0.9)
    assert table[1]["paired"]["share_lower"] == 1.0
    assert table[1]["paired"]["sign_test_p"] == pytest.approx(2 / 2 ** 8)
    text = design_answers._mitigation_answer(table, noise=0.09)  # a - b = -0.05: noise
    assert "not separable" in text and "higher: c" in text
    assert "The best: a" in design_answers._mitigation_answer(table, noise=0.01)
    mixed = [x - 0.9 if k % 2 else x - 0.5 for k, x in enumerate(base)]  # half the states
    table = tables.mitigation_table(study, rows("baseline", base) + rows("a", a)
                                    + rows("b", mixed) + rows("c", c), "baseline")
    assert "not separable" in design_answers._mitigation_answer(table, noise=0.01)
    same = tables.mitigation_table(study, sum((rows(n, base) for n in ("baseline", *"abc")),
                                               []), "baseline")
    assert "None lowers the split" in design_answers._mitigation_answer(same, noise=0.09)


def test_mitigations_judge_each_state_against_its_runs_own_errors():
    # Errors as jam_cases.apply gives them (fractions of the corner load): a state whose change
    # is within the two runs' errors summed is neither lower nor higher.
    def rows(name, splits_pct, errors_pct, converged="yes"):
        return [{"role": "mitigation", "mitigation": name, "sample": k, "status": "ok",
                 "split_change_rel": v / 100, "split_change_rel_error": e / 100,
                 "split_change_rel_converged": converged, "pull_deg": 0.1}
                for k, (v, e) in enumerate(zip(splits_pct, errors_pct))]
    base = [5.0, 1.0, 3.0, 8.0]
    a = [x - 0.5 for x in base]
    errors = [0.1, 0.1, 0.3, 0.1]  # state 2: 0.5 lower, but 0.6 of error: unresolved
    paired = tables.paired_change({r["sample"]: r for r in rows("baseline", base, errors)},
                                  {r["sample"]: r for r in rows("a", a, errors)})
    assert paired["share_lower"] == 0.75 and paired["unresolved"] == 1
    assert paired["error_median"] == pytest.approx(0.2) and paired["not_converged"] == 0
    assert paired["sign_test_p"] == pytest.approx(2 / 2 ** 3)  # over the 3 resolved states
    jumping = tables.paired_change({r["sample"]: r for r in rows("baseline", base, errors)},
                                   {r["sample"]: r for r in rows("a", a, [1.7] * 4, "no")})
    assert jumping["share_lower"] == 0.0 and jumping["not_converged"] == 4
    # A median change within the states' median error is no improvement, whatever the noise.
    assert not design_answers._better(dict(paired, error_median=0.6, sign_test_p=0.01), 0.0)
    assert design_answers._better(dict(paired, sign_test_p=0.01), 1.0)


def test_jam_cases_are_the_refined_parts_runs_at_or_above_the_jam_mu_s():
    study = design_smoke.quick(STUDY)[0]
    parts = {"map": design_runs.map_scenes(study), "line": design_runs.line_scenes(study),
             "mc": design_runs.monte_carlo_scenes(study),
             "mitigation": design_runs.mitigation_scenes(study)}
    jam = jam_cases.jam_scenes(study, parts)
    assert jam and all(s.friction.law.mu_s >= 0.3 for s in jam.values())
    assert not any(n.startswith("mc_") for n in jam)  # the Monte Carlo is not a refined part
    every = [n for role in ("map", "mitigation") for n, (s, _) in parts[role].items()
             if s.friction.law.mu_s >= 0.3]
    assert sorted(jam) == sorted(every)
    none = dataclasses.replace(study, accuracy=Accuracy(parts=["sobol"]))
    assert jam_cases.jam_scenes(none, parts) == {}


def test_rows_carry_their_runs_own_errors_or_the_noise_sample_s():
    @dataclasses.dataclass
    class Refined:  # what jam_cases.apply reads of sweep.refine.Refined
        outcomes: dict
        steps_s: dict

        def run_wall_s(self, name):
            return 12.5
    refined = Refined({("map0_001", "split_change_rel"): {
        "value": 0.05, "error": 0.017, "converged": False, "step_s": 1.25e-4,
        "values": [0.067, 0.067, 0.05, 0.067]}}, {"map0_001": [1e-3, 5e-4, 2.5e-4, 1.25e-4]})
    rows = [{"name": n, "status": "ok", "step_s": 1e-3, "split_change_rel": 0.067,
             "pull_deg": math.nan} for n in ("map0_001", "mc_0000")]
    jam_cases.apply(rows, refined, {"split_change_rel": 9e-4, "pull_deg": 0.04})
    jam, other = rows
    assert jam["split_change_rel"] == 0.05 and jam["split_change_rel_error"] == 0.017
    assert jam["split_change_rel_converged"] == "no"
    assert jam["split_change_rel_values"] == "0.067;0.067;0.05;0.067"
    assert jam["refine_wall_s"] == 12.5 and math.isnan(other["refine_wall_s"])
    assert other["split_change_rel_error"] == 9e-4
    assert other["split_change_rel_error_from"] == "noise sample"
    assert other["split_change_rel_converged"] == "-"
    assert math.isnan(other["pull_deg_error"])  # no pull measured: no error either


def test_the_refinement_s_cost_counts_each_distinct_run_once_in_its_loops(monkeypatch):
    # docs/findings/design.md's run: 832 distinct runs took 2140 s, their 695 refinement runs
    # 5937 s, 3.77 x. Here: a row's run and its twin row count once, level 0 is the study's
    # own run, two names of one halved scene count once, a halved run that is also a row's
    # (a noise sample's half step of a jam case) is the study's, a failed row and "extra" not
    # at all. Runs are keyed as the sweep keys them (here: by their scene, a string).
    monkeypatch.setattr(jam_cases, "key_parts", lambda scene: scene)
    monkeypatch.setattr(jam_cases, "run_key", lambda parts: parts)

    def run(key, cpu):
        return types.SimpleNamespace(scene=key, cpu_s=cpu)
    rows = [{"hash": "a", "status": "ok", "run_cpu_s": 4.0},
            {"hash": "a", "status": "ok", "run_cpu_s": 4.0},
            {"hash": "b", "status": "ok", "run_cpu_s": 6.0},
            {"hash": "n", "status": "ok", "run_cpu_s": 8.0},
            {"hash": "c", "status": "failed", "run_cpu_s": math.nan}]
    refined = types.SimpleNamespace(runs={
        0: {"m1": run("a", 4.0)}, 1: {"m1": run("a1", 8.0), "m2": run("a1", 8.0),
                                      "m3": run("n", 8.0)},
        2: {"m1": run("a2", 16.0)}, "extra": {"x": run("x", 99.0)}})
    loops = jam_cases.loops_cpu_s(refined, rows)
    assert loops == {"unrefined": 18.0, "refinement": 24.0}
    assert "took 18 s of CPU and the refinement 24 s: the study with it 2.33 ×" in \
        jam_cases._cost(loops)
    assert jam_cases._cost(None) == "" and jam_cases._cost({"unrefined": 0.0}) == ""


def test_a_map_s_boundary_is_drawn_no_finer_than_each_cell_s_error_and_names_open_cells():
    spec = dataclasses.replace(STUDY.maps[0], points=3)
    values = [0.5, 0.9, 2.0]  # % of the corner load, along μs; the threshold is 1 %
    rows = []
    for _ in range(3):
        for k, v in enumerate(values):
            rows.append({"status": "ok", "split_change_rel": v / 100,
                         "split_change_rel_error": (0.2 if k == 1 else 0.0) / 100,
                         "split_change_rel_converged": "no" if k == 1 else "yes",
                         "split_change_rel_values": "0.009;0.011;0.009"})
    text = design_answers.boundary_lines(STUDY, spec, rows, "split_change_rel", 100.0, 1.0,
                                        "The lasting split")
    assert "(within the error)" in text and "(beyond it)" in text
    assert "Not converged at the finest step tried" in text and "+0.90 / +1.10 / +0.90" in text
    # Errors larger than the values (a cell not converged, its error the span of its steps)
    # make no cell surely above the threshold: |v| - error is floored at 0, not folded up.
    wide = [dict(r, split_change_rel=v / 100, split_change_rel_error=0.015,
                 split_change_rel_converged="yes")
            for r, v in zip(rows, [0.2, 0.3, 0.4] * 3)]
    text = design_answers.boundary_lines(STUDY, spec, wide, "split_change_rel", 100.0, 1.0,
                                        "The lasting split")
    assert text.count("from already at μs = 0.05 (within the error) to nowhere in the range "
                      "(beyond it)") == 3


def test_a_bad_accuracy_section_is_refused_by_its_key(tmp_path):
    for text, says in (("parts: [map, sobl]", "accuracy.parts: 'sobl' not a part"),
                       ("split_tolerance: 0.0", "accuracy.split_tolerance = 0.0 must be"),
                       ("finest_step_s: .nan", "accuracy.finest_step_s = nan must be"),
                       ("finest_step_s: 5.0e-4", "must be at most a quarter of the base"),
                       ("parts: [map, map]", "must be a list of distinct parts")):
        spec = tmp_path / "study.yaml"  # the section replaced (a key given twice is refused)
        shipped = resource("scenes/studies/design.yaml").read_text()
        spec.write_text(shipped[:shipped.index("  accuracy: {")] + f"  accuracy: {{{text}}}\n")
        with pytest.raises(SceneError, match=says.replace("[", r"\[")):
            load_study(spec, "study")


def test_answers_say_when_no_pull_was_measured():
    study = dataclasses.replace(STUDY, maps=[], mitigations=[])
    jam = {"runs": 3, "split": {"n": 3, "median": 0.5, "p90": 1.1, "share_above": 1 / 3},
           "pull": {"n": 0}}  # every run ended before the pull distance
    (first,) = design_answers.answers(study, [], None, jam, [], {})
    assert "the pull not measured" in first and "0.50 %" in first


def test_the_study_s_runs():
    quick = design_smoke.quick(STUDY)[0]
    maps = design_runs.map_scenes(quick)
    assert len(maps) == sum(m.points ** 2 for m in quick.maps)
    lines = design_runs.line_scenes(STUDY)
    assert len(lines) == len(STUDY.line_mu_s) * sum(len(line.values) for line in STUDY.lines)
    scene, values = lines["line1_mu1_04"]
    assert scene.car.front.top_mount_stiffness_Npm == STUDY.lines[1].values[4]
    assert scene.friction.law.mu_s == STUDY.line_mu_s[1] and values["line"] == STUDY.lines[1].key
    mc = design_runs.monte_carlo_scenes(STUDY, samples=2)
    scene = next(iter(mc.values()))[0]
    # Hands off: the driver lets go where the hands-on run ends, so place b (the last 0.5 s
    # before) is one window for both.
    on = STUDY.base.manoeuvre.timeline
    assert scene.steering.release_s == pytest.approx(on.duration_s)
    assert scene.manoeuvre.timeline.duration_s > on.duration_s + STUDY.pull_distance_m / on.speed_mps
    mitigations = design_runs.mitigation_scenes(quick)
    assert len(mitigations) == (len(quick.mitigations) + 1) * quick.mitigation_samples
    # Each group over the same jam states at the mitigations' μs; the car as it is first.
    quick_mc = design_runs.monte_carlo_scenes(quick, samples=2)
    first = mitigations["mitigation0_0001"][0]
    assert first.friction.law.mu_s == STUDY.mitigation_mu_s
    assert first.road == quick_mc["mc_0001"][0].road
    lower = [m for m in STUDY.mitigations if "friction" in m.scene_text]
    assert lower  # a group equal to the Monte Carlo's runs shares their hashes: run once
    j = 1 + STUDY.mitigations.index(lower[0])
    assert scene_hash(mitigations[f"mitigation{j}_0001"][0]) == scene_hash(quick_mc["mc_0001"][0])
    parts = {"map": maps, "line": lines, "mc": mc}
    sample = design_runs.noise_sample(dataclasses.replace(STUDY, noise_samples=6), parts)
    assert len(sample) == len(set(sample)) == 6
    assert all(sum(name in part for name in sample) == 2 for part in parts.values())


@pytest.mark.slow
def test_design_study_quick_end_to_end(tmp_path):
    out = tmp_path / "design"
    command = [sys.executable, str(ROOT / "experiments" / "design.py"), "--out",
               str(out), "--quick", "--refine", "local"]
    result = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, timeout=900)
    assert result.returncode == 0, result.stderr[-3000:]
    study = out / "study"
    text = (out / "report.md").read_text()
    assert "## One factor at a time" in text and "## Accuracy where the struts jam" in text
    # A smoke test says so on every page: the report's title, the answers, summary.json and
    # stderr (the figures' titles: tests/test_your_car.py).
    assert "(SMOKE TEST: not findings)" in text.splitlines()[0]
    assert "Smoke test (--quick)" in result.stderr
    assert "the paper's geometry" not in text
    for name in ("table.csv", "summary.json", "sobol.png", "monte_carlo.png", "lines.png",
                 "map0_split_change_rel.png", "map0_pull_deg.png"):
        assert (study / name).stat().st_size > 0, name
    summary = json.loads((study / "summary.json").read_text())
    assert summary["runs"]["failed"] == 0 and summary["answers"]
    assert summary["smoke_test"]["changes"] and "not findings" in summary["smoke_test"]["note"]
    table = (study / "table.csv").read_text().splitlines()
    assert len(table) - 1 == summary["runs"]["total"]
    with open(study / "table.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    # Accuracy on demand, local route: every jam case of the refined parts
    # (Sobol's included) resolved its events, its row from that run; the others at the study's
    # step with the noise sample's error, the noise sample drawn from them.
    resolved = [r for r in rows if r["resolved_by"] == "windows"]
    jam_roles = set(summary["accuracy"]["parts"])
    assert {r["name"] for r in resolved} == {
        r["name"] for r in rows if r["role"] in jam_roles and float(r["friction.law.mu_s"]) >= 0.3}
    assert any(r["role"] == "sobol" for r in resolved)
    assert summary["accuracy"]["route"] == "local" and summary["accuracy"]["runs"] == len(resolved)
    for r in resolved:
        record = json.loads((out / "sweep" / "runs" / r["hash"] / "run.json").read_text())
        assert record["resolution"]["window_count"] == int(r["windows"])
        assert r["split_change_rel_error_from"] in ("windows", "noise sample (no window opened)")
    assert any(r["split_change_rel_error_from"] == "windows" for r in resolved)
    others = [r for r in rows if r["resolved_by"] == "-"]
    assert all(r["split_change_rel_error_from"] == "noise sample" for r in others)
    names = {r["name"] for r in resolved}
    assert not any(r["of"] in names for r in rows if r["role"] == "noise")
    # Rerunning reuses every finished run (rows of equal scenes share one run).
    with open(study / "table.csv", newline="") as f:
        runs = {row["hash"] for row in csv.DictReader(f)}
    assert len(runs) < len(table) - 1  # the mitigations' lower-friction group is the MC's
    again = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, timeout=900)
    assert again.returncode == 0
    assert json.loads((study / "summary.json").read_text())["runs"]["reused"] == len(runs)


@pytest.mark.slow
def test_design_study_quick_on_the_global_route(tmp_path):
    """--refine global (the default, the reference): every jam case ran at three steps or more and says
    whether it converged; the others carry the noise sample's error."""
    out = tmp_path / "design"
    result = subprocess.run([sys.executable, str(ROOT / "experiments" / "design.py"), "--out",
                             str(out), "--quick", "--refine", "global"], cwd=ROOT,
                            capture_output=True, text=True, timeout=900)
    assert result.returncode == 0, result.stderr[-3000:]
    summary = json.loads((out / "study" / "summary.json").read_text())
    with open(out / "study" / "table.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    refined = [r for r in rows if r["split_change_rel_error_from"] == "own steps"]
    assert refined and all(float(r["friction.law.mu_s"]) >= 0.3 for r in refined)
    assert all(r["resolved_by"] == "halving" for r in refined)
    assert any(r["role"] == "sobol" for r in refined)
    assert all(r["split_change_rel_converged"] in ("yes", "no") for r in refined)
    assert all(len(r["split_change_rel_values"].split(";")) >= 3 for r in refined)
    assert all(float(r["split_change_rel_step_s"]) <= float(r["step_s"]) / 4 for r in refined)
    assert summary["accuracy"]["runs"] == len(refined)
    loops = summary["accuracy"]["loops_cpu_s"]  # the cost, in the runs' loops, reported
    assert loops["unrefined"] > 0 and loops["refinement"] > 0, loops
    assert "the study with it" in (out / "report.md").read_text()


def test_the_study_runs_on_another_tyre_file_laid_over_its_base_scene():
    sedan = ROOT / "tests" / "data" / "tyres" / "Sedan_Pac02Tire.tir"
    study = load_study(resource("scenes/studies/design.yaml"), "study",
                       f"{{tyres: !MagicFormula {{tir_file: {sedan}}}}}")
    assert study.base.tyres.tir_file == str(sedan)
    assert study.base.friction.law.mu_s == STUDY.base.friction.law.mu_s  # the rest as it was
    quick = design_smoke.quick(study)[0]
    scenes = [s for part in (design_runs.map_scenes(quick), design_runs.mitigation_scenes(quick))
              for s, _ in part.values()]
    assert scenes and all(s.tyres.tir_file == str(sedan) for s in scenes)
    with pytest.raises(SceneError, match="tyres"):
        load_study(resource("scenes/studies/design.yaml"), "study",
                   "{tyres: !MagicFormula {tir_fiel: x.tir}}")


def test_the_noise_sample_leaves_out_the_pairs_of_refined_runs():
    rows = [{"name": "map0_001", "role": "map", "status": "ok", "split_change_rel": 0.067},
            {"name": "noise_map0_001", "role": "noise", "status": "ok", "of": "map0_001",
             "split_change_rel": 0.050},  # a branch jump of a jam case
            {"name": "mc_0000", "role": "mc", "status": "ok", "split_change_rel": 0.0050},
            {"name": "noise_mc_0000", "role": "noise", "status": "ok", "of": "mc_0000",
             "split_change_rel": 0.0052}]
    for row in rows:
        row.update({k: math.nan for k in OUTCOMES if k != "split_change_rel"})
    assert tables.noise_levels(rows)["split_change_rel"] == pytest.approx(0.017)
    assert tables.noise_levels(rows, exclude={"map0_001"})["split_change_rel"] == \
        pytest.approx(0.0002)
