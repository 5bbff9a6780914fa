"""Sweeps: many scenes, each run as one Dask task (``dask.distributed``), each result kept as
it completes.

Where runs go: a ``LocalCluster`` started here, one single-threaded worker process per core
(``workers``), its scheduler, nannies, workers and dashboards all on 127.0.0.1 only; or any
running cluster by its scheduler's address (``scheduler``; left running; its workers must be
able to import drake_car). A scene travels as its YAML (Drake's configs do not pickle) and is
loaded and checked on the worker; its ``Run`` comes back as its files' texts
(``results.record.run_texts``: history.csv, scene.yaml, run.json with the provenance of the
worker that ran it, diagram.dot), never a pickle.

``run_sweep(scenes, out_dir)`` writes a results folder keyed by each run's key
(``sweep.store.run_key``: the scene's content hash, the content hash of the files it reads,
the code and versions that run it; equal keys make equal runs, two names with one key run
once; a worker whose code or files differ from the key's refuses the run, an infrastructure
failure that names the difference)::

    DIR/runs/<hash>/status.json   hash, name(s), status (ok|failed), kind (a failed run's:
                                  run|infrastructure; else null), wall_s (the task on its
                                  worker: build, equilibrium unless cached, run), worker,
                                  finished_utc, error, traceback
    DIR/runs/<hash>/scene.yaml    the scene (rerun it: drake-car-run --scene it)
    DIR/runs/<hash>/history.csv, run.json, diagram.dot   an ok run's files (their sha256 in
                                  status.json's "files": checked on resume, a damaged run is
                                  run again; a folder with a *.pkl is refused)
    DIR/index.csv                 hash, name, status, wall_s, error: a row per run folder

A run folder appears whole (``runs/.tmp-*`` renamed) as its run completes, and its row is
appended to the index, which is rebuilt from the folders at the start and the end (also on
Ctrl-C, or SIGTERM made SystemExit: the rest is cancelled; Ctrl-C is then a
``SweepInterrupted`` saying what was kept; the workers ignore SIGINT and are shut down,
``sweep.cluster``). A worker that dies mid-run is
restarted by its nanny and its runs handed out again. A failed run is recorded with its error,
traceback and kind, and the sweep goes on. Kind "run": the simulation raised in ``run_task``;
not retried (a run is a pure function of its scene: it would fail again). Kind
"infrastructure": Dask gave no result for it (KilledWorker, after its workers died more than
``distributed.scheduler.allowed-failures`` (3) times; cancelled; a worker lost; run_task not
importable there), or its files could not be written (``commit_run``). A restarted sweep
reuses every ok run and, unless ``rerun_failed``, every run failure; it runs the missing
scenes and the infrastructure failures again (``missing``). A status.json without a kind
(written before kinds were recorded) counts as a run failure. One sweep per folder at a time
(``DIR/.sweep.lock``). A restart under other code or files makes other keys: its scenes run
again (the old runs are kept, and counted on stderr with what differs).
"""
import contextlib
import dataclasses
import datetime
import os
import pickle
import sys
import time
import traceback
import uuid
from pathlib import Path

from pydrake.common.yaml import yaml_load_typed

from drake_car.law.checks import one_line
from drake_car.law.errors import RunFailed
from drake_car.results.files import run_texts
from drake_car.results.provenance import code_versions
from drake_car.results.record import run_from_texts
from drake_car.scene.load import dump_scene, scene_hash
from drake_car.scene.scene import Scene
from drake_car.sim.branch import branch_point, simulate_family
from drake_car.sim.lane_change_calibration import adapted_scenes
from drake_car.sim.simulate import simulate
from drake_car.sweep.cluster import cores, dask_client, local_cluster  # noqa: F401 (theirs)
from drake_car.sweep.store import (
    INFRASTRUCTURE_FAILURE, RUN_FAILURE, announce, announce_other_code, append_index_row,
    check_layout, commit_run, damage, failure_kind, files_read, key_parts, load_run,
    read_status, run_key, writing)
from drake_car.systems.failure import SimulationFailure

# -- on the worker ---------------------------------------------------------------------------

