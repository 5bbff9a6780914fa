"""Hostile or damaged input from outside (issue 25), beside ``test_bad_input.py``'s table and
under its conventions: exit status 2, one error line naming the key or the path, no
traceback, nothing written, nothing left behind; a planted pickle is never loaded (no marker
file appears); an alias bomb is refused in a process with bounded memory."""

import json
import os
import pickle
import resource
import subprocess
import sys
from pathlib import Path

import pytest

from drake_car.commands import cli
from drake_car.commands import run as run_command
from drake_car.results.folder import OutputError
from drake_car.commands import sweep as sweep_command
from drake_car.sweep import scene_grid
from drake_car.sweep.store import load_run

ROOT = Path(__file__).resolve().parents[1]
BOMB = "\n".join(["a: &a [lol, lol, lol, lol, lol, lol, lol, lol, lol]"]
                 + [f"{c}: &{c} [{', '.join([f'*{p}'] * 9)}]"
                    for p, c in zip("abcdefgh", "bcdefghi")]
                 + ["scene:", "  name: *i", ""])  # 9^9 = 387 million strings expanded


def write(tmp_path, name, text):
    (tmp_path / name).write_text(text)
    return tmp_path / name


def tyre(path):
    return ["--scene", "scenes/paper_study.yaml:a_1", "--scene_text",
            f"tyres: !MagicFormula {{tir_file: {path}}}"]


def big_tir(tmp_path):
    path = tmp_path / "bad.tir"
    with open(path, "w") as f:
        f.write("[MODEL]\n" + "$ padding\n" * 120_000)
    return path


A_1 = ["--scene", "scenes/paper_study.yaml:a_1"]
CASES = [
    ("alias bomb in a scene file", run_command.main,
     lambda t: ["--scene", f"{write(t, 'bad.tir', BOMB)}:scene"], "alias"),
    ("alias bomb in --scene_text", run_command.main,
     lambda t: A_1 + ["--scene_text", BOMB.replace("scene:\n  name: *i", "name: *i")], "alias"),
    ("duplicate key", run_command.main,
     lambda t: A_1 + ["--scene_text", "friction: {law: {mu_s: 0.2, mu_s: 0.3}}"],
     "'mu_s' given twice"),
    ("duplicate scene entry", run_command.main,
     lambda t: ["--scene", f"{write(t, 'bad.tir', 'a_1: {}' + chr(10) + 'a_1: {}')}:a_1"],
     "'a_1' given twice"),
    ("entry name that is a path", run_command.main,
     lambda t: ["--scene", f"{write(t, 'bad.tir', '../ESCAPED_a_1: {}')}:../ESCAPED_a_1"],
     "'../ESCAPED_a_1' is not a plain name"),
    ("scene file is a device", run_command.main, lambda t: ["--scene", "/dev/zero"],
     "/dev/zero: not a regular file"),
    ("a huge value quoted", run_command.main,
     lambda t: A_1 + ["--scene_text", "friction: {law: {mu_s: [" + ", ".join(["1"] * 100000) + "]}}"],
     "friction.law.mu_s = [1, 1, 1, 1, 1, 1, ...] must be a number"),
    (".tir is a device", run_command.main, lambda t: tyre("/dev/zero"),
     "/dev/zero: not a regular file"),
    (".tir is /proc/self/mem", run_command.main, lambda t: tyre("/proc/self/mem"),
     "/proc/self/mem: cannot be read"),
    (".tir over its size limit", run_command.main, lambda t: tyre(big_tir(t)),
     "bad.tir: over 1000000 bytes"),
    (".tir is a folder", run_command.main, lambda t: tyre(t), "is a folder"),
    ("a road profile over its sample limit", run_command.main,
     lambda t: A_1 + ["--scene_text", "road: !SampledProfile {x_m: [" + ", ".join(
         map(str, range(100_001))) + "], z_m: [" + ", ".join(["0"] * 100_001) + "]}"],
     "'x_m' is a list of 100001 items; lists (a !SampledProfile's samples) are limited to "
     "100000 (about 20 s and 0.2 GB"),
    ("a --grid product over its limit", sweep_command.main,
     lambda t: ["--scene", "scenes/paper_study.yaml:a_1"] + [
         f"--grid={key}=" + ",".join(f"{base + k * step:g}" for k in range(30))
         for key, base, step in (("friction.law.mu_s", 0.3, 0.001), ("friction.law.mu_d", 0.1,
                                 0.001), ("car.front.strut_damping_Nspm", 100, 10))],
     "--grid: 27000 scenes (30 x 30 x 30): about"),
    ("a friction threshold that makes a non-finite PD gain", run_command.main,
     lambda t: A_1 + ["--scene_text", "friction: {law: {dv_translation_mps: 5.0e-324}}"],
     "friction.law.dv_translation_mps = 5e-324 is too small: the PD gain"),
    ("a creep bound that makes a non-finite PD gain", run_command.main,
     lambda t: A_1 + ["--scene_text", "friction: {law: {dmax_rotation_rad: 1.0e-310}}"],
     "friction.law.dmax_rotation_rad = 1e-310 is too small: the PD gain"),
    ("a run made too long by straight_s", run_command.main,
     lambda t: A_1 + ["--scene_text", "manoeuvre: {timeline: {straight_s: 1000.0}}"],
     "manoeuvre.timeline.straight_s = 1000.0 makes the run 1008.8 s long"),
    ("a ball joint inboard of the lower-arm pivots", run_command.main,
     lambda t: A_1 + ["--scene_text", "car: {front: {ball_joint_offset_b_m: 0.5949}}"],
     "car.front.ball_joint_offset_b_m = 0.5949 must lie in [0, 0.205) m"),
    ("sweep: missing .tir found before any run", sweep_command.main,
     lambda t: ["--scene", "scenes/paper_study.yaml:a_1", "--scene_text",
                f"tyres: !MagicFormula {{tir_file: {t / 'nowhere.tir'}}}"],
     "nowhere.tir: tyre property file not found"),
]


