"""Hostile or damaged input from outside (issue 25), beside ``test_bad_input.py``'s table and
under its conventions: exit status 2, one error line naming the key or the path, no
traceback, nothing written, nothing left behind; a planted pickle is never loaded (no marker
file appears); an alias bomb is refused in a process with bounded memory."""

import errno
import functools
import json
import os
import pickle
import re
import resource
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from drake_car.commands import cli
from drake_car.commands import ride as ride_command
from drake_car.commands import run as run_command
from drake_car.commands import strut_rig as rig_command
from drake_car.commands import sweep as sweep_command
from drake_car.commands import tyre as tyre_command
from drake_car.results.folder import OutputError
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


TYRES = ROOT / "tests" / "data" / "tyres"
SEDAN = (TYRES / "Sedan_Pac02Tire.tir").read_text()
MF61 = (TYRES / "MagicFormula61_Parameters.tir").read_text()


def tir(tmp_path, text, key, value):
    """``text`` (a .tir file's) with ``key``'s line set to ``KEY = value`` (its line number
    kept), as tmp_path/bad.tir."""
    damaged, n = re.subn(rf"(?m)^{key}\s*=.*$", f"{key} = {value}".rstrip(), text)
    assert n == 1, key
    path = tmp_path / "bad.tir"
    path.write_text(damaged)
    return path


def line_of(text, key):
    return next(i for i, line in enumerate(text.splitlines(), 1) if line.startswith(key + " "))


@functools.lru_cache(maxsize=1)
def synthetic_loop():
    """A synthetic measured loop (the rig command's synthetic.csv as issue 30 took it, before
    issue 31 loaded the rig at the car's side load at rest: the car's strut at μs 0.3, μd 0.22,
    1000 N at the strut's lower mount, ±10 mm at 1 Hz, 1 ms samples, plus 10 N and 2 µm of
    noise, seed 23): (t, stroke, force). Fitted with ``LOWER_MOUNT``, its side force's point
    (the command's default is the top mount, where the rig's own loops apply it)."""
    from drake_car.law.friction.frd import StrutFrictionParameters
    from drake_car.model.parameters import CarParameters
    from drake_car.sim.rigs.strut import StrutRigOptions, simulate_strut_rig
    options = StrutRigOptions(side_force_N=1000.0, stroke_amplitude_m=0.01,
                              stroke_frequency_hz=1.0)
    h = simulate_strut_rig(CarParameters(), options,
                           StrutFrictionParameters(mu_s=0.3, mu_d=0.22), cycles=5.0)
    rng = np.random.default_rng(23)
    stroke = h["stroke_m"] + rng.normal(0.0, 2e-6, len(h["t"]))
    force = h["load_cell_N"] + rng.normal(0.0, 10.0, len(h["t"]))
    return h["t"], stroke, force


LOWER_MOUNT = ["--side_force_point_below_top_m", "0.47"]  # the shipped strut's lower mount


def loop_csv(tmp_path, *, stroke_scale=1.0, force=lambda f, v: f, time=True):
    """The synthetic loop as tmp_path/loop.csv (columns t_s when ``time``, stroke_m, force_N,
    as the rig command's synthetic.csv), its stroke scaled, its force changed by
    ``force(force, velocity)``."""
    t, stroke, f = synthetic_loop()
    columns = {"t_s": t} if time else {}
    columns |= {"stroke_m": stroke * stroke_scale,
                "force_N": force(f, np.gradient(stroke, t))}
    path = tmp_path / "loop.csv"
    path.write_text(",".join(columns) + "\n" + "".join(
        ",".join(repr(float(c[i])) for c in columns.values()) + "\n" for i in range(len(t))))
    return path


