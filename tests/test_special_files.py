"""An input file that is not a regular file (review rv44): a named pipe would block its reader
for ever (a FIFO's open waits for a writer), a device would be read until memory runs out.
Every reader of an input file refuses them before reading, in one line naming the file (and
the option, where a command gives one). Each reader is called in a thread with a timeout:
before the fix it blocked on the pipe."""

import os

import pytest

from test_sweep import in_thread

from drake_car.law.errors import InputError

TIMEOUT_S = 20.0  # a refusal is a stat and an open: far below this on any machine


def returns(call):
    """What ``call()`` raised or returned, failing the test if it is still blocked after
    TIMEOUT_S (the thread is a daemon: a blocked read does not hold up pytest's exit)."""
    thread, outcome = in_thread(call)
    thread.join(TIMEOUT_S)
    assert not thread.is_alive(), f"still reading the named pipe after {TIMEOUT_S} s"
    return outcome


@pytest.fixture
def fifo(tmp_path):
    path = tmp_path / "pipe"
    os.mkfifo(path)
    yield path
    try:  # a reader still blocked on open() (before the fix) is released by a writer's EOF
        os.close(os.open(path, os.O_WRONLY | os.O_NONBLOCK))
    except OSError:  # no reader left (ENXIO)
        pass


def _readers():
    from drake_car.law.tyre.tir import read_tir_bytes
    from drake_car.scene.guard import read_yaml_file
    from drake_car.scene.load import load_scene
    from drake_car.study.design.spec import load_study
    from drake_car.study.rig.measured import read_loop
    return {"measured loop": read_loop, "tyre property file": read_tir_bytes,
            "scene file": read_yaml_file, "load_scene": load_scene,
            "study file": lambda p: load_study(p, "study")}


@pytest.mark.parametrize("reader", ["measured loop", "tyre property file", "scene file",
                                    "load_scene", "study file"])
def test_a_named_pipe_is_refused_unread(fifo, reader):
    outcome = returns(lambda: _readers()[reader](fifo))
    error = outcome.get("error")
    assert isinstance(error, InputError), outcome
    assert "not a regular file (a named pipe)" in str(error) and "\n" not in str(error)


@pytest.mark.parametrize("reader", ["measured loop", "scene file", "study file"])
def test_a_device_is_refused_unread(reader):
    outcome = returns(lambda: _readers()[reader]("/dev/zero"))
    error = outcome.get("error")
    assert isinstance(error, InputError), outcome
    assert "not a regular file (a character device)" in str(error)


@pytest.mark.parametrize("option, argv", [
    ("--measured", lambda p: ["--quick", "--measured", str(p), "--side_force_N", "1000"]),
    ("--scene", lambda p: ["--scene", str(p)]),
])
def test_the_command_names_the_option(fifo, tmp_path, capsys, option, argv):
    from drake_car.commands import cli
    from drake_car.commands import strut_rig
    args = argv(fifo) + ["--out", str(tmp_path / "out")]
    outcome = returns(lambda: cli.run_main(strut_rig.main, args))
    assert isinstance(outcome.get("error"), SystemExit) and outcome["error"].code == 2, outcome
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"error: {option} {fifo}: not a regular file (a named pipe)"), err
    assert len(err.splitlines()) == 1 and not (tmp_path / "out").exists()


def test_design_names_study(fifo, tmp_path, capsys):
    from drake_car.commands import cli
    from drake_car.commands import design
    outcome = returns(lambda: cli.run_main(design.main, [
        "--study", f"{fifo}:study", "--out", str(tmp_path / "out")]))
    assert isinstance(outcome.get("error"), SystemExit) and outcome["error"].code == 2, outcome
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"error: --study {fifo}: not a regular file (a named pipe)"), err
