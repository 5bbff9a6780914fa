"""The Dask cluster a sweep runs on (``sweep.runner``), and how it stops when interrupted.

``local_cluster``: one single-threaded worker process per core, its scheduler, nannies, workers
and dashboards on 127.0.0.1 only. ``dask_client``: a Client of it, or of a running cluster by
its scheduler's address.

Ctrl-C in a terminal reaches the whole process group, the workers too. A worker process
ignores SIGINT (``dask_setup``, Dask's preload hook, run as each worker starts, a restarted one
too; a command's workers ignore it from their first import, ``drake_car.commands``): the
parent, interrupted, shuts them down. The parent's Dask loggers are quiet while it does (a
worker still running a simulation is killed after Dask's grace period, which Dask announces),
and so is each worker's notice of the runs cancelled as it closes: an interrupt is the
command's one line (``commands.cli.run_main``), not Dask's messages. Ctrl-C while the local
cluster starts is held until it is up (one interrupted half started cannot be closed).
"""

import contextlib
import logging
import os
import signal
import threading

from drake_car.sweep.scheduler import CONNECT_TIMEOUT_S, check_scheduler

LOOPBACK = "127.0.0.1"
# Dask's own loggers in the parent, silenced while an interrupted cluster shuts down.
DASK_LOGGERS = ("distributed", "tornado", "asyncio")
# A worker's notice, as it closes, of each task it was running ("Async instruction for <Task
# ...> ended with CancelledError": Dask's worker_state_machine logs it only in Worker.close).
CANCELLED_AT_CLOSE = "ended with CancelledError"


def cores():
    """The cores this process may run on."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()


def local_cluster(workers=None, **kwargs):
    """A LocalCluster of ``workers`` single-threaded worker processes (default: one per core),
    everything listening on 127.0.0.1 (Dask's dashboard would take every interface); each
    worker set up by ``dask_setup``."""
    from distributed import LocalCluster
    return LocalCluster(n_workers=workers or cores(), threads_per_worker=1, processes=True,
                        host=LOOPBACK, dashboard_address=f"{LOOPBACK}:0",
                        preload=[__name__], **kwargs)


@contextlib.contextmanager
def dask_client(scheduler=None, workers=None):
    """A Client of the cluster at ``scheduler`` (left running) or of a ``local_cluster`` of
    ``workers`` started here and closed on exit. An unreachable scheduler raises OSError.
    Left by an exception (Ctrl-C, a full disk), Dask's loggers are quiet while it closes."""
    from distributed import Client
    with _levels_restored():
        if scheduler:
            check_scheduler(scheduler)
            with Client(scheduler, timeout=CONNECT_TIMEOUT_S, set_as_default=False) as client:
                with _quiet_if_left_by_error():
                    yield client
            return
        with _started(workers) as cluster, Client(cluster, set_as_default=False) as client:
            with _quiet_if_left_by_error():
                yield client


def _started(workers):
    """A ``local_cluster``, Ctrl-C held while it starts and raised once it is up (it is then
    closed): a cluster interrupted half started cannot be closed (Dask's exit handler fails
    with a traceback)."""
    held = []
    hold = (threading.current_thread() is threading.main_thread()
            and signal.getsignal(signal.SIGINT) is signal.default_int_handler)
    if hold:
        signal.signal(signal.SIGINT, lambda signum, frame: held.append(signum))
    try:
        cluster = local_cluster(workers)
    finally:
        if hold:
            signal.signal(signal.SIGINT, signal.default_int_handler)
    if held:
        _quiet()
        cluster.close()
        raise KeyboardInterrupt
    return cluster


def _quiet():
    for name in DASK_LOGGERS:
        logging.getLogger(name).setLevel(logging.CRITICAL + 1)


@contextlib.contextmanager
def _quiet_if_left_by_error():
    try:
        yield
    except BaseException:
        _quiet()
        raise


@contextlib.contextmanager
def _levels_restored():
    loggers = [logging.getLogger(name) for name in DASK_LOGGERS]
    levels = [logger.level for logger in loggers]
    try:
        yield
    finally:
        for logger, level in zip(loggers, levels):
            logger.setLevel(level)


class _NotAtClose(logging.Filter):
    def filter(self, record):
        return CANCELLED_AT_CLOSE not in record.getMessage()


def dask_setup(worker):
    """Dask's preload hook, in each worker process of a ``local_cluster`` as it starts: SIGINT
    ignored (the parent shuts the worker down), the notices of runs cancelled at close left
    out."""
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    logging.getLogger("distributed.worker.state_machine").addFilter(_NotAtClose())
