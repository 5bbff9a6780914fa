"""Signals around what must not be cut short: SIGTERM as an exit (so ``finally`` blocks clean
up as on Ctrl-C), and SIGINT/SIGTERM held for a few renames that belong together."""

import contextlib
import signal


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
def signals_held():
    """SIGINT and SIGTERM held for a few renames that belong together (a set of files is not
    left half old, half new): one that comes meanwhile is noted and raised again as the block
    ends, meeting the handler it would have met. (Blocking the signal with pthread_sigmask
    would not do: another thread takes it and Python raises it in this one all the same.)"""
    caught = []
    try:
        previous = {s: signal.signal(s, lambda signum, frame: caught.append(signum))
                    for s in (signal.SIGINT, signal.SIGTERM)}
    except ValueError:  # not the main thread: its signals cannot reach this code
        yield
        return
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)
        if caught:
            signal.raise_signal(caught[0])
