"""Smoke tests of the experiment scripts: short runs, their files, their columns, bad options."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from drake_car.outputs import output_folder, read_csv

ROOT = Path(__file__).resolve().parents[1]


def run(script, *args, check=True):
    result = subprocess.run([sys.executable, str(ROOT / "experiments" / script), *map(str, args)],
                            cwd=ROOT,
                            capture_output=True, text=True, timeout=600)
    if check:
        assert result.returncode == 0, result.stderr[-3000:]
    return result


def test_settle_script(tmp_path):
    out = tmp_path / "settle"
    run("settle.py", "--out", out, "--duration_s", 0.3)
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
    run("suspension_kinematics.py", "--out", out, "--points", 5)
    table = read_csv(out / "kinematics.csv")
    assert list(table)[:8] == ["side", "wheel_travel_m", "camber_deg", "toe_deg", "caster_deg",
                               "kingpin_deg", "strut_length_m", "overlap_m"]
    steering = read_csv(out / "steering.csv")
    assert list(steering)[:3] == ["rack_m", "steer_left_deg", "steer_right_deg"]
    assert (out / "kinematics.png").exists() and (out / "steering.png").exists()


def test_friction_rig_script(tmp_path):
    out = tmp_path / "rig"
    run("friction_rig.py", "--out", out, "--duration_s", 0.05, "--force_N", 100)
    h = read_csv(out / "history.csv")
    assert list(h) == ["t", "x_m", "v_mps", "creep_m", "mu", "phase", "friction_N"]
    assert all(np.all(np.isfinite(v)) for v in h.values())
    assert (out / "history.png").exists()


@pytest.mark.parametrize("args, option", [
    (["--mu_s", "0.1", "--mu_d", "0.2"], "mu_s"),
    (["--time_step_s", "-1"], "time_step_s"),
    (["--shape", "quadratic"], "shape"),
    (["--mass_kg", "abc"], "mass_kg"),
])
def test_friction_rig_bad_options_name_the_option(tmp_path, args, option):
    out = tmp_path / "rig"
    result = run("friction_rig.py", "--out", out, *args, check=False)
    assert result.returncode == 2
    assert option in result.stderr
    assert not out.exists(), "nothing may be written on bad input"


def test_main_study_writes_report_and_pictures(tmp_path):
    out = tmp_path / "study"
    run("study.py", "--out", out, "--settle_s", 0.3, "--html_s", 0.05)
    for name in ("report.md", "diagram.svg", "car.html", "phase_I.csv", "phase_I.png",
                 "settle/settle.json", "kinematics/kinematics.csv"):
        assert (out / name).stat().st_size > 0, name
    assert "<svg" in (out / "diagram.svg").read_text()[:2000]
    assert "strut_friction" in (out / "diagram.svg").read_text()
    assert "<html" in (out / "car.html").read_text()[:5000].lower()
    phase = read_csv(out / "phase_I.csv")
    assert all(np.all(np.isfinite(v)) for v in phase.values())


def test_output_folder_is_all_or_nothing(tmp_path):
    target = tmp_path / "out"
    with pytest.raises(RuntimeError):
        with output_folder(target) as staging:
            (staging / "half.csv").write_text("t\n0\n")
            raise RuntimeError("simulation failed")
    assert not target.exists()
    assert not list(tmp_path.iterdir()), "the staging folder must be removed"


def test_drive_script(tmp_path):
    out = tmp_path / "drive"
    run("drive.py", "--out", out, "--case", "b", "--duration_s", 0.3)
    h = read_csv(out / "history.csv")
    required = ["t", "phase", "x_m", "y_m", "yaw_rad", "speed_mps", "rack_m", "steer_fl_deg",
                "steer_fr_deg"] + [f"{f}_{w}_N" for f in ("Fz", "Fy") for w in
                                   ("fl", "fr", "rl", "rr")] + ["Fx_fl_N", "Fx_fr_N"]
    assert set(required) <= set(h), set(required) - set(h)
    assert set(h["phase"]) == {"I"}
    assert all(np.all(np.isfinite(h[c])) for c in required if c != "phase")
    for name in ("path.png", "speed.png", "wheel_loads.png", "drive.json"):
        assert (out / name).stat().st_size > 0, name


def test_scripts_take_scenes(tmp_path):
    out = tmp_path / "drive"
    run("drive.py", "--out", out, "--scene", "scenes/car.yaml:bump",
        "--scene_text", "simulator: {end_time_s: 0.2}")
    assert "road:" in (out / "scene.yaml").read_text()
    out = tmp_path / "settle"
    run("settle.py", "--out", out, "--scene", "scenes/car.yaml:settle_jammed",
        "--scene_text", "simulator: {end_time_s: 0.3}")
    assert json.loads((out / "settle.json").read_text())["friction"]["mu_s"] == 0.4
    bad = run("drive.py", "--out", tmp_path / "bad", "--scene", "scenes/car.yaml:straight",
              "--scene_text", "tyres: {model: brush}", check=False)
    assert bad.returncode == 2 and "tyres.model" in bad.stderr
    assert not (tmp_path / "bad").exists()


SCRIPTS = sorted(path.name for path in (ROOT / "experiments").glob("*.py")
                 if not path.name.startswith("_"))


@pytest.mark.parametrize("script", SCRIPTS)
def test_every_experiment_script_takes_scene_options(tmp_path, script):
    """--scene_text is parsed as a scene: an unknown key stops the script with exit 2, the key
    named, before anything is written."""
    out = tmp_path / "out"
    bad = run(script, "--out", out, "--scene_text", "wheels: {count: 5}", check=False)
    assert bad.returncode == 2 and "wheels" in bad.stderr, bad.stderr[-2000:]
    assert not out.exists()


def test_kinematics_and_rig_take_their_car_and_law_from_a_scene(tmp_path):
    out = tmp_path / "kinematics"
    run("suspension_kinematics.py", "--out", out, "--points", 3, "--scene_text",
        "car: {ball_joint_offset_b_m: 0.06}")
    assert (out / "kinematics.csv").is_file()
    out = tmp_path / "rig"
    run("friction_rig.py", "--out", out, "--duration_s", 0.05, "--force_N", 100,
        "--scene", "scenes/car.yaml:settle_jammed")
    assert json.loads((out / "rig.json").read_text())["law"]["mu_s"] == 0.4
    off = run("friction_rig.py", "--out", tmp_path / "off", "--scene", "scenes/car.yaml:settle",
              check=False)
    assert off.returncode == 2 and "friction mode 'off'" in off.stderr


def test_main_job_smoke(tmp_path):
    """The README's main job on a timeline shortened 20 times (no half-step check, no replay):
    it writes the report, the six runs and the figures."""
    out = tmp_path / "study"
    run("lane_change.py", "--out", out, "--scale_time", 0.05, "--jobs", 1, "--no_verify",
        "--no_html")
    report = (out / "report.md").read_text()
    assert "| 1 |" in report and "| 6 |" in report
    for name in ("a_1", "a_2", "a_3", "b_1", "b_2", "b_3"):
        assert (out / f"{name}.csv").is_file()
    assert (out / "fig14_a.png").is_file() and (out / "diagram.svg").is_file()


def test_accuracy_sweep_smoke(tmp_path):
    """The accuracy sweep with its reference at 0.1 ms on a timeline shortened 30 times: the CSV
    has the issue's columns and a row per case, the plot is drawn."""
    out = tmp_path / "accuracy"
    run("accuracy_cost.py", "--out", out, "--scale_time", 0.033, "--reference_step_s", 1e-4,
        "--steps", "5e-3,2e-3,1e-3,5e-5", "--explicit_step_s", 0)
    header = (out / "accuracy_cost.csv").read_text().splitlines()[0].split(",")
    for column in ("scene", "time_step_s", "friction_scheme", "tyre_model",
                   "max_abs_dd_error_m", "final_dd_error_m", "wall_s", "real_time_factor"):
        assert column in header
    rows = (out / "accuracy_cost.csv").read_text().splitlines()[1:]
    assert len(rows) == 2 * (4 + 6 + 2)
    assert (out / "accuracy_cost.png").is_file()