A_1 = ["--scene", "scenes/paper_study.yaml:a_1"]
RIDE = ["--classes", "A", "--no_run"]
# Issue 30: nothing silently wrong -- each row a case that was accepted (or failed with a
# traceback, or a message naming neither the file nor the key) before its fix.
CHECKED = [
    ("tyre command: an empty value", tyre_command.main,
     lambda t: ["--tir", tir(t, SEDAN, "PDY1", "")],
     f"bad.tir:{line_of(SEDAN, 'PDY1')}: PDY1 is given no value"),
    ("scene: an empty .tir value", run_command.main,
     lambda t: tyre(tir(t, SEDAN, "PDY1", "  $ left empty")),
     f"bad.tir:{line_of(SEDAN, 'PDY1')}: PDY1 is given no value"),
    ("tyre command: a negative longitudinal relaxation length", tyre_command.main,
     lambda t: ["--tir", tir(t, SEDAN, "PTX1", "-2.3")],
     (f"bad.tir:{line_of(SEDAN, 'PTX1')}: PTX1 = -2.3", "σκ = -",
      "must be > 0 at every load in FZMIN..FZMAX = 225..10125 N")),
    ("scene: a negative relaxation length, not used", run_command.main,
     lambda t: tyre(tir(t, SEDAN, "PTX1", "-2.3")),
     (f"bad.tir:{line_of(SEDAN, 'PTX1')}: PTX1 = -2.3", "must be > 0 at every load")),
    ("scene: a negative relaxation length, used", run_command.main,
     lambda t: A_1 + ["--scene_text", f"tyres: !MagicFormula {{tir_file: "
                      f"{tir(t, SEDAN, 'PTX1', '-2.3')}, slip: {{relaxation_lengths_from_file: "
                      "true}}"],
     (f"bad.tir:{line_of(SEDAN, 'PTX1')}: PTX1 = -2.3", "must be > 0 at every load")),
    ("tyre command: a zero lateral relaxation length", tyre_command.main,
     lambda t: ["--tir", tir(t, SEDAN, "PTY1", "0")],
     (f"bad.tir:{line_of(SEDAN, 'PTY1')}: PTY1 = 0", "σα = 0")),
    ("tyre command: PTY2 = 0 divides by zero", tyre_command.main,
     lambda t: ["--tir", tir(t, SEDAN, "PTY2", "0")],
     (f"bad.tir:{line_of(SEDAN, 'PTY2')}: PTY2 = 0", "divides")),
    ("tyre command: an MF 6.1 carcass stiffness below 0", tyre_command.main,
     lambda t: ["--tir", tir(t, MF61, "LONGITUDINAL_STIFFNESS", "-3.5e5")],
     (f"bad.tir:{line_of(MF61, 'LONGITUDINAL_STIFFNESS')}: LONGITUDINAL_STIFFNESS = -350000",
      "σκ = -", "must be > 0 at every load")),
    ("tyre command: a negative FZMIN", tyre_command.main,
     lambda t: ["--tir", tir(t, SEDAN, "FZMIN", "-1e9")],
     f"bad.tir:{line_of(SEDAN, 'FZMIN')}: FZMIN = -1e+09 N must be >= 0"),
    ("scene: FZMIN equal to FZMAX", run_command.main,
     lambda t: tyre(tir(t, SEDAN, "FZMIN", "10125")),
     f"bad.tir:{line_of(SEDAN, 'FZMIN')}: FZMIN = 10125 must be below FZMAX = 10125"),
    ("scene: a tyre for lighter cars (FZMAX below the wheel load)", run_command.main,
     lambda t: tyre(tir(t, SEDAN, "FZMAX", "2000")), "a tyre for a lighter vehicle"),
    ("scene: a tyre for heavier cars (FZMIN above the wheel load)", run_command.main,
     lambda t: tyre(tir(t, SEDAN, "FZMIN", "5000")), "a tyre for a heavier vehicle"),
    ("tyre command: an unknown TYRESIDE", tyre_command.main,
     lambda t: ["--tir", tir(t, SEDAN, "TYRESIDE", "'MIDDLE'")],
     f"bad.tir:{line_of(SEDAN, 'TYRESIDE')}: TYRESIDE = 'MIDDLE' must be LEFT or RIGHT"),
    ("scene: an unknown TYRESIDE", run_command.main,
     lambda t: tyre(tir(t, SEDAN, "TYRESIDE", "'MIDDLE'")), "TYRESIDE = 'MIDDLE' must be"),
    ("tyre command: LFZO = 0 divides by zero", tyre_command.main,
     lambda t: ["--tir", tir(t, SEDAN, "LFZO", "0")],
     f"bad.tir:{line_of(SEDAN, 'LFZO')}: LFZO = 0 must be > 0"),
    ("scene: LMUY = 0 divides by zero", run_command.main,
     lambda t: tyre(tir(t, SEDAN, "LMUY", "0")),
     f"bad.tir:{line_of(SEDAN, 'LMUY')}: LMUY = 0 must be > 0"),
    ("tyre command: Python's underscore in a number", tyre_command.main,
     lambda t: ["--tir", tir(t, SEDAN, "PDY1", "1_0")],
     f"bad.tir:{line_of(SEDAN, 'PDY1')}: PDY1 = '1_0' is not a number"),
    ("tyre command: a pressure a PAC2002 file has no terms for", tyre_command.main,
     lambda t: ["--tir", TYRES / "Sedan_Pac02Tire.tir", "--pressure_Pa", "2e5"],
     "Sedan_Pac02Tire.tir: pressure_Pa = 200000 has no effect: the file is PAC2002"),
    ("tyre command: a pressure outside the file's range", tyre_command.main,
     lambda t: ["--tir", TYRES / "MagicFormula61_Parameters.tir", "--pressure_Pa", "1e12"],
     ("pressure_Pa = 1e+12 lies outside the file's PRESMIN..PRESMAX = 200000..400000 Pa",)),
    ("ride: a speed that is no number", ride_command.main,
     lambda t: RIDE + ["--speeds", "60,nan"], "--speeds = nan must lie in (0, 250] km/h"),
    ("ride: a speed with its unit", ride_command.main,
     lambda t: RIDE + ["--speeds", "60kph"], "--speeds = '60kph' must be a comma-separated "
     "list of numbers in km/h"),
    ("ride: a negative speed", ride_command.main,
     lambda t: RIDE + ["--speeds", "-60"], "--speeds = -60.0 must lie in (0, 250] km/h"),
    ("ride: a speed beyond a passenger car's", ride_command.main,
     lambda t: RIDE + ["--speeds", "300"], "--speeds = 300.0 must lie in (0, 250] km/h"),
    ("ride: an unknown road class", ride_command.main,
     lambda t: ["--classes", "Z", "--no_run"], "--classes = 'Z' must be one of A, B, C, D"),
    ("rig: a measured stroke in mm (the issue's command)", rig_command.main,
     lambda t: ["--measured", loop_csv(t, stroke_scale=1000.0)],
     ("--measured ", "loop.csv: the stroke reaches 9.8", "beyond the strut's travel",
      "is it in mm?")),
    ("rig: a measured stroke in mm with its side load", rig_command.main,
     lambda t: ["--measured", loop_csv(t, stroke_scale=1000.0), "--side_force_N", "1000"],
     ("loop.csv: the stroke reaches 9.8", "beyond the strut's travel")),
    ("rig: a measured loop without its side load", rig_command.main,
     lambda t: ["--measured", loop_csv(t)], "--side_force_N: must be given with --measured"),
    ("rig: an amplitude the loop contradicts", rig_command.main,
     lambda t: ["--measured", loop_csv(t), "--amplitude_m", "0.05", "--side_force_N", "3000"],
     ("loop.csv: its stroke amplitude is 0.0098", "not --amplitude_m 0.05")),
    ("rig: a frequency the loop contradicts", rig_command.main,
     lambda t: ["--measured", loop_csv(t), "--frequency_hz", "0.2", "--side_force_N", "1000"],
     ("loop.csv: its stroke frequency is 1.0", "not --frequency_hz 0.2")),
    ("rig: a sample period the loop's time column contradicts", rig_command.main,
     lambda t: ["--measured", loop_csv(t), "--sample_period_s", "0.01",
                "--side_force_N", "1000"],
     ("loop.csv: its t_s column steps 0.001 s", "not --sample_period_s 0.01")),
    ("rig: a loop with no time base", rig_command.main,
     lambda t: ["--measured", loop_csv(t, time=False), "--side_force_N", "1000"],
     ("loop.csv: has no t_s column: give --sample_period_s",)),
    ("rig: a frequency the loop contradicts at its sample period", rig_command.main,
     lambda t: ["--measured", loop_csv(t, time=False), "--sample_period_s", "0.01",
                "--frequency_hz", "1", "--side_force_N", "1000"],
     ("loop.csv: its stroke frequency is 0.100 Hz", "not --frequency_hz 1")),
    ("rig: a force beyond what μ <= 2 allows at the side load", rig_command.main,
     lambda t: ["--measured", loop_csv(t), "--side_force_N", "100", *LOWER_MOUNT],
     ("loop.csv: the force reaches", "μ <= 2 allows at --side_force_N 100 at the strut's "
      "lower mount")),
    ("rig: a force of the opposite sign", rig_command.main,
     lambda t: ["--measured", loop_csv(t, force=lambda f, v: -f), "--side_force_N", "1000"],
     ("loop.csv: the force opposes the stroke's motion while sliding",)),
]
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
] + CHECKED


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
    for part in key if isinstance(key, tuple) else (key,):
        assert part in lines[0], f"{label}: {part!r} not in {lines[0][:500]!r}"
    assert "Traceback" not in err and "np.float64" not in err
    assert not (tmp_path / "out").exists(), label
    assert not leftovers(tmp_path) and set(tmp_path.iterdir()) - before <= {
        tmp_path / "bad.tir", tmp_path / "loop.csv"}, label


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
    from drake_car.results.signals import terminate_as_exit
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


