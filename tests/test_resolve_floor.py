"""benchmarks/resolve_floor.py's arithmetic on a made-up pair of job folders: a window a b run
takes over from its a run is counted once, a window's solver twin (inside its finest level's
CPU) is counted apart, the floor keeps the first three levels only, and a folder that is not
what the option says is refused in one line."""

import importlib.util
import json
from pathlib import Path

import pytest

from drake_car.law.errors import InputError

ROOT = Path(__file__).resolve().parents[1]


def _module():
    spec = importlib.util.spec_from_file_location("resolve_floor",
                                                  ROOT / "benchmarks" / "resolve_floor.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _window(start, cpus, twin, merged_twin=0.0, merged_cpu=0.0):
    levels = [{"step_s": 1e-3 / 2 ** k, "steps": 10, "cpu_s": c,
               "positions": {"left_translation": 1e-3 + 1e-6 * k, "right_translation": 2e-3}}
              for k, c in enumerate(cpus)]
    levels[-1]["cpu_s"] += twin  # the twin runs beside the finest level
    return {"start_s": start, "end_s": start + 0.5, "levels": levels,
            "solver_twin": {"steps": 10, "cpu_s": twin},
            "merged": {"windows": 0, "cpu_s": merged_cpu, "steps": 0,
                       "solver_cpu_s": merged_twin},
            "cpu_s": sum(cpus) + twin + merged_cpu + 0.5}  # 0.5 s of bookkeeping


def _job(folder, runs, cpu_s, refinement=True):
    folder.mkdir()
    for name, windows in runs.items():
        (folder / name).mkdir()
        (folder / name / "run.json").write_text(json.dumps({"resolution": {"windows": windows}}))
    summary = {"cpu_s": cpu_s, "provenance": {"git_commit": "abc"},
               "refinement": ({"runs": {n: {"route": "local"} for n in runs}} if refinement
                              else None)}
    (folder / "summary.json").write_text(json.dumps(summary))


def test_floor_counts_a_shared_window_once_and_keeps_three_levels(tmp_path, capsys):
    shared = _window(0.9, [1.0, 2.0, 4.0], twin=3.0)          # before the branch: in both
    deep = _window(5.0, [1.0, 2.0, 4.0, 8.0, 16.0], twin=5.0, merged_twin=1.0, merged_cpu=2.0)
    _job(tmp_path / "local", {"a_3": [shared, deep], "b_3": [shared]}, cpu_s=100.0)
    _job(tmp_path / "nv", {}, cpu_s=20.0, refinement=False)
    _module().main([str(tmp_path / "local"), "--no_verify", str(tmp_path / "nv")])
    out = capsys.readouterr().out
    # windows without twins: shared 7 + 0.5 = 7.5; deep 31 + 2 (merged, of it 1 its twin)
    # + 0.5 - 1 = 32.5 -> 40.0 s; twins 3 + 5 + 1 = 9; the rest 100 - 40 - 9 = 51
    assert "2 windows 40.0 s, their solver twins 9.0 s" in out
    assert "own work) 51.0 s" in out
    # the floor: shared whole (7.5); deep less its 4th and 5th levels (8 + 16): 8.5 -> 16.0 s;
    # with the twins scaled: 51 + 16 + 9 * 16 / 40 = 70.6 s = 3.53 x; without 67 / 20 = 3.35 x
    assert "every window at its third level: 16.0 s; the floor 70.6 s = 3.53 x" in out
    assert "without them 3.35 x" in out


def test_a_job_with_accuracy_on_demand_is_refused_as_the_no_verify_one(tmp_path):
    _job(tmp_path / "local", {"a_3": [_window(0.9, [1.0, 2.0, 4.0], twin=1.0)]}, cpu_s=10.0)
    with pytest.raises(InputError, match="--no_verify .*a job with accuracy on demand"):
        _module().main([str(tmp_path / "local"), "--no_verify", str(tmp_path / "local")])
    with pytest.raises(InputError, match="summary.json: missing"):
        _module().main([str(tmp_path / "nowhere"), "--no_verify", str(tmp_path / "local")])