def leftovers(folder):
    return [p for p in folder.rglob("*") if ".partial-" in p.name or ".tmp" in p.name]


@pytest.mark.parametrize("label, main, argv, key", CASES, ids=[c[0] for c in CASES])
def test_hostile_input_is_refused_cleanly(label, main, argv, key, tmp_path, capsys,
                                          monkeypatch):
    monkeypatch.chdir(ROOT)
    args = [str(a) for a in argv(tmp_path)] + ["--out", str(tmp_path / "out")]
    before = set(tmp_path.iterdir())
    with pytest.raises(SystemExit) as stopped:
        cli.run_main(main, args)
    assert stopped.value.code == 2, label
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.startswith("error:")]
    assert len(lines) == 1 and len(lines[0]) < 1000, f"{label}: {err[-500:]!r}"
    assert key in lines[0], f"{label}: {key!r} not in {lines[0][:500]!r}"
    assert "Traceback" not in err
    assert not (tmp_path / "out").exists(), label
    assert not leftovers(tmp_path) and set(tmp_path.iterdir()) - before <= {
        tmp_path / "bad.tir"}, label


def test_an_alias_bomb_is_refused_in_bounded_memory(tmp_path):
    """In a process limited to 4 GB of address space (drake's import takes about 1.5 GB of
    it) and 120 s: exit 2 naming the alias expansion (before: memory grew until killed)."""
    bomb = write(tmp_path, "bomb.yaml", BOMB)

    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))
    done = subprocess.run([sys.executable, "-m", "drake_car.commands.run", "--scene", f"{bomb}:scene",
                           "--out", str(tmp_path / "out")], cwd=ROOT, capture_output=True,
                          text=True, timeout=120, preexec_fn=limit)
    assert done.returncode == 2, done.stderr[-800:]
    assert "aliases expand to over" in done.stderr and "Traceback" not in done.stderr
    assert not (tmp_path / "out").exists()


class _Planted:
    """A pickle that leaves a marker file when loaded."""

    def __init__(self, marker):
        self.marker = marker

    def __reduce__(self):
        return (Path.touch, (Path(self.marker),))


def _planted_sweep(tmp_path):
    out = tmp_path / "sweep"
    folder = out / "runs" / "0123456789abcdef"
    folder.mkdir(parents=True)
    (folder / "status.json").write_text(json.dumps({"hash": folder.name, "status": "ok"}))
    (folder / "run.pkl").write_bytes(pickle.dumps(_Planted(tmp_path / "MARKER")))
    (out / "sweep.json").write_text(json.dumps({"invocations": []}))
    return out, folder


def test_a_planted_pickle_is_never_loaded(tmp_path, capsys):
    """The design study's loader (``load_run``) and the sweep command refuse a folder with a
    pickle, naming it; the pickle's code does not run."""
    out, folder = _planted_sweep(tmp_path)
    with pytest.raises(OutputError, match=r"run\.pkl: a pickle in a results folder"):
        load_run(out, folder.name)
    with pytest.raises(SystemExit) as stopped:
        cli.run_main(sweep_command.main, ["--scene", str(ROOT / "scenes/paper_study.yaml:a_1"),
                                          "--out", str(out)])
    assert stopped.value.code == 2
    assert f"{folder / 'run.pkl'}: a pickle" in capsys.readouterr().err
    assert not (tmp_path / "MARKER").exists()


