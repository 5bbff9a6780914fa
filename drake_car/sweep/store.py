"""A sweep's results folder: a run folder per content hash (written whole as its run
completes), the index rebuilt from them, a lock so that one sweep writes at a time
(``sweep.runner`` describes the layout). A failed run's status.json says its kind: "run" (the
simulation raised: kept) or "infrastructure" (Dask gave no result, or its files could not be
written: the next sweep runs it again); one without a kind counts as "run"."""

import csv
import io
import json
import pickle
import shutil
import traceback
import uuid
from pathlib import Path

from drake_car.results.files import write_run, write_text
from drake_car.results.folder import OutputError
from drake_car.results.folder import folder_lock as results_folder_lock
from drake_car.results.lock import holder
from drake_car.scene.load import dump_scene_file

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
    buffer = io.StringIO(newline="")
    writer = csv.DictWriter(buffer, INDEX_FIELDS, extrasaction="ignore")
    writer.writeheader()
    writer.writerows(rows)
    write_text(out / "index.csv", buffer.getvalue())


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
    """Refuses ``out`` while another live sweep writes to it (holds its ``.sweep.lock``)."""
    owner = holder(Path(out) / ".sweep.lock")
    if owner is not None:
        raise OutputError(f"--out {out}: another sweep (pid {owner}) is writing to it; wait "
                          "for it or choose another folder")


def folder_lock(out):
    """The sweep folder's lock (``results.lock``): one sweep writes to a folder at a time."""
    return results_folder_lock(Path(out) / ".sweep.lock", out, what="sweep")
