"""Output folders written all or nothing.

``output_folder(out)`` checks the target at once (an existing file, a folder that is not a
drake_car output, an unwritable place are refused before any work), takes the folder's lock
(``results.lock``: a second writer to the same folder is refused), and yields a temporary
folder beside the target; on success the target is replaced by it whole (a reused folder never
mixes old and new files), on any error, Ctrl-C or SIGTERM the temporary folder is removed.
An old output is replaced only while it holds nothing but what it wrote (its MARKER lists its
files): another output, a sweep folder or a user's file put inside it later is named and
refused (``check_only_its_own``), not deleted with it. A mount point is refused as --out (it
cannot be renamed; a folder inside it can).
Temporary folders of killed runs are removed by the next run that takes the lock (nobody else
can be writing them then) and ignored by git (``.gitignore``).
"""

import contextlib
import errno
import json
import os
import re
import shutil
import tempfile
import uuid
from pathlib import Path

from drake_car.law.checks import excerpt
from drake_car.law.errors import InputError
from drake_car.results.columns import folder_readme
from drake_car.results.files import write_text
from drake_car.results.lock import LockHeld, exclusive, holder
from drake_car.results.signals import signals_held, terminate_as_exit


class OutputError(InputError):
    """The output folder cannot be used; the message names it and why."""


MARKER = ".drake_car_output"  # in every folder this module wrote, listing what it wrote
_MARKER_TEXT = "written by drake_car; replaced whole by the next run that writes here\n"
_LISTED = "its files and folders (anything else here stops that replacement):"


# The names made beside --out: ".NAME.partial-PID-HEX8-old-HEX8" is the longest.
_BESIDE_BYTES = len(".partial--old-") + 2 * 8 + 1 + 10


def check_output_target(out_dir):
    """Refuses an output target that cannot be written as a whole, before any work: a file, a
    foreign non-empty folder, a dangling symbolic link, a name too long for the folder it is
    in (with the temporary names made beside it), an unwritable place, a place inside or
    around another run's folder in progress (its lock held), a name that is not UTF-8."""
    out_dir = Path(out_dir)
    try:  # the output's files name their folder (README, provenance) in UTF-8 text
        os.fsencode(out_dir).decode("utf-8")
    except UnicodeDecodeError as e:
        shown = repr(os.fsencode(out_dir))[2:-1]  # its bytes, the odd one as \\xNN
        raise OutputError(f"--out {shown}: byte {e.start} of the name is not UTF-8; the "
                          "output's files name their folder in UTF-8 text: choose a UTF-8 "
                          "name") from None
    if out_dir.is_symlink() and not out_dir.exists():
        raise OutputError(f"--out {out_dir}: a dangling symbolic link (to "
                          f"{os.readlink(out_dir)}); remove it or choose another folder")
    if out_dir.is_file() or (out_dir.exists() and not out_dir.is_dir()):
        raise OutputError(f"--out {out_dir}: is a file, not a folder")
    if is_mount_point(out_dir):
        raise OutputError(f"--out {out_dir}: a mount point (a file system's root, which cannot "
                          "be renamed, and an output is replaced whole by a rename); give a "
                          f"folder inside it, e.g. --out {out_dir / 'results'}")
    if out_dir.is_dir() and any(out_dir.iterdir()) and not (out_dir / MARKER).is_file():
        raise OutputError(f"--out {out_dir}: exists, is not empty and was not written by "
                          "drake_car; choose a new or empty folder (it would be replaced whole)")
    parent = out_dir.parent
    probe = parent
    while not probe.exists():
        probe = probe.parent
    if not probe.is_dir() or not os.access(probe, os.W_OK | os.X_OK):
        raise OutputError(f"--out {out_dir}: {probe} is not a writable folder")
    check_writable(out_dir, probe)
    try:
        name_max = os.pathconf(probe, "PC_NAME_MAX")
    except (OSError, ValueError):
        name_max = 255
    for part in out_dir.absolute().relative_to(probe.absolute()).parts:
        if len(os.fsencode(part)) + _BESIDE_BYTES > name_max:
            raise OutputError(f"--out {out_dir}: the name {excerpt(part)} is "
                              f"{len(os.fsencode(part))} bytes; names here are limited to "
                              f"{name_max} bytes, {name_max - _BESIDE_BYTES} for an output "
                              "folder (its temporary names are longer)")
    check_no_run_in_progress(out_dir)
    check_only_its_own(out_dir)