@pytest.mark.parametrize("damage, named", [
    (lambda out: (out / "sweep.json").write_text("{not json"), "sweep.json: not readable JSON"),
    (lambda out: (out / "sweep.json").write_text("{}"), "sweep.json: not a sweep's record"),
    (lambda out: (out / "index.csv").mkdir(), "index.csv: is not a file"),
    (lambda out: (out / "runs").write_text("x"), "runs: is not a folder"),
])
def test_damaged_sweep_bookkeeping_is_named_and_kept(damage, named, tmp_path, capsys):
    out = tmp_path / "sweep"
    out.mkdir()
    (out / "sweep.json").write_text(json.dumps({"invocations": []}))
    damage(out)
    before = {p: (p.stat().st_mtime_ns, p.is_dir()) for p in out.rglob("*")}
    with pytest.raises(SystemExit) as stopped:
        cli.run_main(sweep_command.main, ["--scene", str(ROOT / "scenes/paper_study.yaml:a_1"),
                                          "--out", str(out)])
    err = capsys.readouterr().err
    assert stopped.value.code == 2 and named in err and "Traceback" not in err, err[-500:]
    assert "repair" in err or "remove" in err or "move" in err
    assert {p: (p.stat().st_mtime_ns, p.is_dir()) for p in out.rglob("*")} == before


@pytest.fixture
def silent_listener():
    """A TCP port that accepts connections and never answers."""
    import socket
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(8)
    yield f"tcp://127.0.0.1:{server.getsockname()[1]}"
    server.close()


@pytest.fixture
def http_server():
    """An HTTP server: it answers, but not as a Dask scheduler."""
    import http.server
    import threading

    class Quiet(http.server.SimpleHTTPRequestHandler):
        def log_message(self, *args):
            pass
    server = http.server.HTTPServer(("127.0.0.1", 0), Quiet)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    yield f"tcp://127.0.0.1:{server.server_address[1]}"
    server.shutdown()
    server.server_close()


@pytest.mark.parametrize("address, reason", [
    ("foo://", "not a Dask scheduler address"),
    ("http://", "not a Dask scheduler address"),
    ("http://127.0.0.1:8786", "not a Dask scheduler address"),
    ("silent", "no Dask scheduler answered within 2 s"),
    ("http", "no Dask scheduler"),
])
def test_a_scheduler_that_is_not_one_is_refused(address, reason, request, tmp_path, capsys,
                                                monkeypatch):
    """--scheduler: a bad address refused before the scenes are read, a listener that is not
    a Dask scheduler refused by the handshake under its timeout (here 2 s; before: the Client
    waited forever, or stalled 20 s and printed a stray traceback); one line, exit 2, nothing
    written."""
    from drake_car.sweep import scheduler
    monkeypatch.setattr(scheduler, "CONNECT_TIMEOUT_S", 2)
    address = {"silent": lambda: request.getfixturevalue("silent_listener"),
               "http": lambda: request.getfixturevalue("http_server")}.get(
                   address, lambda: address)()
    out = tmp_path / "sweep"
    with pytest.raises(SystemExit) as stopped:
        cli.run_main(sweep_command.main, ["--scene", str(ROOT / "scenes/paper_study.yaml:a_1"),
                                          "--scene_text", "simulator: {end_time_s: 0.05}",
                                          "--scheduler", address, "--out", str(out), "--quiet"])
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.startswith("error:")]
    assert stopped.value.code == 2 and len(lines) == 1, err[-800:]
    assert f"--scheduler {address}: {reason}" in lines[0], lines
    assert "Traceback" not in err and not out.exists()


@pytest.mark.parametrize("signum, raised", [("SIGINT", KeyboardInterrupt), ("SIGTERM", SystemExit)])
def test_an_interrupt_stops_a_run_between_monitor_chunks(signum, raised):
    """Ctrl-C or SIGTERM while the simulator steps is raised between the monitor's chunks (the
    simulated time a whole number of monitor periods), never inside a system Drake calls back
    from C++ where it could be lost; SIGTERM under ``terminate_as_exit`` as SystemExit."""
    import signal
    import threading

    from conftest import paper_scene
    from drake_car.results.folder import terminate_as_exit
    from drake_car.sim.simulate import SceneRunner
    runner = SceneRunner(paper_scene("a_3", "simulator: {end_time_s: 8.0}"))
    runner.start()
    timer = threading.Timer(1.0, os.kill, (os.getpid(), getattr(signal, signum)))
    timer.start()
    try:
        with pytest.raises(raised), terminate_as_exit():
            runner.advance_to(8.0)
    finally:
        timer.cancel()
    period = runner.scene.simulator.monitor_period_s
    t = runner.root.get_time()
    assert 0 < t < 8.0 and abs(t / period - round(t / period)) < 1e-6, t
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