# -- issue 30: nothing silently wrong -------------------------------------------------------

def test_a_tyre_file_is_read_as_its_format_defines(tmp_path):
    """A UTF-8 BOM is skipped; a Fortran real with a D exponent is the number it writes (TNO
    and Adams files come from Fortran tools); absent and empty differ: an absent coefficient
    takes the format's default and is listed, an empty one is refused (CHECKED)."""
    from drake_car.law.tyre.magic_formula import MagicFormulaTyre
    from drake_car.law.tyre.tir import parse_tir, read_tir
    plain = MagicFormulaTyre.from_file(TYRES / "Sedan_Pac02Tire.tir")
    bom = tmp_path / "bom.tir"
    bom.write_bytes(b"\xef\xbb\xbf" + SEDAN.encode())
    assert read_tir(bom).coefficients() == read_tir(TYRES / "Sedan_Pac02Tire.tir").coefficients()
    assert MagicFormulaTyre.from_file(bom).PDY1 == plain.PDY1
    for written, value in (("0.10489D+01", 1.0489), ("10489d-4", 1.0489), ("1.0489E0", 1.0489),
                           ("+.10489e+1", 1.0489)):
        assert parse_tir(f"[LATERAL_COEFFICIENTS]\nPDY1 = {written}\n").coefficients()[
            "PDY1"] == pytest.approx(value, rel=1e-15), written
    absent = tmp_path / "absent.tir"
    absent.write_text(re.sub(r"(?m)^PDY1\s*=.*$", "", SEDAN))
    assert "PDY1" in MagicFormulaTyre.from_file(absent).defaulted


