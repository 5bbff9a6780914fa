"""Sweeps on Dask (``sweep.runner``, ``python -m drake_car.sweep``): a worker killed mid-sweep
loses nothing and every result equals the serial run's bit for bit; a restarted sweep redoes
only the missing runs and those the infrastructure lost, starting no cluster when there are
none; a failing run is recorded with its kind and the others complete; the local cluster
listens on 127.0.0.1 only; the command's bad input exits 2 with nothing written.

The runs are the paper's lane changes cut to 0.3 s, from an equilibrium settled for 1 s."""

import concurrent.futures
import csv
import json
import re
import os
import shutil
import signal
import threading
import subprocess
import sys
import time
import types

import numpy as np
import psutil
import pytest
from distributed import Client

from conftest import PAPER_SCENES, paper_scene
from drake_car.commands import cli
from drake_car.commands import sweep as sweep_command
from drake_car.results.record import RUN_FILES, checksums, read_run
from drake_car.results.files import write_csv
from drake_car.sim.simulate import simulate
from drake_car.sweep import runner as study_sweep
from drake_car.sweep.runner import Job, _record, local_cluster, missing, run_scenes, run_sweep
from drake_car.sweep.store import commit_run, key_parts, read_status, run_key
from drake_car.systems.failure import SimulationFailure

SHORT = "simulator: {end_time_s: 0.3, equilibrium_settle_s: 1.0}"
# An explicit tyre spring of 5e7 N/m at 5 ms: diverges within about 0.3 s.
DIVERGES = ("car: {tyre: {radial_stiffness_Npm: 5.0e7}}\nplant: {time_step: 0.005}\n"
            "simulator: {end_time_s: 2.0, equilibrium_settle_s: 1.0}")


def scene_key(scene):
    """The run folder's name of ``scene`` (its content, files and code)."""
    return run_key(key_parts(scene))


def short(*children):
    return {c: paper_scene(c, SHORT) for c in children}


def folders(out):
    return sorted(p.name for p in (out / "runs").iterdir())


def index(out):
    with open(out / "index.csv", newline="") as f:
        return list(csv.DictReader(f))


def listening(processes):
    """(pid, local address) of every listening inet socket of ``processes``."""
    found = []
    for p in processes:
        try:
            found += [(p.pid, c.laddr) for c in p.net_connections(kind="inet")
                      if c.status == psutil.CONN_LISTEN]
        except psutil.NoSuchProcess:
            pass
    return found


def in_thread(target):
    """Runs ``target()`` in a thread; returns (thread, what it returned or raised)."""
    outcome = {}

    def body():
        try:
            outcome["value"] = target()
        except BaseException as e:  # noqa: BLE001 - handed to the test
            outcome["error"] = e
    thread = threading.Thread(target=body, daemon=True)
    thread.start()
    return thread, outcome


def assert_same_run(folder, serial, tmp_path):
    """A run folder holds the serial run: history.csv bytes, and the Run read back from its
    files (no pickle) has the serial run's arrays and final state, bit for bit."""
    write_csv(tmp_path / "serial.csv", serial.history)
    assert (folder / "history.csv").read_bytes() == (tmp_path / "serial.csv").read_bytes()
    assert not list(folder.glob("*.pkl"))
    run = read_run(folder)
    assert run.history.keys() == serial.history.keys()
    for name, values in serial.history.items():
        assert np.array_equal(np.asarray(run.history[name]), np.asarray(values)), name
    assert run.scene_hash == serial.scene_hash and run.final == serial.final