def run_task(items):
    """Runs on a worker: the scenes of ``items`` ([(scene YAML, content hash), ...]), checked
    and simulated; scenes that share a prefix (``sim.branch``: a lane change's cases) run it
    once. Returns, per item, {"run": its files' texts (None if it raised), "wall_s", "worker",
    and if it raised "error" (type: message), "traceback" and "exception" (pickled, or None)}:
    a run's failure is a result (Dask neither retries nor logs it). When a family fails, its
    scenes are run one by one, so that only the failing one is recorded as failed."""
    from distributed import get_worker
    worker = get_worker().address
    began = time.perf_counter()
    try:
        scenes = [_scene_of(text, parts) for text, parts in items]
    except OtherCode as e:
        return [_failed(e, began, worker) | {"kind": INFRASTRUCTURE_FAILURE}] * len(items)
    try:
        runs = simulate_family(scenes) if len(scenes) > 1 else [simulate(scenes[0])]
        wall = (time.perf_counter() - began) / len(runs)
        return [{"run": run_texts(run, worker=worker), "wall_s": wall, "worker": worker}
                for run in runs]
    except Exception as e:
        if len(items) == 1:
            return [_failed(e, began, worker)]
    results = []
    for scene in scenes:
        began = time.perf_counter()
        try:
            results.append({"run": run_texts(simulate(scene), worker=worker),
                            "wall_s": time.perf_counter() - began, "worker": worker})
        except Exception as e:
            results.append(_failed(e, began, worker))
    return results


class OtherCode(RunFailed):
    """A worker's code, versions or files differ from what the run's key was made of."""


def _scene_of(text, parts):
    # The parent checked the scene; its hash says this is that scene: not checked again.
    scene = yaml_load_typed(schema=Scene, data=text)
    if scene_hash(scene) != parts["scene_hash"]:
        raise RuntimeError(f"the scene's YAML loads back as {scene_hash(scene)}, "
                           f"not {parts['scene_hash']}")
    here = {"code": code_versions(), "files": files_read(scene)}
    for what in ("code", "files"):
        if here[what] != parts[what]:
            differ = {k: (parts[what].get(k), here[what].get(k))
                      for k in parts[what].keys() | here[what].keys()
                      if parts[what].get(k) != here[what].get(k)}
            raise OtherCode(f"this worker's {what} differ from the sweep's (sweep, worker): "
                            f"{differ}"[:400])
    return scene


def _failed(e, began, worker):
    return {"run": None, "wall_s": time.perf_counter() - began, "worker": worker,
            "error": f"{type(e).__name__}: {one_line(e)}",
            "traceback": traceback.format_exc(), "exception": _pickled(e)}


def _pickled(error):
    """``error`` pickled, if it unpickles again (else None)."""
    with contextlib.suppress(Exception):
        blob = pickle.dumps(error)
        pickle.loads(blob)
        return blob
    return None


# -- in the parent ---------------------------------------------------------------------------

@dataclasses.dataclass
class Job:
    """One distinct run: its key (``run_key``), the names it goes by, its scene (the first
    name), what its key is made of (``key_parts``)."""
    hash: str
    names: list
    scene: Scene
    parts: dict = None


def jobs_of(scenes: dict):
    """key -> Job for name -> Scene (as it runs: adapted to its car here, not on a worker)."""
    jobs = {}
    for name, scene in adapted_scenes(scenes, run=simulate).items():
        parts = key_parts(scene)
        key = run_key(parts)
        if key in jobs:
            jobs[key].names.append(name)
        else:
            jobs[key] = Job(key, [name], scene, parts)
    return jobs


def tasks_of(jobs):
    """The jobs grouped into tasks: those whose scenes share a prefix (``sim.branch``) in one
    task, which runs the prefix once; every other job alone."""
    groups = {}
    for job in jobs:
        point = branch_point(job.scene)
        groups.setdefault(point if point is not None else ("alone", job.hash), []).append(job)
    return list(groups.values())