@pytest.mark.parametrize("side, read_as", [("'LEFT'", "LEFT"), ("'right'", "RIGHT"),
                                           ("'UNKNOWN'", "LEFT"), ("'SYMMETRIC'", "LEFT")])
def test_a_tyre_side_is_one_the_format_knows(side, read_as, tmp_path):
    """TYRESIDE: LEFT or RIGHT; 'UNKNOWN' (files exported by tools that did not record it, as
    tests/data/tyres/335_65R22_5_G275MSA_60psi.tir; Chrono's ChPac02Tire reads it as LEFT) and
    'SYMMETRIC' (no side) are read as LEFT, and the note says so; any other is refused."""
    from drake_car.law.tyre.magic_formula import MagicFormulaTyre
    tyre = MagicFormulaTyre.from_file(tir(tmp_path, SEDAN, "TYRESIDE", side))
    assert tyre.side == read_as
    assert (f"TYRESIDE {side.upper()} read as LEFT" in tyre.format_note) == (
        side in ("'UNKNOWN'", "'SYMMETRIC'")), tyre.format_note


def test_every_shipped_and_test_tyre_file_passes_the_read_time_checks():
    """The checks refuse damaged files, not real ones: every .tir here is read."""
    from drake_car.law.tyre.magic_formula import MagicFormulaTyre
    for path in [*TYRES.glob("*.tir"), *(ROOT / "urdf" / "tyres").glob("*.tir")]:
        MagicFormulaTyre.from_file(path)


