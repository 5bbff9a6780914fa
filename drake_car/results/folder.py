"""Output folders written all or nothing.

``output_folder(out)`` checks the target at once (an existing file, a folder that is not a
drake_car output, an unwritable place are refused before any work), takes the folder's lock
(``results.lock``: a second writer to the same folder is refused), and yields a temporary
folder beside the target; on success the target is replaced by it whole (a reused folder never
mixes old and new files), on any error, Ctrl-C or SIGTERM the temporary folder is removed.
Temporary folders of killed runs are removed by the next run that takes the lock (nobody else
can be writing them then) and ignored by git (``.gitignore``).
"""

import contextlib
import os
import shutil
import signal
import uuid
from pathlib import Path

from drake_car.results.lock import LockHeld, exclusive

MARKER = ".drake_car_output"  # in every folder this module wrote


class OutputError(ValueError):
    """The output folder cannot be used; the message names it and why."""


def check_output_target(out_dir):
    """Refuses an output target that cannot be written as a whole, before any work."""
    out_dir = Path(out_dir)
    if out_dir.is_file() or (out_dir.exists() and not out_dir.is_dir()):
        raise OutputError(f"--out {out_dir}: is a file, not a folder")
    if out_dir.is_dir() and any(out_dir.iterdir()) and not (out_dir / MARKER).is_file():
        raise OutputError(f"--out {out_dir}: exists, is not empty and was not written by "
                          "drake_car; choose a new or empty folder (it would be replaced whole)")
    parent = out_dir.parent
    probe = parent
    while not probe.exists():
        probe = probe.parent
    if not probe.is_dir() or not os.access(probe, os.W_OK | os.X_OK):
        raise OutputError(f"--out {out_dir}: {probe} is not a writable folder")


@contextlib.contextmanager
def folder_lock(lock_path, target, what="run"):
    """``results.lock.exclusive`` on ``lock_path`` for the output ``target``; another holder
    is refused as an OutputError naming the target."""
    try:
        with exclusive(lock_path):
            yield
    except LockHeld as e:
        raise OutputError(f"--out {target}: another {what} (pid {e.owner or 'unknown'}) is "
                          "writing to it; wait for it or choose another folder") from None


@contextlib.contextmanager
def terminate_as_exit(*, once=False):
    """SIGTERM raises SystemExit here, so ``finally`` blocks clean up as on Ctrl-C; ``once``:
    a second SIGTERM during that cleanup is ignored."""
    def handler(signum, frame):
        if once:
            signal.signal(signal.SIGTERM, signal.SIG_IGN)
        raise SystemExit(128 + signum)
    try:
        previous = signal.signal(signal.SIGTERM, handler)
    except ValueError:  # not the main thread: leave the signal alone
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


@contextlib.contextmanager
def output_folder(out_dir):
    """Yields a temporary folder beside ``out_dir``; on success it replaces ``out_dir`` whole;
    on any error (or SIGINT/SIGTERM) it is removed and ``out_dir`` is left as it was."""
    out_dir = Path(out_dir).absolute()
    check_output_target(out_dir)
    parent, name = out_dir.parent, out_dir.name
    parent.mkdir(parents=True, exist_ok=True)
    with terminate_as_exit(), folder_lock(parent / f".{name}.lock", out_dir):
        for stale in parent.glob(f".{name}.partial-*"):  # killed runs': we hold the lock
            shutil.rmtree(stale, ignore_errors=True)
        staging = parent / f".{name}.partial-{os.getpid()}-{uuid.uuid4().hex[:8]}"
        staging.mkdir()
        try:
            (staging / MARKER).write_text("written by drake_car; replaced whole by the next "
                                          "run that writes here\n")
            yield staging
            check_output_target(out_dir)  # still a folder we may replace
            old = None
            if out_dir.exists():
                old = parent / f".{name}.partial-{os.getpid()}-old-{uuid.uuid4().hex[:8]}"
                out_dir.rename(old)
            staging.rename(out_dir)
            if old is not None:
                shutil.rmtree(old, ignore_errors=True)
        finally:
            if staging.exists():
                shutil.rmtree(staging, ignore_errors=True)