SHORT = A_1 + ["--scene_text", "simulator: {end_time_s: 0.05}", "--quiet"]


def _refused(capsys, argv, key):
    """Runs drake_car.run with ``argv``: exit 2, one error line holding ``key``, no traceback."""
    with pytest.raises(SystemExit) as stopped:
        cli.run_main(run_command.main, [str(a) for a in argv])
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.startswith("error:")]
    assert stopped.value.code == 2 and len(lines) == 1, err[-800:]
    assert key in lines[0] and "Traceback" not in err, lines[0][:500]


@pytest.fixture
def held_lock(tmp_path):
    """Holds a folder's lock (``results.lock``) from another process, as a run writing it."""
    processes = []

    def hold(lock):
        code = ("import sys, time; from drake_car.results.lock import exclusive\n"
                "with exclusive(sys.argv[1]):\n    print('held', flush=True); time.sleep(120)")
        process = subprocess.Popen([sys.executable, "-c", code, str(lock)], cwd=ROOT,
                                   stdout=subprocess.PIPE, text=True,
                                   env=dict(os.environ, PYTHONPATH=str(ROOT)))
        assert process.stdout.readline().strip() == "held"
        processes.append(process)
        return process.pid
    yield hold
    for process in processes:
        process.kill()
        process.wait()


@pytest.mark.parametrize("label, out, key", [
    ("--out name over 255 bytes", lambda t: t / ("x" * 250), "is 250 bytes; names here are limited to"),
    ("--out a dangling symlink", lambda t: (t / "out").symlink_to(t / "nowhere") or t / "out",
     "a dangling symbolic link (to"),
    ("scene name is a path", None, "name = '../x' is not a plain name"),
])
def test_a_bad_out_or_name_is_refused_before_any_work(label, out, key, tmp_path, capsys,
                                                      monkeypatch):
    monkeypatch.chdir(ROOT)
    argv = A_1 + ["--quiet"]
    if out is None:
        argv, target = A_1 + ["--scene_text", "name: ../x"], tmp_path / "out"
    else:
        target = out(tmp_path)
    before = {p.name for p in tmp_path.iterdir()}
    _refused(capsys, argv + ["--out", target], key)
    assert {p.name for p in tmp_path.iterdir()} == before, label


def test_out_inside_a_folder_another_run_replaces_is_refused(tmp_path, capsys, held_lock,
                                                             monkeypatch):
    """``--out A/B`` while another run writes ``A`` (its lock held): refused, naming A (before:
    accepted, then deleted by the other run's swap); and ``--out A`` while another run writes
    ``A/B``: refused, naming A/B."""
    monkeypatch.chdir(ROOT)
    outer = tmp_path / "A"
    pid = held_lock(tmp_path / ".A.lock")
    _refused(capsys, SHORT + ["--out", outer / "B"],
             f"inside {outer}, which another run (pid {pid}) is writing")
    assert not outer.exists()
    outer.mkdir()
    (outer / ".drake_car_output").write_text("")
    pid = held_lock(outer / ".B.lock")
    _refused(capsys, SHORT + ["--out", outer], f"holds {outer / 'B'}, which another run (pid {pid})")
    assert sorted(p.name for p in outer.iterdir()) == [".B.lock", ".drake_car_output"]


def test_a_sweep_inside_a_folder_another_run_replaces_is_refused(tmp_path, capsys, held_lock,
                                                                 monkeypatch):
    """The sweep command's --out too: a sweep folder inside a folder another run writes (and
    will replace whole) is refused before any work, naming that folder."""
    from drake_car.commands import sweep as sweep_command
    monkeypatch.chdir(ROOT)
    outer = tmp_path / "A"
    pid = held_lock(tmp_path / ".A.lock")
    with pytest.raises(SystemExit) as stopped:
        cli.run_main(sweep_command.main, ["--scene", "scenes/paper_study.yaml:a_1", "--out",
                                          str(outer / "sweep"), "--quiet"])
    err = capsys.readouterr().err
    assert stopped.value.code == 2, err[-800:]
    assert f"inside {outer}, which another run (pid {pid}) is writing" in err, err[-800:]
    assert not outer.exists()