def test_a_ride_road_is_derived_from_the_speeds():
    """140 and 250 km/h (before: a bare ValueError "raise road_length_m", no option): the road
    is as long as the fastest run needs (plus 10 m), never shorter than the default 400 m (so
    the slower studies' roads, and their runs' keys, are unchanged)."""
    from drake_car.study.ride.grid import RideStudy, ride_scenes
    for speeds, longest in (([60.0, 100.0], 400.0), ([140.0, 250.0], None)):
        scenes = ride_scenes(RideStudy(classes=["A"], speeds_kph=speeds, mu_s=[0.0]))
        assert len(scenes) == 2 * len(speeds)
        for scene in scenes.values():
            timeline = scene.manoeuvre.timeline
            distance = timeline.speed_mps * (0.5 * timeline.speed_up_s + timeline.steer_s)
            assert scene.road.x_m[-1] >= distance + 10.0, scene.name
            if longest:
                assert scene.road.x_m[-1] < longest + 10.0, scene.name


def test_a_ride_road_given_too_short_is_named():
    """The run's distance with the Escort's own launch to 140 km/h: 8.9 s (its drive allows
    4.54 m/s²: 38.9 m/s / 4.54 + 0.3 s of blends, up to 0.1 s), so 38.9 m/s × (8.9 / 2 + 1 +
    6 s) + 10 m."""
    from drake_car.law.checks import ParameterError
    from drake_car.study.ride.grid import RideStudy, ride_scenes
    with pytest.raises(ParameterError, match=r"road_length_m = 300.0 is shorter than the run at "
                                             r"140 km/h needs \(455 m"):
        ride_scenes(RideStudy(classes=["A"], speeds_kph=[140.0], mu_s=[0.0],
                              road_length_m=300.0))


def test_the_sweep_command_says_one_thing_of_its_out(capsys):
    """Its --out is added to, never replaced (before: the option's help said "replaced
    whole", the description "added to, never replaced")."""
    with pytest.raises(SystemExit):
        sweep_command.main(["--help"])
    text = " ".join(capsys.readouterr().out.split())
    out_help = text[text.index("--out OUT", text.index("options:")) + len("--out OUT"):]
    out_help = out_help[:out_help.index(" --")]
    assert "replaced whole" not in text and "all or nothing" not in out_help, out_help
    assert "never replaced" in out_help, out_help


def test_numbers_in_messages_are_plain():
    """A numpy scalar in a message is its number (before: ``np.float64(2.11...)``)."""
    from drake_car.law.checks import ParameterError
    message = str(ParameterError("mu_s", np.float64(2.11), "must be <= 2"))
    assert message == "mu_s = 2.11 must be <= 2", message
    assert str(ParameterError("n", np.int64(3), "x")) == "n = 3 x"


