"""Ctrl-C (review rv44): one line on stderr, exit status 130, no traceback, whenever it comes.

- while a command imports its heavy modules (the first 1-4 s): before, an import traceback
  and death by SIGINT (``drake_car.commands`` now handles it until ``cli.run_main`` runs);
- during a sweep on a local Dask cluster, sent to the whole process group as a terminal does:
  before, each worker printed a KeyboardInterrupt traceback and Dask its shutdown warnings;
  now the workers ignore it (``sweep.cluster``), the parent shuts them down quietly, the
  finished runs are kept and the one line says so and how to finish.

Each test runs a command in a subprocess (its own session, SIGINT at its default: a test
runner started in the background may have it ignored) and signals it at a moment it observes
(an import finished, a run folder written), never after a guessed delay."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
WAIT_S = 300  # far beyond any of these commands' run; only a hang reaches it


def _start(argv, tmp_path, **kw):
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""),
               DRAKE_CAR_CACHE_DIR=str(tmp_path / "cache"))
    return subprocess.Popen([sys.executable, *argv], env=env, cwd=tmp_path, text=True,
                            stderr=subprocess.PIPE, stdout=subprocess.DEVNULL,
                            start_new_session=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
                            **kw)


def _finish(process):
    try:
        _, err = process.communicate(timeout=WAIT_S)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        process.communicate()
        pytest.fail(f"still running {WAIT_S} s after SIGINT")
    return process.returncode, err


def test_ctrl_c_while_a_command_imports(tmp_path):
    # -X importtime: each import is reported as it completes; SIGINT once the package
    # drake_car.commands is in, while the command's module imports drake and numba
    process = _start(["-X", "importtime", "-m", "drake_car.commands.run", "--scene",
                      f"{ROOT}/scenes/car.yaml:straight", "--out", str(tmp_path / "out")],
                     tmp_path)
    for line in process.stderr:
        if line.rstrip().endswith("| drake_car.commands"):
            process.send_signal(signal.SIGINT)
            break
    else:
        pytest.fail("the command ended before drake_car.commands was imported")
    code, err = _finish(process)
    said = [line for line in err.splitlines() if not line.startswith("import time:")]
    assert code == 130 and said == ["interrupted"], (code, err[-3000:])
    assert not (tmp_path / "out").exists()


def test_ctrl_c_to_a_sweeps_process_group(tmp_path):
    out = tmp_path / "sweep"
    # one short run, then two long ones (their settling cut to 0.3 s): interrupted once the
    # short one's folder is written, while the long ones run on both workers
    process = _start(["-m", "drake_car.commands.sweep", "--scene",
                      f"{ROOT}/scenes/car.yaml:straight", "--out", str(out), "--workers", "2",
                      "--quiet", "--scene_text", "simulator: {equilibrium_settle_s: 0.3}",
                      "--grid", "simulator.end_time_s=0.05,9.5,10.0"], tmp_path)
    began = time.monotonic()
    while process.poll() is None and time.monotonic() - began < WAIT_S:
        runs = out / "runs"
        if runs.is_dir() and any(not p.name.startswith(".") for p in runs.iterdir()):
            break
        time.sleep(0.05)
    assert process.poll() is None, ("the sweep ended before a run was kept",
                                    process.communicate()[1][-3000:])
    time.sleep(1.0)  # the long runs under way on the workers
    os.killpg(process.pid, signal.SIGINT)  # as a terminal's Ctrl-C: every process of it
    code, err = _finish(process)
    lines = [line for line in err.splitlines() if line.strip()]
    assert code == 130, (code, err[-3000:])
    assert "Traceback" not in err and "distributed" not in err and "WARNING" not in err, err
    assert lines[-1].startswith("interrupted: 1 of 3 runs kept in "), err
    assert "the same command again runs the rest" in lines[-1]
    kept = [p for p in (out / "runs").iterdir() if not p.name.startswith(".")]
    assert len(kept) == 1 and (kept[0] / "status.json").is_file()
