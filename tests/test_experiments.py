"""The commands and experiment scripts, run as a user runs them: their files, their columns;
the main job end to end on a shortened timeline."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from drake_car.results.files import read_csv
from drake_car.study.paper.outcomes import read_outcomes

ROOT = Path(__file__).resolve().parents[1]
# The paper's timeline shortened 20 times (every phase), laid over every run's scene.
# The rack as given (the shipped calibration's profile): none is calibrated for such a timeline.
SHORT = ("manoeuvre: !LaneChange {timeline: {settle_s: 0.04, speed_up_s: 0.15, "
         "straight_s: 0.06, steer_s: 0.12, calm_s: 0.13}, amplitude_m: 0.005908525382359731, "
         "second_lobe: 1.012425560052948}")


def run(args, check=True, timeout=900):
    """Runs ``python ARGS`` from the project's root (a script path or ``-m module``)."""
    result = subprocess.run([sys.executable, *map(str, args)], cwd=ROOT, capture_output=True,
                            text=True, timeout=timeout)
    if check:
        assert result.returncode == 0, result.stderr[-3000:]
    return result


def test_generic_run_command_and_rerun_of_its_scene(tmp_path):
    first, second = tmp_path / "first", tmp_path / "second"
    run(["-m", "drake_car.commands.run", "--scene", "scenes/paper_study.yaml", "--child", "a_3",
         "--scene_text", "simulator: {end_time_s: 0.3}", "--out", first, "--quiet"])
    for name in ("history.csv", "scene.yaml", "run.json", "diagram.svg"):
        assert (first / name).stat().st_size > 0, name
    assert "<svg" in (first / "diagram.svg").read_text()[:3000]
    # The saved scene is what ran: rerun, it gives the same history bit for bit.
    run(["-m", "drake_car.commands.run", "--scene", first / "scene.yaml", "--out", second, "--quiet"])
    assert (first / "history.csv").read_bytes() == (second / "history.csv").read_bytes()
    record = json.loads((first / "run.json").read_text())
    assert record["frozen_sap_steps"] == 0 and record["steps"] == 300


def test_settle_script(tmp_path):
    out = tmp_path / "settle"
    run(["experiments/settle.py", "--out", out, "--scene_text",
         "manoeuvre: !Settle {duration_s: 0.3}"])
    data = json.loads((out / "settle.json").read_text())
    for key, members in (("corner_loads_N", {"fl", "fr", "rl", "rr"}),
                         ("ride_height_m", {"front", "rear"}),
                         ("strut_overlap_m", {"left", "right"}),
                         ("design_axle_loads_N", {"front", "rear"})):
        assert set(data[key]) == members, key
        assert all(np.isfinite(v) for v in data[key].values()), key
    assert data["total_mass_kg"] > 0
    assert (out / "settle.png").stat().st_size > 0


def test_kinematics_script(tmp_path):
    out = tmp_path / "kin"
    run(["experiments/kinematics.py", "--out", out, "--points", 5, "--scene_text",
         "car: {front: {ball_joint_offset_b_m: 0.06}}"])
    table = read_csv(out / "kinematics.csv")
    assert list(table)[:8] == ["side", "wheel_travel_m", "camber_deg", "toe_deg", "caster_deg",
                               "kingpin_deg", "strut_length_m", "overlap_m"]
    steering = read_csv(out / "steering.csv")
    assert list(steering)[:3] == ["rack_m", "steer_left_deg", "steer_right_deg"]
    assert (out / "kinematics.png").exists() and (out / "steering.png").exists()


def test_friction_rig_script(tmp_path):
    out = tmp_path / "rig"
    run(["experiments/friction_rig.py", "--out", out, "--duration_s", 0.05, "--force_N", 100,
         "--friction", "{law: {mu_s: 0.4, mu_d: 0.3}}"])
    h = read_csv(out / "history.csv")
    assert list(h) == ["t", "x_m", "v_mps", "creep_m", "mu", "phase", "friction_N"]
    assert all(np.all(np.isfinite(v)) for v in h.values())
    assert json.loads((out / "rig.json").read_text())["law"]["mu_s"] == 0.4
    assert (out / "history.png").exists()


@pytest.mark.slow
def test_car_checks_script(tmp_path):
    out = tmp_path / "car"
    run(["experiments/car_checks.py", "--out", out])
    for name in ("report.md", "settle/settle.json", "kinematics/kinematics.csv",
                 "jammed/replay.html", "jammed/diagram.svg", "jammed/scene.yaml"):
        assert (out / name).stat().st_size > 0, name
    assert "strut_friction" in (out / "jammed" / "diagram.svg").read_text()