def _enospc(monkeypatch, where):
    """Path.write_text raises ENOSPC, with no path as a real full disk does (the error comes
    from the file's write, not its open), for files under ``where`` (a str in their path)."""
    write = Path.write_text

    def full(self, *args, **kwargs):
        if where in str(self):
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return write(self, *args, **kwargs)
    monkeypatch.setattr(Path, "write_text", full)


@pytest.mark.parametrize("main, argv", [
    (run_command.main, SHORT),
    (tyre_command.main, ["--tir", str(TYRES / "Sedan_Pac02Tire.tir"), "--quiet"]),
], ids=["run", "tyre"])
def test_a_full_disk_is_one_line_and_keeps_the_previous_output(main, argv, tmp_path, capsys,
                                                               monkeypatch):
    """The disk fills while the output's files are written (the error naming no file, as a
    real write's): exit 2, one line naming --out and the reason, nothing left, the previous
    output kept (before: a traceback, exit 1)."""
    monkeypatch.chdir(ROOT)
    out = tmp_path / "out"
    out.mkdir()
    (out / ".drake_car_output").write_text("")
    (out / "earlier.csv").write_text("kept")
    _enospc(monkeypatch, ".partial-")
    with pytest.raises(SystemExit) as stopped:
        cli.run_main(main, [*argv, "--out", str(out)])
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.startswith("error:")]
    assert stopped.value.code == 2 and len(lines) == 1, err[-800:]
    assert f"--out {out}: " in lines[0] and "No space left on device" in lines[0], lines
    assert "Traceback" not in err
    assert (out / "earlier.csv").read_text() == "kept"
    assert not leftovers(tmp_path), leftovers(tmp_path)


def test_a_vanished_working_folder_is_one_line(tmp_path, capsys, monkeypatch):
    """The folder the command was started in removed under it (before: a traceback from
    os.getcwd)."""
    monkeypatch.chdir(tmp_path)

    def gone():
        raise FileNotFoundError(errno.ENOENT, os.strerror(errno.ENOENT))
    monkeypatch.setattr(os, "getcwd", gone)
    with pytest.raises(SystemExit) as stopped:
        cli.run_main(tyre_command.main, ["--tir", str(TYRES / "Sedan_Pac02Tire.tir"),
                                         "--out", "tyre"])
    err = capsys.readouterr().err
    assert stopped.value.code == 2 and "Traceback" not in err, err[-800:]
    assert err.splitlines()[-1] == ("error: the current folder no longer exists (removed "
                                    "while the command ran?); change to one that does"), err


def test_a_sweep_run_that_cannot_be_written_stops_the_sweep_and_leaves_no_part(tmp_path,
                                                                               monkeypatch):
    """A full disk while a finished run's files are written: the error goes up (the disk will
    not empty itself; before: each run was recorded as failed and the sweep went on, so every
    other run was computed and lost too), and no half-written run folder is left."""
    import types
    from drake_car.sweep.store import commit_run
    runs = tmp_path / "runs"
    runs.mkdir()
    _enospc(monkeypatch, "history.csv")
    job = types.SimpleNamespace(hash="0123456789abcdef", scene=None)
    files = {name: "x" for name in ("history.csv", "run.json", "scene.yaml", "diagram.dot")}
    with pytest.raises(OSError, match="No space left"):
        commit_run(runs, job, {"hash": job.hash, "status": "ok"}, files)
    assert list(runs.iterdir()) == []


def test_an_index_row_is_appended_whole_or_not_at_all(tmp_path, monkeypatch):
    """The sweep's index.csv gains a run's row whole, or is left as it was (before: a row cut
    where the disk filled)."""
    from drake_car.sweep import store
    index = tmp_path / "index.csv"
    index.write_text("hash,name,status,wall_s,error\r\n")
    before = index.read_bytes()
    real = os.write

    def short(fd, data):  # the disk fills half-way through the row
        if len(data) > 10:
            real(fd, data[:10])
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return real(fd, data)
    monkeypatch.setattr(os, "write", short)
    with pytest.raises(OSError, match="No space left"):
        store.append_index_row(tmp_path, {"hash": "ab", "name": "a_1", "status": "ok",
                                          "wall_s": 1.0, "error": ""})
    assert index.read_bytes() == before
    monkeypatch.setattr(os, "write", real)
    store.append_index_row(tmp_path, {"hash": "ab", "name": "a_1", "status": "ok",
                                      "wall_s": 1.0, "error": ""})
    assert index.read_text().splitlines()[-1] == "ab,a_1,ok,1.0,"