@pytest.mark.slow
def test_a_killed_worker_loses_nothing_and_runs_equal_the_serial_ones(tmp_path):
    scenes = short("a_1", "a_2", "a_3", "b_1", "b_2", "b_3")
    out = tmp_path / "sweep"
    killed = []
    with local_cluster(2) as cluster, Client(cluster, set_as_default=False) as client:
        pids = client.run(os.getpid)  # worker address -> its process
        thread, outcome = in_thread(lambda: run_sweep(
            scenes, out, scheduler=cluster.scheduler_address, progress=False))
        deadline = time.monotonic() + 120
        while not killed and thread.is_alive() and time.monotonic() < deadline:
            if (out / "runs").is_dir() and any((out / "runs").glob("[0-9a-f]*")):
                executing = client.run(lambda dask_worker: [
                    str(ts.key) for ts in dask_worker.state.executing])
                busy = [address for address, keys in executing.items() if keys]
                if busy:  # a run is executing there: SIGKILL its worker process
                    os.kill(pids[busy[0]], signal.SIGKILL)
                    killed.append((pids[busy[0]], busy[0], executing[busy[0]][0].split("-")[1]))
            time.sleep(0.02)
        thread.join(timeout=180)
        assert not thread.is_alive()
        client.wait_for_workers(2, timeout=60)  # the nanny started a new worker
    assert killed, "no worker was killed mid-run"
    pid, address, interrupted = killed[0]
    assert not psutil.pid_exists(pid)
    again = read_status(out / "runs" / interrupted)  # the interrupted run, done elsewhere
    assert again["status"] == "ok" and again["worker"] != address
    summary = outcome["value"]
    assert (summary["ok"], summary["failed"], summary["reused"]) == (6, 0, 0)
    hashes = {name: scene_key(scene) for name, scene in scenes.items()}
    assert folders(out) == sorted(hashes.values())  # each run once, nothing half-written
    rows = index(out)
    assert sorted(r["hash"] for r in rows) == sorted(hashes.values())
    assert {r["status"] for r in rows} == {"ok"}
    for name, scene in scenes.items():
        assert_same_run(out / "runs" / hashes[name], simulate(scene), tmp_path)


@pytest.mark.slow
def test_the_command_restarts_with_only_the_missing_runs_on_loopback(tmp_path, monkeypatch):
    out = tmp_path / "sweep"
    argv = ["--scene", f"{PAPER_SCENES}:a_3", "--out", str(out), "--scene_text", SHORT,
            "--grid", "friction.law.mu_s=0.4,0.5,0.6", "--workers", "2", "--quiet"]
    me = psutil.Process()
    before = set(listening([me]))  # earlier tests in this process may still listen
    thread, outcome = in_thread(lambda: sweep_command.main(argv))
    sockets, processes = set(), set()
    while thread.is_alive():  # what listens while the sweep runs
        children = me.children(recursive=True)
        processes |= {c.pid for c in children}
        sockets |= set(listening([me, *children])) - before
        time.sleep(0.1)
    assert "error" not in outcome, outcome
    # the scheduler, its dashboard, two nannies; each worker's comm and HTTP server
    assert len(sockets) >= 8 and len({pid for pid, _ in sockets}) >= 3, sockets
    assert all(address.ip == "127.0.0.1" for _, address in sockets), sockets
    assert not set(listening([me])) - before, "the sweep's cluster must be closed"
    workers = {pid for pid, _ in sockets} - {me.pid}
    assert workers <= processes and not [  # the worker processes have ended
        p for p in workers if psutil.pid_exists(p)
        and psutil.Process(p).status() != psutil.STATUS_ZOMBIE]

    rows = index(out)
    assert sorted(r["name"] for r in rows) == [
        f"a_3[friction.law.mu_s={v}]" for v in ("0.4", "0.5", "0.6")]
    assert {r["status"] for r in rows} == {"ok"} and all(float(r["wall_s"]) > 0 for r in rows)
    keep, lose = folders(out)[:2], folders(out)[2]
    before = {k: read_status(out / "runs" / k) for k in keep}
    shutil.rmtree(out / "runs" / lose)
    (out / "runs" / f".tmp-{lose}-killed").mkdir()  # as a killed sweep leaves it
    sweep_command.main(argv)
    assert folders(out) == sorted(keep + [lose])
    assert {k: read_status(out / "runs" / k) for k in keep} == before  # reused, not redone
    log = json.loads((out / "sweep.json").read_text())["invocations"]
    assert [e["summary"]["ok"] for e in log] == [3, 1]
    assert [e["summary"]["reused"] for e in log] == [0, 2]
    assert sorted(log[1]["scenes"].values()) == folders(out)

    def no_cluster(*args, **kwargs):
        raise AssertionError("nothing is left to do: no cluster may be started")
    monkeypatch.setattr(study_sweep, "dask_client", no_cluster)
    monkeypatch.setattr(study_sweep, "local_cluster", no_cluster)
    sweep_command.main(argv)  # nothing left to do: no cluster at all
    assert len(index(out)) == 3