def compute(client, jobs, done, *, progress=True, desc="sweep"):
    """Submits ``jobs`` to ``client`` (as ``tasks_of``) and calls ``done(job, record,
    result)`` for each as its task completes (``result``: the pickled Run, or if it failed its
    exception, pickled when it could be, or Dask's); a progress bar with the time left.
    Whatever has not completed when this returns or raises is cancelled."""
    from distributed import as_completed
    from tqdm import tqdm
    token = uuid.uuid4().hex[:8]  # distinct task keys for each sweep on a shared scheduler
    tasks = tasks_of(jobs)
    futures = client.map(run_task, [[(dump_scene(j.scene), j.parts) for j in task]
                                    for task in tasks],
                         key=[f"run-{task[0].hash}-{len(task)}-{token}" for task in tasks],
                         pure=False)
    pending = {f.key: task for f, task in zip(futures, tasks)}
    failed = 0
    bar = tqdm(total=len(jobs), desc=desc, unit="run", file=sys.stderr, smoothing=0.1,
               disable=None if progress else True)
    try:
        # with_results: each result is fetched as soon as it is done (one left on a worker
        # that dies would be computed again); loop: this client's, not the default client's
        for future, results in as_completed(futures, loop=client.loop, with_results=True,
                                            raise_errors=False):
            task = pending.pop(future.key)
            future.release()
            if not isinstance(results, list):  # the task itself failed (a killed worker ...)
                results = [results] * len(task)
            for job, result in zip(task, results):
                record, result = _record(job, result)
                done(job, record, result)
                failed += record["status"] == "failed"
                bar.set_postfix(failed=failed, refresh=False)
                bar.update()
    finally:
        bar.close()
        if pending:
            client.cancel([f for f in futures if f.key in pending])


def _record(job, result):
    """(status record, the pickled Run or the error) of what Dask gave for ``job``: a failure
    of kind ``RUN_FAILURE`` when run_task returned its error, else ``INFRASTRUCTURE_FAILURE``
    (Dask gave no result dict: KilledWorker, cancelled, ...)."""
    record = {"hash": job.hash, "key": job.parts, "name": job.names[0], "names": job.names,
              "status": "failed",
              "kind": INFRASTRUCTURE_FAILURE, "wall_s": None, "worker": "", "error": "",
              "traceback": "",
              "finished_utc": datetime.datetime.now(datetime.timezone.utc).isoformat(
                  timespec="milliseconds")}
    if isinstance(result, dict):  # run_task's
        record.update({k: result[k] for k in ("wall_s", "worker", "error", "traceback")
                       if k in result})
        if result["run"] is not None:
            record.update(status="ok", kind=None)
            return record, result["run"]
        record["kind"] = result.get("kind") or RUN_FAILURE
        return record, result["exception"]
    if isinstance(result, tuple):  # as_completed gives (type, error, traceback)
        result = result[1]
    # KilledWorker, cancelled, run_task not importable on the worker, ...
    record.update(error=f"{type(result).__name__}: {one_line(result)}",
                  traceback="".join(traceback.format_exception(result)))
    return record, result


def failure(name, record, error=None):
    """The exception for run ``name`` that failed (``error``: its exception, or it pickled):
    its own type with the run named (else the exception itself, or a SimulationFailure with
    the error's text), the worker's traceback as a note."""
    original = error
    if isinstance(error, bytes):
        with contextlib.suppress(Exception):
            original = pickle.loads(error)
    if isinstance(original, Exception):  # its own type, naming the run, where it can
        try:
            e = type(original)(f"run {name}: {original}")
            e.__cause__ = original
        except Exception:
            e = original
    else:
        e = SimulationFailure(f"run {name} failed: {record['error']}")
    e.add_note(f"run {name} failed on {record['worker'] or 'a Dask worker'}; there:\n"
               f"{record['traceback']}")
    return e


def missing(scenes, out_dir, *, rerun_failed=False, jobs=None):
    """The Jobs of ``scenes`` to run: those ``out_dir`` has no run folder for, or one that
    failed of kind ``INFRASTRUCTURE_FAILURE``, or (``rerun_failed``) any failed one. ``jobs``:
    ``jobs_of(scenes)`` when the caller has them (a run's key: ~8 ms, its scene as YAML)."""
    runs = Path(out_dir) / "runs"
    jobs = jobs if jobs is not None else jobs_of(scenes)
    todo = []
    for job in jobs.values():
        record = read_status(runs / job.hash)
        why = damage(runs / job.hash, record)
        if why:
            announce(f"{runs / job.hash}: {why}; run again")
            record = None
        if not kept(record, rerun_failed=rerun_failed):
            todo.append(job)
    announce_other_code(runs, {job.parts["scene_hash"]: job for job in todo})
    return todo


