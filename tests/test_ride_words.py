"""The ride study's words, from report inputs made here (no simulation): one class's slope is
one value, no "-0 %", and --no_run on a folder of another car's runs says so."""

import dataclasses
import json
import subprocess
import sys
from pathlib import Path

import pytest

from drake_car.scene.scene import Scene
from drake_car.study.ride.report import cost_table, signed, summary_text
from drake_car.sweep.holdings import none_of_these

ROOT = Path(__file__).resolve().parents[1]


def _rows(road_class="B", aw=(0.50, 0.54, 0.58, 0.62, 0.66), rear=(0.1, 0.1, 0.1, 0.1, 0.0999)):
    """A cell's runs: the lubricated car, then μs 0.1 ... 0.4 (a_w linear in μs)."""
    rows = []
    for k, (a, r) in enumerate(zip(aw, rear)):
        rows.append({"name": f"{road_class}_60kph_mu{0.1 * k:.2f}" + ("_damper" if k else ""),
                     "road_class": road_class, "speed_kph": 60.0, "mu_s": 0.1 * k,
                     "strut": "damper" if k else "lubricated", "aw_seat_mps2": a,
                     "err_aw_seat_mps2": 1e-4, "dlc_front": 0.1 + 0.01 * k, "dlc_rear": r,
                     "rig_friction_N": 100.0 * k, "held_speed": True})
    return rows


def test_one_class_s_slope_is_one_value_and_no_change_reads_minus_zero():
    text = summary_text(_rows())
    assert "+0.040 m/s² per 0.1 of μs (linear fit over μs 0-0.4, class B)" in text, text
    assert " to " not in text.split("per 0.1")[0]
    assert "rear 0 % at μs 0.4" in text and "-0 %" not in text and "+0 %" not in text
    two = summary_text(_rows() + _rows("C", aw=(1.0, 1.1, 1.2, 1.3, 1.4)))
    assert "+0.040 to +0.100 m/s² per 0.1 of μs (linear fit over μs 0-0.4, classes B, C)" \
        in two, two
    assert "-0 " not in cost_table(_rows(rear=(0.1,) * 5, aw=(0.5, 0.4999, 0.5, 0.5, 0.5)))
    assert signed(-0.004) == "0" and signed(-0.6) == "-1" and signed(-0.0004, 3) == "0.000"


def _folder_of_another_car(tmp_path):
    """A sweep folder holding two finished runs of another car (their status.json and the
    head of their scene.yaml, as the sweep writes them)."""
    out = tmp_path / "other"
    for key in ("0f339301ceded7b1", "2bd47a0f9d28e577"):
        run = out / "runs" / key
        run.mkdir(parents=True)
        (run / "status.json").write_text(json.dumps({
            "hash": key, "key": {"scene_hash": "1f7c6a206de9c520"}, "status": "ok",
            "name": "B_60kph_mu0.10_damper"}))
        (run / "scene.yaml").write_text("# The scene as it ran (drake_car).\nscene:\n  name: "
                                        "B_60kph_mu0.10_damper\n  car_file: cars/hatch.yaml\n"
                                        "  car:\n    mass: {}\n")
    (out / "index.csv").write_text("hash,name,status,wall_s,error\n")
    return out


def test_no_run_on_another_car_s_folder_says_it_holds_none_of_this_car_s_runs(tmp_path):
    out = _folder_of_another_car(tmp_path)
    scenes = {f"run{k}": dataclasses.replace(Scene(), name=f"run{k}") for k in range(3)}
    text = none_of_these(out, scenes, {}, "this car's ride runs")
    assert text == (f"holds none of this car's ride runs (none of the {len(scenes)} this "
                    "command asks for); it holds 2 finished runs: 2 of other scenes (their "
                    "cars: cars/hatch.yaml: 2); run without --no_run to make them"), text
    assert "holds 1 of this car's ride runs but not with their half-step twins" in \
        none_of_these(out, scenes, {"run0": None}, "this car's ride runs")
    empty = tmp_path / "empty"
    empty.mkdir()
    assert "it holds no finished run;" in none_of_these(empty, scenes, {}, "these runs")


@pytest.mark.slow  # the command makes its scenes first (their launches: about a minute)
def test_the_command_says_it_on_one_line_and_status_2(tmp_path):
    out = _folder_of_another_car(tmp_path)
    result = subprocess.run([sys.executable, "-m", "drake_car.commands.ride", "--out",
                             str(out), "--no_run", "--classes", "B", "--speeds", "60"],
                            capture_output=True, text=True, cwd=ROOT,
                            env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    assert result.returncode == 2, result.stderr
    assert len(result.stderr.strip().splitlines()) == 1
    assert "holds none of the shipped car's ride runs" in result.stderr
    assert "cars/hatch.yaml: 2" in result.stderr