@pytest.mark.slow
def test_main_job_smoke(tmp_path):
    """The README's main job on a timeline shortened 20 times, with accuracy on demand's global
    route (--refine global: every run halved whole) down to 1/8 of the step: the report, outcomes.csv (every run's deciding outcomes with its own error
    or "not converged"), the six runs (each with its scene as it ran), the figures and the
    replay."""
    out = tmp_path / "study"
    result = run(["experiments/paper.py", "--out", out, "--scene_text", SHORT,
                  "--finest_step_s", 1.25e-4, "--refine", "global"])
    report = (out / "report.md").read_text()
    assert "| 1 |" in report and "| 6 |" in report and "## Sets and cases" in report
    summary = json.loads((out / "summary.json").read_text())
    assert len(summary["claims"]) == 6
    assert all(isinstance(c["reproduced"], bool) for c in summary["claims"])
    outcomes = read_outcomes(out / "outcomes.csv")
    header = (out / "outcomes.csv").read_text().splitlines()[0].split(",")
    assert header[:7] == ["run", "outcome", "value", "error", "unit", "step_s", "converged"]
    for name in ("a_1", "a_2", "a_3", "b_1", "b_2", "b_3"):
        row = outcomes[(name, "split_change")]
        assert row["steps_s"][:3] == [1e-3, 5e-4, 2.5e-4] and 1.25e-4 <= row["step_s"] <= 2.5e-4
        assert row["value"] == row["values"][-1] and row["converged"] in (True, False)
        x0, x1, x2 = row["values"][-3:]
        # The solver axis: a twin at the run's finest step with SAP's tolerance loosened.
        assert row["solver_error"] is not None and row["solver_error"] >= 0
        if row["converged"]:  # the same run's last differences: the last, no less than the
            # one before halved (first order), within the tolerance, or within what the
            # solver alone moves it by (the solver's floor)
            error = max(abs(x1 - x2), abs(x0 - x1) / 2)
            floored = max(abs(x0 - x1), abs(x1 - x2)) <= row["solver_error"]
            assert (error <= row["tolerance"] or floored) and row["error"] == error
        else:  # never a number with a small error: the span of its last steps
            assert row["error"] == pytest.approx(max(x0, x1, x2) - min(x0, x1, x2))
    assert ("a_3|b_3", "mirror_residual_m") in outcomes
    claims_table = report.split("## The paper's claims")[1].split("\n## ")[0]
    for claim, line in zip(summary["claims"], claims_table.splitlines()[4:10]):
        assert ("undecided at the finest step tried" in line) is (claim["decided"] is False)
    for name in ("a_1", "a_2", "a_3", "b_1", "b_2", "b_3"):
        h = read_csv(out / f"{name}.csv")
        assert all(np.all(np.isfinite(v)) for k, v in h.items() if k != "phase")
        assert "steer_s: 0.12" in (out / name / "scene.yaml").read_text()
    # Each run's folder and CSV are the run at the finest step it was refined to (the numbers'
    # run), its scene.yaml that run's; the replay, made at the scene's own step, kept beside.
    for name in ("a_1", "a_3"):
        step = outcomes[(name, "split_change")]["step_s"]
        assert f"    time_step: {step}\n" in (out / name / "scene.yaml").read_text(), name
    assert (out / "a_3" / "replay.html").stat().st_size > 0
    for name in ("fig13.png", "fig14_a.png", "fig15_b.png", "fig16.png", "diagram.svg"):
        assert (out / name).stat().st_size > 0, name
    assert "claims reproduced" in result.stdout
    assert summary["refinement"]["finest_step_s"] >= 1.25e-4


@pytest.mark.slow
def test_main_job_smoke_local_route(tmp_path):
    """The main job's local route (--refine local) on the shortened timeline: the dry runs resolve their
    events locally (outcomes.csv says "local", how many windows and events, the finest step
    and the CPU they took), the runs without dry friction are halved whole (route "global");
    the report says how each run was made accurate."""
    out = tmp_path / "study"
    run(["experiments/paper.py", "--out", out, "--scene_text", SHORT, "--no_html",
         "--refine", "local"])
    outcomes = read_outcomes(out / "outcomes.csv")
    for name in ("a_1", "a_2", "a_3", "b_1", "b_2", "b_3"):
        row = outcomes[(name, "split_change")]
        assert np.isfinite(row["value"]), name
        if name.endswith("_1"):  # no dry friction: no events, refined globally
            assert row["route"] == "global" and row["steps_s"][:3] == [1e-3, 5e-4, 2.5e-4]
        else:
            assert row["route"] == "local", name
            assert row["windows"] >= 0 and row["events_resolved"] >= 0
            assert row["run_cpu_s"] is not None and row["run_cpu_s"] > 0
            if row["windows"]:  # a window's finest step is a halving of the run's
                assert row["finest_step_s"] <= 0.5e-3
    report = (out / "report.md").read_text()
    assert "## How each run was made accurate, and what it cost" in report
    summary = json.loads((out / "summary.json").read_text())
    assert summary["refinement"]["route"] == "local"
    # summary.json holds all a report says: read back (its int keys now strings), it makes the
    # same report
    from drake_car.study.paper.report import report as paper_report
    assert paper_report(summary) == report


@pytest.mark.slow
def test_accuracy_sweep_smoke(tmp_path):
    """The accuracy sweep on a timeline shortened 30 times, a_3 and b_3 with the fast scheme at
    two steps and the explicit one at one: a row per run, scheme, step and outcome, the mirror
    residual between a_3 and b_3, a work-precision figure per outcome, the branches named."""
    out = tmp_path / "accuracy"
    run(["experiments/accuracy.py", "--out", out, "--scale_time", 0.033, "--runs",
         "a_3,b_3", "--fast_steps", "2e-3,1e-3", "--explicit_runs", "a_3", "--explicit_steps",
         "6e-6", "--runs_dir", tmp_path / "runs"])
    header = (out / "accuracy_cost.csv").read_text().splitlines()[0].split(",")
    for column in ("run", "scheme", "time_step_s", "outcome", "value", "reference", "error",
                   "cpu_s"):
        assert column in header
    rows = (out / "accuracy_cost.csv").read_text().splitlines()[1:]
    assert len(rows) == (2 + 2 + 1) * 8
    assert "mirror_mm" in (out / "outcomes_by_step.csv").read_text().splitlines()[0]
    assert (out / "accuracy_cost_split_pct.png").is_file()
    assert "a_3: lasting split" in (out / "branches.txt").read_text()