@pytest.mark.parametrize("errno_name, at", [("ENOSPC", "write"), ("EACCES", "rename"),
                                             ("ENAMETOOLONG", "rename")])
def test_os_errors_on_the_output_take_the_one_error_path(errno_name, at, tmp_path, capsys,
                                                         monkeypatch):
    """A full disk while the run's files are written, a rename refused at the swap: exit 2, the
    path and the reason in one line, no temporary folder left, a previous output kept (before:
    a traceback, after the whole simulation)."""
    import errno
    monkeypatch.chdir(ROOT)
    out = tmp_path / "out"
    out.mkdir()
    (out / ".drake_car_output").write_text("")
    (out / "earlier.csv").write_text("kept")
    code = getattr(errno, errno_name)
    if at == "write":
        def write_run(run, folder):
            raise OSError(code, os.strerror(code), str(folder / "history.csv"))
        monkeypatch.setattr(run_command, "write_run", write_run)
    else:
        rename = Path.rename

        def refused(self, target):
            if Path(target) == out and "-old-" not in self.name:  # the new output's move
                raise OSError(code, os.strerror(code), str(self), str(target))
            return rename(self, target)
        monkeypatch.setattr(Path, "rename", refused)
    _refused(capsys, SHORT + ["--out", out], f"--out {out}: ")
    assert (out / "earlier.csv").read_text() == "kept"
    assert not leftovers(tmp_path), leftovers(tmp_path)


def test_a_symlinked_out_replaces_what_it_names_and_leaves_no_link_behind(tmp_path,
                                                                         monkeypatch):
    """--out LINK -> REAL: REAL replaced whole, LINK kept, no orphaned ``.partial-…-old-…``
    link (before: the link was renamed away and left)."""
    monkeypatch.chdir(ROOT)
    real, link = tmp_path / "real", tmp_path / "link"
    real.mkdir()
    (real / ".drake_car_output").write_text("")
    (real / "stale.csv").write_text("from an earlier run")
    link.symlink_to(real)
    cli.run_main(run_command.main, SHORT + ["--out", str(link)])
    assert link.is_symlink() and (real / "history.csv").is_file()
    assert not (real / "stale.csv").exists()
    assert not leftovers(tmp_path), leftovers(tmp_path)


def test_a_large_grid_is_announced_and_goes_on_when_asked(monkeypatch, capsys):
    """Past the announcement threshold: the estimate on stderr, then the scenes; past the limit
    with ``large``: the same (the limits lowered here to keep the test small)."""
    monkeypatch.chdir(ROOT)
    monkeypatch.setattr(scene_grid, "GRID_ANNOUNCE_SCENES", 2)
    monkeypatch.setattr(scene_grid, "GRID_MAX_SCENES", 3)
    grid = [("friction.law.mu_s", ["0.3", "0.4"]), ("friction.law.mu_d", ["0.1", "0.2"])]
    with pytest.raises(Exception, match=r"--grid: 4 scenes \(2 x 2\): about .* over the limit "
                                        r"of 3 scenes; give fewer values, or --large to go on"):
        scene_grid.build_scenes("scenes/paper_study.yaml:a_1", "", grid)
    assert len(scene_grid.build_scenes("scenes/paper_study.yaml:a_1", "", grid,
                                   large=True)) == 4
    assert "--grid: 4 scenes (2 x 2): about" in capsys.readouterr().err


def test_a_long_road_is_announced_with_its_cost():
    """A !SampledProfile past ANNOUNCE_ROAD_SAMPLES (below the limit that refuses it) is
    announced, naming the key and the estimated cost, before any work."""
    import logging
    from drake_car.scene.guard import ANNOUNCE_ROAD_SAMPLES
    from drake_car.scene.load import load_scene
    n = ANNOUNCE_ROAD_SAMPLES + 1
    x = ", ".join(f"{0.01 * i:g}" for i in range(n))
    z = ", ".join("0" for _ in range(n))
    records = []
    handler = logging.Handler(logging.WARNING)
    handler.emit = records.append
    logger = logging.getLogger("drake_car")
    logger.addHandler(handler)
    try:
        load_scene(ROOT / "scenes" / "car.yaml", child="bump",
                   scene_text=f"road: !SampledProfile {{x_m: [{x}], z_m: [{z}]}}")
    finally:
        logger.removeHandler(handler)
    assert any(f"road.x_m has {n} samples" in r.getMessage() and "GB" in r.getMessage()
               for r in records), [r.getMessage()[-200:] for r in records]
