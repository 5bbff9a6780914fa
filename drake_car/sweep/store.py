"""A sweep's results folder: a run folder per content hash (written whole as its run
completes), the index rebuilt from them, a lock so that one sweep writes at a time
(``sweep.runner`` describes the layout). A failed run's status.json says its kind: "run" (the
simulation raised: kept) or "infrastructure" (Dask gave no result, or its files could not be
written: the next sweep runs it again); one without a kind counts as "run"."""

import contextlib
import csv
import logging
import hashlib
import io
import json
import os
import shutil
import traceback
import uuid
from pathlib import Path

from drake_car.law.tyre.tir import read_tir_bytes
from drake_car.model.loading import tir_path
from drake_car.results.columns import folder_readme
from drake_car.results.files import named, write_text
from drake_car.results.folder import (
    OutputError, check_no_run_in_progress, check_writable, os_error_reason)
from drake_car.results.folder import folder_lock as results_folder_lock
from drake_car.results.lock import holder
from drake_car.results.provenance import code_versions
from drake_car.results.record import (
    RUN_FILES, checksums, read_texts, refuse_pickles, run_from_texts)
from drake_car.scene.load import dump_scene_file, scene_hash
from drake_car.scene.scene import TirTyre

log = logging.getLogger(__name__)

INDEX_FIELDS = ("hash", "name", "status", "wall_s", "error")
# A failed run's kind (its status.json's "kind"): the run itself raised (kept: a run is a pure
# function of its scene), or the machinery around it failed (run again by the next sweep).
RUN_FAILURE = "run"
INFRASTRUCTURE_FAILURE = "infrastructure"


def files_read(scene):
    """path -> sha256 of every file ``scene``'s run reads beyond the package's code and data
    (its .tir file; the model files are the package's, under its commit): a missing or bad
    file raises TirFileError naming it, before any run."""
    files = {}
    if isinstance(scene.tyres, TirTyre):
        path = tir_path(scene.tyres.tir_file)
        files[scene.tyres.tir_file] = hashlib.sha256(read_tir_bytes(path)).hexdigest()
    return files


def key_parts(scene):
    """What a run's key is made of: the scene's content hash, the content of the files it
    reads (``files_read``) and the code that runs it (``results.provenance.code_versions``)."""
    return {"scene_hash": scene_hash(scene), "files": files_read(scene),
            "code": code_versions()}