def is_mount_point(path):
    """Whether ``path`` is a mount point: another file system's root (``os.path.ismount``) or
    a bind mount of a folder of the same one (listed in /proc/self/mountinfo, Linux)."""
    path = Path(path)
    if not path.is_dir() or path.is_symlink():
        return False
    if os.path.ismount(path):
        return True
    try:
        lines = Path("/proc/self/mountinfo").read_text().splitlines()
    except OSError:
        return False
    where = os.path.realpath(path)
    # field 5 is the mount point, with space, tab, newline and backslash escaped in octal
    points = {re.sub(r"\\([0-7]{3})", lambda m: chr(int(m.group(1), 8)), line.split(" ")[4])
              for line in lines if len(line.split(" ")) > 4}
    return where in points


def written_by_it(out_dir):
    """The paths (relative, POSIX, a folder's ending in "/") the output in ``out_dir`` listed in
    its MARKER as its own, or None when its MARKER lists none (written before the list was
    kept)."""
    try:
        lines = (Path(out_dir) / MARKER).read_text(errors="replace").splitlines()
    except OSError:
        return None
    if len(lines) < 2 or lines[1] != _LISTED:
        return None
    listed = set()
    for line in lines[2:]:
        with contextlib.suppress(ValueError):
            listed.add(json.loads(line))
    return listed


def _kind(path):
    """What ``path`` (in an old output, not its own) is, for the message."""
    if path.is_dir() and not path.is_symlink():
        if (path / MARKER).is_file():
            return "another drake_car output"
        if any((path / name).is_file() for name in ("sweep.json", "index.csv")):
            return "a sweep folder"
    if path.name.startswith(".") and path.name.endswith(".lock"):
        return "another run's lock file"
    if path.name.startswith(".") and ".partial-" in path.name:
        return "another output's unfinished temporary folder"
    return None


def check_only_its_own(out_dir):
    """An old output at ``out_dir`` is replaced whole, and anything in it with it: refused,
    naming the first, when it holds what it did not write (another drake_car output, a sweep
    folder, a lock file, a user's file or folder). An output written before its MARKER listed
    its files is checked for those that can be told (outputs, sweeps, locks, temporary
    folders)."""
    out_dir = Path(out_dir)
    if out_dir.is_symlink() or not (out_dir / MARKER).is_file():
        return
    own = written_by_it(out_dir)
    for folder, dirs, files in os.walk(out_dir):
        dirs.sort()
        for name in sorted(files) + list(dirs):
            path = Path(folder) / name
            rel = path.relative_to(out_dir).as_posix()
            if own is None:
                kind = _kind(path)
            elif (rel + "/" if name in dirs else rel) in own:
                kind = None
            else:
                kind = _kind(path) or ("a folder" if name in dirs else "a file") + \
                    " the previous output did not write"
            if kind is not None:
                raise OutputError(f"--out {out_dir}: the previous output there holds {rel} "
                                  f"({kind}), which replacing it would delete; move that out "
                                  "of it, or give another --out")
        dirs[:] = [d for d in dirs if not (Path(folder) / d).is_symlink()]


def _listing(staging):
    """The MARKER's text for the output being finished in ``staging``: every path in it."""
    paths = [MARKER]
    for folder, dirs, files in os.walk(staging):
        for name in dirs + files:
            path = Path(folder) / name
            rel = path.relative_to(staging).as_posix()
            paths.append(rel + "/" if name in dirs else rel)
    return _MARKER_TEXT + _LISTED + "\n" + "".join(
        json.dumps(p) + "\n" for p in sorted(set(paths)))


def check_apart(out, other, option):
    """``other`` (a folder another option names, e.g. --runs_dir, kept and added to) neither
    is --out, nor inside it, nor holds it: --out is replaced whole and would delete it."""
    if other is None or out is None:
        return
    a, b = Path(os.path.realpath(out)), Path(os.path.realpath(other))
    if b.is_relative_to(a) or a.is_relative_to(b):
        where = "is" if a == b else "is inside" if b.is_relative_to(a) else "holds"
        raise OutputError(f"{option} {other} {where} --out {out}; --out is replaced whole and "
                          f"{option} is kept: give folders apart, e.g. {option} "
                          f"{Path(out).parent / (Path(out).name + '_runs')}")