def kept(record, *, rerun_failed=False):
    """Whether a run folder's status record (None: no folder) stands, not to be run again: an
    ok run, or a run failure unless ``rerun_failed`` (see ``missing``)."""
    status = (record or {}).get("status")
    if status == "failed":
        return not rerun_failed and failure_kind(record) == RUN_FAILURE
    return status == "ok"


def run_sweep(scenes: dict, out_dir, *, client=None, scheduler=None, workers=None,
              progress=True, rerun_failed=False, jobs=None) -> dict:
    """Runs every scene of ``scenes`` (name -> Scene) that ``out_dir`` lacks, writing each
    result as it completes (see the module). On ``client``, else on the cluster at
    ``scheduler``, else on a local cluster of ``workers`` (default: one per core, at most one
    per run). ``jobs``: ``jobs_of(scenes)`` when the caller has them. Returns {"ok",
    "failed", "reused": counts, "wall_s", "status": hash -> ok|failed, "hashes": name ->
    hash}."""
    began = time.perf_counter()
    out = Path(out_dir)
    runs = out / "runs"
    jobs = jobs if jobs is not None else jobs_of(scenes)
    check_layout(out)
    counts = {"ok": 0, "failed": 0, "reused": 0}
    status = {}

    def done(job, record, result):
        commit_run(runs, job, record, result)
        append_index_row(out, record)
        status[job.hash] = record["status"]
        counts[record["status"]] += 1

    try:
        with writing(out):  # locked, its index rebuilt before and after
            todo = missing(scenes, out, rerun_failed=rerun_failed, jobs=jobs)
            for key in jobs.keys() - {job.hash for job in todo}:
                status[key] = read_status(runs / key)["status"]
            counts["reused"] = len(status)
            if todo and client is not None:
                compute(client, todo, done, progress=progress)
            elif todo:
                with dask_client(scheduler, min(workers or cores(), len(todo))) as own:
                    compute(own, todo, done, progress=progress)
    except KeyboardInterrupt:
        now = counts["ok"] + counts["failed"]
        raise SweepInterrupted(
            f"{now + counts['reused']} of {len(jobs)} runs kept in {out} ({now} finished now); "
            "the same command again runs the rest" if now + counts["reused"] else
            f"none of {len(jobs)} runs finished") from None
    return {**counts, "wall_s": time.perf_counter() - began, "status": status,
            "hashes": {name: key for key, job in jobs.items() for name in job.names}}


class SweepInterrupted(KeyboardInterrupt):
    """Ctrl-C during ``run_sweep``: its message says what was kept and how to finish."""


def run_scenes(scenes: dict, *, progress=True, workers=None, scheduler=None,
               out_dir=None, client=None, skip_failed=False, rerun_failed=False) -> dict:
    """name -> Run for name -> Scene, run as a sweep (see the module), in the scenes' order.
    ``out_dir`` None: the results are kept in memory only; a folder: they are written there
    too, as ``run_sweep`` does (a restart reuses its runs). On ``client`` if given (e.g. one
    cluster for the rounds of ``sweep.refine``), else as ``run_sweep``. If any run failed,
    raises the first failed run's error, in the scenes' order (``failure``), after all have
    run; with ``skip_failed`` leaves the failed runs out instead (their record is in
    ``out_dir``, where ``rerun_failed`` runs them again as ``run_sweep`` does)."""
    jobs = jobs_of(scenes := adapted_scenes(scenes, run=simulate))  # each as it runs
    results = {}
    if not jobs:
        return {}
    if out_dir is not None:
        run_sweep(scenes, out_dir, client=client, scheduler=scheduler, workers=workers,
                  progress=progress, jobs=jobs, rerun_failed=rerun_failed)
        results = {key: load_run(out_dir, key) for key in jobs}
    else:
        def keep(job, record, result):
            results[job.hash] = (record, run_from_texts(result, trusted=True) if record["status"] == "ok"
                                 else result)
        with (contextlib.nullcontext(client) if client is not None else
              dask_client(scheduler, min(workers or cores(), len(jobs)))) as own:
            compute(own, list(jobs.values()), keep, progress=progress, desc="runs")
    runs = {}
    key_of = {name: key for key, job in jobs.items() for name in job.names}
    for name, scene in scenes.items():
        record, run = results[key_of[name]]
        if record["status"] != "ok":
            if skip_failed:
                continue
            raise failure(name, record, run)
        runs[name] = run if run.scene.name == name else dataclasses.replace(run, scene=scene)
    return runs