def run_key(parts):
    """A run folder's name: the hash of its ``key_parts`` (equal keys make equal runs)."""
    text = json.dumps(parts, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def read_status(folder):
    """A run folder's status.json (None when missing, unreadable or not a status record)."""
    try:
        record = json.loads((Path(folder) / "status.json").read_text())
    except (OSError, ValueError):
        return None
    if not (isinstance(record, dict) and record.get("status") in ("ok", "failed")
            and isinstance(record.get("hash"), str)):
        return None
    return record


def damage(folder, record):
    """Why finished run ``folder`` cannot be reused (None if it can): a file missing or not
    matching the checksum recorded when it was committed, a pickle in it, no status."""
    folder = Path(folder)
    if record is None:
        return "status.json missing or damaged" if folder.exists() else None
    if any(folder.glob("*.pkl")):
        return "holds a pickle (never loaded)"
    if record["status"] != "ok":
        return None
    recorded = record.get("files")
    if not isinstance(recorded, dict) or not set(RUN_FILES) <= set(recorded):
        return "no checksums recorded"
    try:
        found = checksums(read_texts(folder, tuple(recorded)))
    except OutputError as e:
        return str(e)
    for name, digest in recorded.items():
        if found.get(name) != digest:
            return f"{name} {'missing' if name not in found else 'changed since its commit'}"
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
    rows.sort(key=lambda s: (str(s.get("finished_utc", "")), s["hash"]))
    buffer = io.StringIO(newline="")
    writer = csv.DictWriter(buffer, INDEX_FIELDS, extrasaction="ignore")
    writer.writeheader()
    writer.writerows(rows)
    if (out / "index.csv").exists() and not (out / "index.csv").is_file():
        raise OutputError(f"{out / 'index.csv'}: is not a file; remove it (the index is "
                          "rebuilt from runs/)")
    write_text(out / "index.csv", buffer.getvalue())
    write_text(out / "README.md", folder_readme(out, f"sweep {out.name}"))


def check_layout(out):
    """Refuses a sweep folder whose bookkeeping is damaged, naming the file and the repair
    (nothing is silently replaced): runs/ not a folder, index.csv not a file, a pickle in it,
    sweep.json not a record of invocations."""
    out = Path(out)
    runs = out / "runs"
    if runs.exists() and not runs.is_dir():
        raise OutputError(f"{runs}: is not a folder; move it away (a sweep keeps its runs "
                          "there)")
    if (out / "index.csv").exists() and not (out / "index.csv").is_file():
        raise OutputError(f"{out / 'index.csv'}: is not a file; remove it (the index is "
                          "rebuilt from runs/)")
    refuse_pickles(out)
    read_sweep_log(out)


def read_sweep_log(out):
    """sweep.json's record of invocations ({"invocations": []} when there is none); one that
    is not such a record is named, never replaced."""
    path = Path(out) / "sweep.json"
    if not path.exists():
        return {"invocations": []}
    try:
        log = json.loads(path.read_text())
    except (OSError, ValueError) as e:
        raise OutputError(f"{path}: not readable JSON ({type(e).__name__}); repair or move it "
                          "away (it records this sweep's invocations; the runs do not need "
                          "it)") from None
    if not (isinstance(log, dict) and isinstance(log.get("invocations"), list)):
        raise OutputError(f"{path}: not a sweep's record (no list of invocations); repair or "
                          "move it away (the runs do not need it)")
    return log


def load_run(out_dir, key):
    """(status record, the Run or None) of run folder ``key`` of ``out_dir``."""
    folder = Path(out_dir) / "runs" / key
    refuse_pickles(folder)
    record = read_status(folder)
    if record is None:
        raise OutputError(f"{folder}: no run there (no readable status.json)")
    if record["status"] != "ok":
        return record, None
    why = damage(folder, record)
    if why:
        raise OutputError(f"{folder}: {why}; run the sweep again (damaged runs are rerun)")
    # The files are what was committed (their checksums): the scene is not checked again.
    return record, run_from_texts(read_texts(folder), str(folder), trusted=True)


def commit_run(runs, job, record, result):
    """Writes one run's folder as ``runs/.tmp-*`` and renames it to ``runs/<hash>``: an ok
    run's ``result`` is its files' texts (``results.record.run_texts``, made on the worker),
    their checksums go into status.json ("files"). An ok run whose worker sent no files is
    recorded as failed, of kind ``INFRASTRUCTURE_FAILURE``; an OS error (a full disk) goes up,
    nothing of the run's folder left: the disk does not empty itself, so the sweep stops (its
    runs so far kept) rather than compute the others to lose them too."""
    tmp = runs / f".tmp-{job.hash}-{uuid.uuid4().hex[:8]}"
    try:
        tmp.mkdir()
        if record["status"] == "ok":
            try:
                if not (isinstance(result, dict) and set(RUN_FILES) <= set(result)):
                    raise ValueError("the worker sent no run files")
                for name, text in result.items():
                    with named(tmp / Path(name).name):
                        (tmp / Path(name).name).write_text(text)
                record["files"] = checksums(result)
            except OSError:
                raise
            except Exception as e:  # this run fails, not the sweep
                shutil.rmtree(tmp)
                tmp.mkdir()
                record.update(status="failed", kind=INFRASTRUCTURE_FAILURE,
                              error=f"writing its files: {type(e).__name__}: {e}",
                              traceback=traceback.format_exc())
        if not (tmp / "scene.yaml").exists():
            with named(tmp / "scene.yaml"):
                (tmp / "scene.yaml").write_text(dump_scene_file(job.scene))
        with named(tmp / "status.json"):
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


def append_index_row(out, record):
    """Appends ``record``'s row to ``out``/index.csv whole, or not at all: a write cut short
    (a full disk) is truncated back and its error goes up naming the file."""
    path = Path(out) / "index.csv"
    buffer = io.StringIO(newline="")
    csv.DictWriter(buffer, INDEX_FIELDS, extrasaction="ignore").writerow(record)
    data = buffer.getvalue().encode()
    fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o666)
    try:
        size = os.fstat(fd).st_size
        try:
            with named(path):
                written = 0
                while written < len(data):
                    written += os.write(fd, data[written:])
        except BaseException:
            os.ftruncate(fd, size)
            raise
    finally:
        os.close(fd)


