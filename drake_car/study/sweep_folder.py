"""A sweep's results folder: a run folder per content hash (written whole as its run
completes), the index rebuilt from them, a lock so that one sweep writes at a time
(``study.sweep`` describes the layout). A failed run's status.json says its kind: "run" (the
simulation raised: kept) or "infrastructure" (Dask gave no result, or its files could not be
written: the next sweep runs it again); one without a kind counts as "run"."""

import contextlib
import csv
import json
import os
import pickle
import shutil
import traceback
import uuid
from pathlib import Path

import psutil

from drake_car.scene.load import dump_scene_file
from drake_car.sim.outputs import OutputError, write_run

INDEX_FIELDS = ("hash", "name", "status", "wall_s", "error")
# A failed run's kind (its status.json's "kind"): the run itself raised (kept: a run is a pure
# function of its scene), or the machinery around it failed (run again by the next sweep).
RUN_FAILURE = "run"
INFRASTRUCTURE_FAILURE = "infrastructure"


def read_status(folder):
    """A run folder's status.json (None when missing or unreadable)."""
    try:
        return json.loads((Path(folder) / "status.json").read_text())
    except (OSError, ValueError):
        return None


def failure_kind(record):
    """A failed run's kind, ``RUN_FAILURE`` or ``INFRASTRUCTURE_FAILURE`` (a status.json
    written before kinds were recorded has none: its run failed)."""
    return record.get("kind") or RUN_FAILURE


def rebuild_index(out_dir):
    """Rewrites ``index.csv`` (atomically) from every run folder's status.json."""
    out = Path(out_dir)
    rows = [s for d in (out / "runs").iterdir()
            if not d.name.startswith(".") and (s := read_status(d))]
    rows.sort(key=lambda s: (s.get("finished_utc", ""), s["hash"]))
    tmp = out / f".index.csv.{uuid.uuid4().hex[:8]}"
    with open(tmp, "w", newline="") as f:
        writer = csv.DictWriter(f, INDEX_FIELDS, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)
    os.replace(tmp, out / "index.csv")


def load_run(out_dir, key):
    """(status record, the Run or None) of run folder ``key`` of ``out_dir``."""
    folder = Path(out_dir) / "runs" / key
    record = read_status(folder)
    if record is None:
        raise OutputError(f"{folder}: no run there (no readable status.json)")
    run = pickle.loads((folder / "run.pkl").read_bytes()) if record["status"] == "ok" else None
    return record, run


def commit_run(runs, job, record, result):
    """Writes one run's folder as ``runs/.tmp-*`` and renames it to ``runs/<hash>``. An ok run
    whose files cannot be written is recorded as failed, of kind ``INFRASTRUCTURE_FAILURE``."""
    tmp = runs / f".tmp-{job.hash}-{uuid.uuid4().hex[:8]}"
    try:
        tmp.mkdir()
        if record["status"] == "ok":
            try:
                write_run(pickle.loads(result), tmp, diagram=False)
                (tmp / "run.pkl").write_bytes(result)
            except Exception as e:  # this run fails, not the sweep
                shutil.rmtree(tmp)
                tmp.mkdir()
                record.update(status="failed", kind=INFRASTRUCTURE_FAILURE,
                              error=f"writing its files: {type(e).__name__}: {e}",
                              traceback=traceback.format_exc())
        if not (tmp / "scene.yaml").exists():
            (tmp / "scene.yaml").write_text(dump_scene_file(job.scene))
        (tmp / "status.json").write_text(json.dumps(record, indent=1) + "\n")
        final = runs / job.hash
        if final.exists():  # a failed run done again: swap (killed in between: run missing)
            old = runs / f".tmp-old-{job.hash}-{uuid.uuid4().hex[:8]}"
            final.rename(old)
            tmp.rename(final)
            shutil.rmtree(old, ignore_errors=True)
        else:
            tmp.rename(final)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


def remove_stale(runs):
    for path in runs.glob(".tmp-*"):
        shutil.rmtree(path, ignore_errors=True)


def check_unlocked(out):
    """Refuses ``out`` while another live sweep writes to it (its ``.sweep.lock``)."""
    try:
        pid = int((Path(out) / ".sweep.lock").read_text().strip() or "0")
    except (OSError, ValueError):
        return
    if pid != os.getpid() and psutil.pid_exists(pid):
        raise OutputError(f"--out {out}: another sweep (pid {pid}) is writing to it; wait "
                          "for it or choose another folder")


@contextlib.contextmanager
def folder_lock(out):
    lock = out / ".sweep.lock"
    for _ in range(2):
        try:
            fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
            break
        except FileExistsError:
            check_unlocked(out)
            lock.unlink(missing_ok=True)  # a killed sweep's lock
    else:
        raise OutputError(f"--out {out}: cannot take the lock {lock}")
    with os.fdopen(fd, "w") as f:
        f.write(str(os.getpid()))
    try:
        yield
    finally:
        lock.unlink(missing_ok=True)