def check_output_file(out):
    """Refuses, before any work, an --out FILE that cannot be written: an existing folder (a
    file's path is wanted), something else that is not a file, a dangling symbolic link, a
    place whose nearest existing folder cannot be written in."""
    out = Path(out)
    if out.is_symlink() and not out.exists():
        raise OutputError(f"--out {out}: a dangling symbolic link (to {os.readlink(out)}); "
                          "remove it or choose another file")
    if out.is_dir():
        raise OutputError(f"--out {out}: is a folder; give a file's path, e.g. --out "
                          f"{out / 'calibration.json'}")
    if out.exists() and not out.is_file():
        raise OutputError(f"--out {out}: exists and is not a file")
    probe = out.parent
    while not probe.exists():
        probe = probe.parent
    if not probe.is_dir() or not os.access(probe, os.W_OK | os.X_OK):
        raise OutputError(f"--out {out}: {probe} is not a folder you can write in")
    check_writable(out, probe)


def check_writable(out_dir, folder):
    """Makes a file in ``folder``, where the output's lock and temporary folder go, and lets it
    go: ``os.access`` says yes to root in /sys or /proc, whose first file would fail only after
    the work. An unnamed file (O_TMPFILE: the folder is not changed, not even its time) where
    the file system makes one; else a named file, removed at once (sysfs and procfs, which make
    neither, refuse it)."""
    try:
        try:
            os.close(os.open(folder, os.O_TMPFILE | os.O_WRONLY, 0o600))
        except (AttributeError, OSError) as e:  # no O_TMPFILE here (not Linux, or this mount)
            if isinstance(e, OSError) and e.errno not in (errno.EOPNOTSUPP, errno.EISDIR):
                raise
            fd, name = tempfile.mkstemp(prefix=".drake_car-probe-", dir=folder)
            os.close(fd)
            os.unlink(name)
    except OSError as e:
        raise OutputError(f"--out {out_dir}: cannot write in {folder} ({e.strerror or e}); "
                          "choose a folder you can write in") from None


def check_no_run_in_progress(out_dir):
    """Another run writing a folder that holds ``out_dir`` (it would replace it, and ours with
    it) or a folder inside ``out_dir`` (ours would replace it) is refused, naming it."""
    out_dir = Path(out_dir).absolute()
    for folder in [out_dir, *out_dir.parents][1:]:
        owner = holder(folder.parent / f".{folder.name}.lock") if folder.name else None
        if owner is not None and owner != os.getpid():
            raise OutputError(f"--out {out_dir}: inside {folder}, which another run (pid "
                              f"{owner if owner > 0 else 'unknown'}) is writing and will "
                              "replace whole; wait for it or choose another folder")
    if out_dir.is_dir() and not out_dir.is_symlink():
        for lock in out_dir.rglob(".*.lock"):
            owner = holder(lock)
            if owner is not None and owner != os.getpid():
                inner = lock.parent / lock.name[1:-len(".lock")]
                raise OutputError(f"--out {out_dir}: holds {inner}, which another run (pid "
                                  f"{owner if owner > 0 else 'unknown'}) is writing; wait for "
                                  "it or choose another folder")


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
def study_lock(out, what):
    """Held while a study command (``what``, e.g. "design study") works in its folder ``out``,
    one that is added to (its sweep's runs) and whose results are rewritten: a second one on
    the same folder is refused at once (OutputError), not left to mix its files with the
    first's. The lock file lies beside ``out`` and goes with the lock."""
    out = Path(out).absolute()
    with _os_errors_named(out, out.parent):
        out.parent.mkdir(parents=True, exist_ok=True)
    with folder_lock(out.parent / f".{out.name}.study.lock", out, what=what):
        yield