@contextlib.contextmanager
def sweep_output(out):
    """Around the writing of sweep folder ``out``: an OS error about it (a full disk, a refused
    write, a folder removed; ``results.folder.os_error_reason``) is an OutputError naming
    --out, the path and the reason, and that the runs finished are kept; a folder this made
    (new, or empty before) that ends in an error before any run is kept in it is removed
    again (emptied, if it was there): nothing written."""
    out = Path(out).absolute()
    new = not out.exists()
    empty = out.is_dir() and not any(out.iterdir())
    try:
        yield
    except BaseException as e:
        kept = kept_runs(out)
        if (new or empty) and not kept and out.is_dir() and holder(
                out / ".sweep.lock") in (None, os.getpid()):
            if new:
                shutil.rmtree(out, ignore_errors=True)
            else:
                for path in out.iterdir():
                    shutil.rmtree(path) if path.is_dir() else path.unlink(missing_ok=True)
        reason = os_error_reason(e, out) if isinstance(e, OSError) else None
        if reason is None:
            raise
        raise OutputError(f"--out {out}: {reason}" + (
            f"; the runs finished ({kept}) are kept: run the same command again to go on"
            if kept else "")) from None


@contextlib.contextmanager
def writing(out):
    """Sweep folder ``out`` being written: ``sweep_output`` (an OS error one line; a new folder
    that gets no run removed again), its lock, its temporary run folders removed and its index
    rebuilt before and after (after an error too, where a second OS error does not hide the
    one that stopped the sweep). Yields ``out``/runs."""
    out = Path(out)
    runs = out / "runs"
    with sweep_output(out):
        runs.mkdir(parents=True, exist_ok=True)
        with folder_lock(out):
            stopped = True
            try:
                remove_stale(runs)
                rebuild_index(out)
                yield runs
                stopped = False
            finally:
                remove_stale(runs)
                try:
                    rebuild_index(out)
                except OSError:
                    if not stopped:
                        raise


def kept_runs(out):
    """How many run folders ``out``/runs holds (its temporary ones not counted)."""
    runs = Path(out) / "runs"
    if not runs.is_dir():
        return 0
    return sum(1 for p in runs.iterdir() if not p.name.startswith("."))


def announce(message):
    log.info(message)


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


def announce_other_code(runs, todo):
    """Says which of the runs to do ``out`` already holds, made by other code or files."""
    if not todo or not runs.is_dir():
        return
    other = {}
    for folder in runs.iterdir():
        record = read_status(folder)
        parts = (record or {}).get("key")
        if isinstance(parts, dict) and parts.get("scene_hash") in todo:
            mine = todo[parts["scene_hash"]].parts
            for what in ("code", "files"):
                if isinstance(parts.get(what), dict) and parts[what] != mine[what]:
                    names = sorted(k for k in parts[what].keys() | mine[what].keys()
                                   if parts[what].get(k) != mine[what].get(k))
                    other.setdefault(f"{what} ({', '.join(names)[:200]})", set()).add(
                        parts["scene_hash"])

    for what, scenes in other.items():
        announce(f"{runs}: {len(scenes)} of these scenes were run before by other {what}; "
                 "they run again under this one (the old runs are kept)")


def check_sweep_folder(out):
    """Refuses an --out that is neither new, nor empty, nor a sweep's folder (sweep.json, or
    index.csv from ``run_sweep``), or that another sweep is writing to."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise OutputError(f"--out {out}: is a file, not a folder")
    if out.is_dir() and any(out.iterdir()) and not any(
            (out / name).is_file() for name in ("sweep.json", "index.csv")):
        raise OutputError(f"--out {out}: exists, is not empty and is not a sweep's folder (no "
                          "sweep.json); choose a new or empty folder, or a sweep's to resume it")
    probe = out
    while not probe.exists():
        probe = probe.parent
    if not probe.is_dir() or not os.access(probe, os.W_OK | os.X_OK):
        raise OutputError(f"--out {out}: {probe} is not a writable folder")
    check_writable(out, probe)
    check_unlocked(out)
    check_no_run_in_progress(out)  # not inside or around another command's output in progress
    if out.is_dir():
        check_layout(out)