@pytest.mark.slow
def test_a_failing_run_is_recorded_and_the_others_complete(tmp_path):
    scenes = short("a_1", "b_1")
    scenes["bad"] = paper_scene("a_1", DIVERGES)
    out = tmp_path / "sweep"
    summary = run_sweep(scenes, out, workers=2, progress=False)
    assert (summary["ok"], summary["failed"]) == (2, 1)
    bad = read_status(out / "runs" / scene_key(scenes["bad"]))
    assert bad["status"] == "failed" and bad["kind"] == "run" and bad["name"] == "bad"
    # the tyre's load check or the monitor's (energy gained) stops it, whichever trips first
    assert re.match(r"(SimulationFailure|DivergenceError): diverged at t = ", bad["error"])
    assert "simulate" in bad["traceback"] and bad["worker"].startswith("tcp://127.0.0.1:")
    assert not (out / "runs" / bad["hash"] / "history.csv").exists()
    assert (out / "runs" / bad["hash"] / "scene.yaml").is_file()  # to rerun it alone
    rows = {r["name"]: r for r in index(out)}
    assert rows["bad"]["status"] == "failed" and "diverged" in rows["bad"]["error"]
    assert rows["a_1"]["status"] == rows["b_1"]["status"] == "ok"
    # main-job use: the first failed run (in the scenes' order) raised, naming it
    with pytest.raises(SimulationFailure, match=r"run bad failed: (SimulationFailure|DivergenceError): diverged"):
        run_scenes(scenes, out_dir=out, progress=False)  # all reused: no cluster
    # in memory (on one cluster for both calls): the run's own exception, naming it; the
    # scenes' order; two names with one content run once
    renamed = paper_scene("a_1", SHORT + "\nname: again")
    with local_cluster(2) as cluster:
        with pytest.raises(SimulationFailure, match=r"^run bad: diverged at t = "):
            run_scenes({"a_1": scenes["a_1"], "bad": scenes["bad"]}, progress=False,
                       scheduler=cluster.scheduler_address)
        runs = run_scenes({"b_1": scenes["b_1"], "again": renamed, "a_1": scenes["a_1"]},
                          progress=False, scheduler=cluster.scheduler_address)
    assert list(runs) == ["b_1", "again", "a_1"]
    assert runs["again"].scene.name == "again" and runs["a_1"].scene.name == "a_1"
    for name in ("a_1", "b_1"):
        folder = out / "runs" / scene_key(scenes[name])
        assert_same_run(folder, runs[name], tmp_path)


def test_missing_reruns_infrastructure_failures_and_keeps_run_failures(tmp_path):
    """Hand-written status.json folders: ok and run failures stand (old records without a kind
    are run failures), infrastructure failures and absent folders are run again."""
    scenes = short("a_1", "a_2", "a_3", "b_1", "b_2")
    records = {"a_1": {"status": "ok", "kind": None},
               "a_2": {"status": "failed", "kind": "run"},
               "a_3": {"status": "failed", "kind": "infrastructure"},
               "b_1": {"status": "failed"}}  # written before kinds; b_2 has no folder
    for name, record in records.items():
        folder = tmp_path / "runs" / scene_key(scenes[name])
        folder.mkdir(parents=True)
        if record["status"] == "ok":  # its files, with their checksums as at commit
            texts = {f: f"{f} of {name}\n" for f in RUN_FILES}
            for f, text in texts.items():
                (folder / f).write_text(text)
            record = record | {"files": checksums(texts)}
        (folder / "status.json").write_text(json.dumps(
            {"hash": folder.name, "name": name, **record}))

    def todo(**options):
        return sorted(job.names[0] for job in missing(scenes, tmp_path, **options))
    assert todo() == ["a_3", "b_2"]
    assert todo(rerun_failed=True) == ["a_2", "a_3", "b_1", "b_2"]
    # an ok run whose history was cut after its commit is run again
    (tmp_path / "runs" / scene_key(scenes["a_1"]) / "history.csv").write_text("history")
    assert todo() == ["a_1", "a_3", "b_2"]


def test_a_failure_records_its_kind(tmp_path):
    """run_task's error is a run failure; no result from Dask, or files that cannot be
    written, an infrastructure failure."""
    from distributed import KilledWorker
    scene = paper_scene("a_1", SHORT)
    job = Job(scene_key(scene), ["a_1"], scene, key_parts(scene))
    raised = {"run": None, "wall_s": 0.1, "worker": "tcp://127.0.0.1:1", "error": "E: e",
              "traceback": "", "exception": None}
    assert _record(job, raised)[0]["kind"] == "run"
    worker = types.SimpleNamespace(address="tcp://127.0.0.1:1")  # its last, as Dask's state
    lost = KilledWorker("run-x", worker, 3)  # the workers running it died more than 3 times
    assert _record(job, lost)[0]["kind"] == "infrastructure"
    assert _record(job, concurrent.futures.CancelledError("run-x"))[0]["kind"] == (
        "infrastructure")
    record = _record(job, {**raised, "run": "not a Run's files"})[0]
    assert (record["status"], record["kind"]) == ("ok", None)
    (tmp_path / "runs").mkdir()
    commit_run(tmp_path / "runs", job, record, "not a Run's files")
    written = read_status(tmp_path / "runs" / job.hash)
    assert (written["status"], written["kind"]) == ("failed", "infrastructure"), written
    assert written["error"].startswith("writing its files: ")


