"""The package installed from a built wheel (not editable), run from another folder: it finds
its shipped scenes, its tyre data and the lane change's calibration as package data."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_a_wheel_installs_and_runs_from_any_folder(tmp_path):
    wheels, target, elsewhere = tmp_path / "wheels", tmp_path / "site", tmp_path / "elsewhere"
    elsewhere.mkdir()
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--quiet", "-w",
                    str(wheels), str(ROOT)], check=True, capture_output=True, timeout=600)
    (wheel,) = wheels.glob("drake_car-*.whl")
    subprocess.run([sys.executable, "-m", "pip", "install", "--no-deps", "--quiet", "--target",
                    str(target), str(wheel)], check=True, capture_output=True, timeout=600)
    env = dict(os.environ, PYTHONPATH=str(target))
    probe = subprocess.run(
        [sys.executable, "-c",
         "import drake_car, sys; from drake_car.scene.load import shipped_scenes; "
         "print(drake_car.__file__); print(len(shipped_scenes()))"],
        cwd=elsewhere, env=env, capture_output=True, text=True, timeout=300, check=True)
    where, count = probe.stdout.split()
    assert Path(where).is_relative_to(target), f"imported {where}, not the installed wheel"
    assert int(count) >= 10
    scene = target / "drake_car" / "data" / "scenes" / "paper_study.yaml"
    run = subprocess.run(
        [sys.executable, "-m", "drake_car.commands.run", "--scene", f"{scene}:a_3", "--scene_text",
         "simulator: {end_time_s: 0.1}", "--out", str(elsewhere / "out"), "--quiet"],
        cwd=elsewhere, env=env, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    assert (elsewhere / "out" / "history.csv").is_file()


def test_every_console_script_names_a_command_with_help():
    """Every console script of pyproject.toml names a ``console`` function of a module whose
    parser's --help says what it writes (an --out folder, or a folder it reads)."""
    import importlib
    import tomllib
    scripts = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]
    # Every command module with a console() is installed, and the README names its script.
    commands = {f"drake_car.commands.{p.stem}:console"
                for p in (ROOT / "drake_car" / "commands").glob("*.py")
                if "def console(" in p.read_text()}
    assert commands == set(scripts.values()), commands ^ set(scripts.values())
    readme = (ROOT / "README.md").read_text()
    assert all(f"`{name}`" in readme for name in scripts), [
        name for name in scripts if f"`{name}`" not in readme]
    for name, target in scripts.items():
        module, _, function = target.partition(":")
        assert callable(getattr(importlib.import_module(module), function)), name
        shown = subprocess.run([sys.executable, "-m", module, "--help"], cwd=ROOT,
                               capture_output=True, text=True, timeout=300)
        assert shown.returncode == 0, (name, shown.stderr[-1000:])
        # what it writes: an --out folder, or (drake-car-cache) the cache folder it reads and
        # clears
        assert "--out" in shown.stdout or "~/.cache/drake_car" in shown.stdout, (
            name, shown.stdout[:500])