@contextlib.contextmanager
def output_folder(out_dir):
    """Yields a temporary folder beside ``out_dir``; on success it replaces ``out_dir`` whole;
    on any error (or SIGINT/SIGTERM) it is removed and ``out_dir`` is left as it was. A
    symbolic link as ``out_dir`` is followed once: the folder it names is replaced, the link
    kept. An OS error on the output's files (a full disk, a refused rename) is an OutputError
    naming the path and the reason."""
    out_dir = Path(out_dir).absolute()
    check_output_target(out_dir)
    if out_dir.is_symlink():
        out_dir = out_dir.resolve()
        check_output_target(out_dir)
    parent, name = out_dir.parent, out_dir.name
    with _os_errors_named(out_dir, parent):
        parent.mkdir(parents=True, exist_ok=True)
    with terminate_as_exit(), _os_errors_named(out_dir, parent), \
            folder_lock(parent / f".{name}.lock", out_dir):
        check_no_run_in_progress(out_dir)  # again, holding our lock: no race with a new one
        for stale in parent.glob(f".{name}.partial-*"):  # killed runs': we hold the lock
            _remove(stale)
        staging = parent / f".{name}.partial-{os.getpid()}-{uuid.uuid4().hex[:8]}"
        try:
            with _os_errors_named(out_dir, parent):
                staging.mkdir()
                write_text(staging / MARKER, _MARKER_TEXT)
            with _os_errors_named(out_dir, parent):
                yield staging
            if not (staging / "README.md").exists():  # what the columns mean
                write_text(staging / "README.md", folder_readme(staging, out_dir.name))
            write_text(staging / MARKER, _listing(staging))
            try:
                check_output_target(out_dir)  # still a folder we may replace
            except OutputError as refused:  # something came into it during the run: the
                kept = _kept_beside(staging, parent, name)  # finished output is not lost
                raise OutputError(f"{refused}; this run's output is kept in {kept}") from None
            with _os_errors_named(out_dir, parent), signals_held():  # both renames or none
                old = None
                if out_dir.exists():
                    old = parent / f".{name}.partial-{os.getpid()}-old-{uuid.uuid4().hex[:8]}"
                    out_dir.rename(old)
                try:
                    staging.rename(out_dir)
                except OSError:
                    if old is not None:
                        old.rename(out_dir)  # put the previous output back
                    raise
            if old is not None:
                _remove(old)
        finally:
            if staging.exists():
                _remove(staging)


def _kept_beside(staging, parent, name):
    """A finished output that may not replace its folder, renamed to a visible name beside
    it (``NAME.kept-N``); returns that path."""
    for n in range(1, 1000):
        kept = parent / f"{name}.kept-{n}"
        if not kept.exists():
            staging.rename(kept)
            return kept
    raise OutputError(f"{parent / name}: 999 kept outputs beside it; remove them")


def _remove(path):
    if path.is_symlink() or not path.is_dir():
        with contextlib.suppress(OSError):
            path.unlink()
    else:
        shutil.rmtree(path, ignore_errors=True)


def _ours(path, out_dir, parent):
    """``path`` is the output, in it, one of its temporary names, or a folder above them."""
    if parent.is_relative_to(path) or path.is_relative_to(out_dir):
        return True
    return path.is_relative_to(parent) and path.relative_to(parent).parts[0].startswith(
        f".{out_dir.name}.")


# OS errors that a write raises with no path (the file's write or close, not its open): the
# disk is full, a quota is reached, a file grows past its limit, the disk is read-only or
# failing. Inside an output's writing they are the output's.
WRITE_ERRNOS = (errno.ENOSPC, errno.EDQUOT, errno.EFBIG, errno.EROFS, errno.EIO)


def os_error_reason(error, out_dir, parent=None):
    """"path: reason" of OSError ``error`` when it is about the output ``out_dir`` (a path
    under it, or one of its temporary names beside it, in ``parent``; or no path and an
    errno of a write, ``WRITE_ERRNOS``), else None."""
    out_dir = Path(out_dir).absolute()
    parent = out_dir.parent if parent is None else parent
    where = next((Path(os.fsdecode(f)) for f in (error.filename, error.filename2)
                  if f is not None), None)
    reason = error.strerror or str(error)
    if where is None:
        return f"{reason} (writing it)" if error.errno in WRITE_ERRNOS else None
    if not _ours(where.absolute(), out_dir, parent):
        return None
    return f"{where}: {reason}"


@contextlib.contextmanager
def _os_errors_named(out_dir, parent):
    """An OSError about the output (``os_error_reason``) becomes an OutputError naming --out,
    the path and the reason; others pass unchanged."""
    try:
        yield
    except OSError as e:
        reason = os_error_reason(e, out_dir, parent)
        if reason is None:
            raise
        raise OutputError(f"--out {out_dir}: {reason}") from None