@pytest.mark.slow
@pytest.mark.parametrize("fails_at", ["sweep.json", "second run"])
def test_a_sweep_on_a_full_disk_loses_no_finished_run(fails_at, tmp_path, capsys,
                                                      monkeypatch):
    """The disk fills when the new sweep folder's sweep.json is written: exit 2, one line,
    nothing left (before: README.md, sweep.json and index.csv left, a traceback). It fills
    when the second of two runs is written: the first run is kept whole, its row in the
    index, no half-written file or run folder; the same command again finishes the sweep."""
    monkeypatch.chdir(ROOT)
    out = tmp_path / "sweep"
    argv = ["--scene", "scenes/paper_study.yaml:a_1", "--scene_text",
            "simulator: {end_time_s: 0.05}", "--grid", "friction.law.mu_s=0.3,0.4",
            "--workers", "1", "--quiet", "--out", str(out)]
    if fails_at == "sweep.json":
        _enospc(monkeypatch, "sweep.json")
    else:
        from drake_car.sweep import store
        commit = store.commit_run
        calls = []

        def second_fails(runs, job, record, result):
            calls.append(job.hash)
            if len(calls) == 2:
                _enospc(monkeypatch, ".tmp-")
            return commit(runs, job, record, result)
        monkeypatch.setattr("drake_car.sweep.runner.commit_run", second_fails)
    with pytest.raises(SystemExit) as stopped:
        cli.run_main(sweep_command.main, argv)
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.startswith("error:")]
    assert stopped.value.code == 2 and len(lines) == 1 and "Traceback" not in err, err[-800:]
    assert f"--out {out}: " in lines[0] and "No space left on device" in lines[0], lines
    if fails_at == "sweep.json":
        assert not out.exists(), sorted(p.name for p in out.rglob("*"))
        return
    runs = [p for p in (out / "runs").iterdir()]
    assert len(runs) == 1 and runs[0].name == calls[0], runs
    assert json.loads((runs[0] / "status.json").read_text())["status"] == "ok"
    assert load_run(out, calls[0])[1] is not None
    index = (out / "index.csv").read_text().splitlines()
    assert len(index) == 2 and index[1].startswith(calls[0]), index
    assert not [p for p in out.rglob("*") if ".tmp" in p.name or ".partial" in p.name]
    monkeypatch.undo()
    monkeypatch.chdir(ROOT)
    cli.run_main(sweep_command.main, argv)
    assert len(list((out / "runs").iterdir())) == 2


def _tmpfs_available():
    try:
        return subprocess.run(["unshare", "-Urm", "true"], capture_output=True,
                              timeout=10).returncode == 0
    except (OSError, subprocess.SubprocessError):
        return False