def _file(tmp_path):
    (tmp_path / "a_file").write_text("not a folder")
    return tmp_path / "a_file"


def _foreign(tmp_path):
    (tmp_path / "home").mkdir()
    (tmp_path / "home" / "thesis.tex").write_text("precious")
    return tmp_path / "home"


_HOLDERS = []  # processes holding a lock for a test, released after it


@pytest.fixture(autouse=True)
def _release_held_locks():
    yield
    while _HOLDERS:
        holder = _HOLDERS.pop()
        holder.stdin.close()
        holder.wait(timeout=30)


def _locked(tmp_path):
    """A sweep's folder that another live process holds the (kernel) lock of."""
    busy = tmp_path / "busy"
    busy.mkdir()
    (busy / "sweep.json").write_text('{"invocations": []}')
    holder = subprocess.Popen(
        [sys.executable, "-c", "import sys\nfrom drake_car.results.lock import exclusive\n"
         "with exclusive(sys.argv[1]):\n    print('held', flush=True)\n    sys.stdin.read()",
         str(busy / ".sweep.lock")], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    _HOLDERS.append(holder)
    assert holder.stdout.readline().strip() == "held"
    return busy


A_3 = ["--scene", f"{PAPER_SCENES}:a_3"]
# (label, argv, what the message names, the --out (None: tmp_path / "out"))
BAD = [
    ("unknown grid key", A_3 + ["--grid", "frictoin.law.mu_s=0.1"], "frictoin", None),
    ("value out of range", A_3 + ["--grid", "friction.law.mu_s=0.4,-1"],
     "friction.law.mu_s", None),
    ("not a number", A_3 + ["--grid", "plant.time_step=fast"], "plant.time_step", None),
    ("grid without values", A_3 + ["--grid", "friction.law.mu_s"], "--grid", None),
    ("grid value twice", A_3 + ["--grid", "friction.law.mu_s=0.4,0.4"], "twice", None),
    ("grid key twice", A_3 + ["--grid", "plant.time_step=0.001", "--grid",
                              "plant.time_step=0.002"], "twice", None),
    ("grid and scene text", A_3 + ["--scene_text", "friction: null", "--grid",
                                   "friction.law.mu_s=0.4"], "friction", None),
    ("bad scene text", A_3 + ["--scene_text", "simulator: {end_time_s: -1.0}"],
     "simulator.end_time_s", None),
    ("live view", A_3 + ["--scene_text", "visualization: !MeshcatLive {}"], "MeshcatLive",
     None),
    ("no such entry", ["--scene", f"{PAPER_SCENES}:c_9"], "c_9", None),
    ("no scenes file", ["--scene", "no/such.yaml"], "no/such.yaml", None),
    ("no workers", A_3 + ["--workers", "0"], "--workers", None),
    ("workers and scheduler", A_3 + ["--workers", "2", "--scheduler", "tcp://127.0.0.1:1"],
     "--workers", None),
    ("out is a file", A_3, "is a file", _file),
    ("out is someone's folder", A_3, "not a sweep's folder", _foreign),
    ("out is being written", A_3, "another sweep", _locked),
]


@pytest.mark.parametrize("label, argv, key, target", BAD, ids=[b[0] for b in BAD])
def test_bad_input_exits_2_with_nothing_written(label, argv, key, target, tmp_path, capsys):
    out = target(tmp_path) if target else tmp_path / "out"
    before = {p: p.stat().st_mtime_ns for p in tmp_path.rglob("*")}
    with pytest.raises(SystemExit) as stopped:
        cli.run_main(sweep_command.main, [*argv, "--out", str(out)])
    assert stopped.value.code == 2, label
    err = capsys.readouterr().err
    assert key in err, err
    assert "error: " in err.strip().splitlines()[-1] and "Traceback" not in err
    assert {p: p.stat().st_mtime_ns for p in tmp_path.rglob("*")} == before  # nothing written
