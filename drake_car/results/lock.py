"""The one lock of the project: a kernel lock (``fcntl.flock``) on a lock file, taken without
waiting. The kernel releases it when its process ends, however it ends, so a killed writer
leaves no lock behind and there is no process id to check for reuse. The lock file holds the
owner's process id (for the message a second writer gets) and is removed on release; a file
left by a killed process is free and taken over."""

import contextlib
import fcntl
import os
from pathlib import Path


class LockHeld(Exception):
    """Another process holds the lock; ``owner`` is its process id (None if unknown)."""

    def __init__(self, path, owner):
        self.path, self.owner = path, owner
        super().__init__(f"{path} is held by process {owner or 'unknown'}")


def _owner(fd):
    with contextlib.suppress(OSError, ValueError):
        return int(os.pread(fd, 32, 0).decode().strip() or "0") or None
    return None


def _same_file(fd, path):
    """Whether ``path`` still names the file open as ``fd`` (not removed or replaced)."""
    try:
        here, there = os.fstat(fd), os.stat(path)
    except FileNotFoundError:
        return False
    return (here.st_dev, here.st_ino) == (there.st_dev, there.st_ino)


@contextlib.contextmanager
def exclusive(path):
    """Holds the lock of ``path`` while the block runs; raises ``LockHeld`` at once if another
    process holds it."""
    path = Path(path)
    while True:
        fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            owner = _owner(fd)
            os.close(fd)
            raise LockHeld(path, owner) from None
        if _same_file(fd, path):
            break
        os.close(fd)  # its holder removed it as we opened it: take the new one
    try:
        os.ftruncate(fd, 0)
        os.pwrite(fd, str(os.getpid()).encode(), 0)
        yield
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(path)  # still ours: nobody else can hold it
        os.close(fd)


def holder(path):
    """The process id holding ``path``'s lock (-1 if it cannot be read), or None when it is
    free or missing."""
    path = Path(path)
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:
        return None
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
        except BlockingIOError:
            return _owner(fd) or -1
        return None
    finally:
        os.close(fd)