@pytest.mark.slow
@pytest.mark.skipif(not _tmpfs_available(), reason="no user namespace to mount a tmpfs in")
@pytest.mark.parametrize("command, size", [
    (["-m", "drake_car.commands.tyre", "--tir", "tests/data/tyres/Sedan_Pac02Tire.tir"], "300k"),
    (["-m", "drake_car.commands.run", "--scene", "scenes/paper_study.yaml:a_1",
      "--scene_text", "simulator: {end_time_s: 0.05}", "--quiet"], "30k"),
    (["-m", "drake_car.commands.sweep", "--scene", "scenes/paper_study.yaml:a_1", "--scene_text",
      "simulator: {end_time_s: 0.05}", "--workers", "1", "--quiet"], "8k"),
], ids=["tyre", "run", "sweep"])
def test_a_real_full_disk_is_one_line_and_leaves_nothing(command, size, tmp_path):
    """The issue's commands on a real tmpfs of ``size`` (mounted in a user namespace, no
    root): exit 2, one line naming --out and "No space left on device", the disk left empty
    (before: a traceback; then, after issue 29, "error: No space left on device", naming
    nothing; the sweep left sweep.json and runs/)."""
    import shlex
    disk = tmp_path / "disk"
    disk.mkdir()
    script = (f"mount -t tmpfs -o size={size} tmpfs {disk} && cd {ROOT} && "
              f"{shlex.join([sys.executable, *command, '--out', str(disk / 'out')])}; "
              f"rc=$?; find {disk} -mindepth 1; exit $rc")
    done = subprocess.run(["unshare", "-Urm", "sh", "-c", script], capture_output=True,
                          text=True, timeout=600, env=dict(os.environ, PYTHONPATH=str(ROOT)))
    lines = [line for line in done.stderr.splitlines() if line.startswith("error:")]
    assert done.returncode == 2 and len(lines) == 1, done.stderr[-800:]
    assert f"--out {disk / 'out'}: " in lines[0], lines  # the output, named
    assert "No space left on device" in lines[0] and "Traceback" not in done.stderr
    assert done.stdout.strip() == "", done.stdout  # nothing left on the disk


def test_a_loop_the_law_does_not_describe_is_flagged():
    """A loop with a monotube damper's gas force (200 N [EST], pushing the rod out whichever
    way it moves) on top of the friction: the fit's residual is far above the loop's own noise,
    so the fit is flagged, never a confident value; the synthetic loop itself is not. (A force
    proportional to the speed, a damper's oil, is not flagged: over the middle half of the
    stroke, where μd is read, the speed varies by 13 % and μd takes it in.)"""
    from drake_car.model.parameters import CarParameters
    from drake_car.sim.rigs.strut import StrutRigOptions, eq4_normal_force_N
    from drake_car.study.rig.measured import residual_check
    t, stroke, force = synthetic_loop()
    options = StrutRigOptions(side_force_N=1000.0)
    normal = np.array([eq4_normal_force_N(CarParameters().front, options, q) for q in stroke])
    fine = residual_check(stroke, force, sample_period_s=1e-3, mu_d=0.22, normal_N=normal)
    assert fine.confident, fine
    assert fine.noise_N == pytest.approx(10.0, rel=0.15), fine  # the noise put in
    gas = residual_check(stroke, force + 200.0, sample_period_s=1e-3, mu_d=0.22,
                         normal_N=normal)
    assert not gas.confident and "residual" in gas.warning, gas


@pytest.mark.slow
def test_a_measured_fit_of_the_right_loop_is_confident_and_of_a_gas_strut_flagged(
        tmp_path, capsys):
    """The right loop (stroke, amplitude and frequency taken from it): μs 0.30 within its
    confidence, confident; the same loop with a gas force: flagged on stderr and in
    measured_fit.json, its line saying it is not a confident value."""
    path = loop_csv(tmp_path)
    cli.run_main(rig_command.main, ["--measured", str(path), "--side_force_N", "1000",
                                    *LOWER_MOUNT, "--out", str(tmp_path / "right")])
    fit = json.loads((tmp_path / "right" / "measured_fit.json").read_text())["fit"]
    assert abs(fit["mu_s"] - 0.30) <= fit["mu_s_ci95"] and fit["confident"], fit
    assert "(95 %)" in capsys.readouterr().out
    path = loop_csv(tmp_path, force=lambda f, v: f + 200.0)
    cli.run_main(rig_command.main, ["--measured", str(path), "--side_force_N", "1000",
                                    *LOWER_MOUNT, "--out", str(tmp_path / "gas")])
    fit = json.loads((tmp_path / "gas" / "measured_fit.json").read_text())["fit"]
    captured = capsys.readouterr()
    assert not fit["confident"] and fit["warnings"], fit
    assert "warning: " in captured.err and "not a confident value" in captured.out, captured
