"""The Dask cluster every distributed command runs on: one place for how a client is made.

``atlas``, ``prove --atlas`` and ``verify`` take ``--workers K`` (a ``LocalCluster`` of ``K``
single-threaded worker processes, started here and closed after) or ``--scheduler
tcp://HOST:PORT`` (a running cluster: ``dask scheduler`` / ``dask worker`` by hand, or
``dask-jobqueue``, see the README).  Worker processes, not threads: the engines' work holds the
GIL in places and python-flint's precision is process-wide.  A scheduler that cannot be reached
within ``CONNECT_TIMEOUT`` is a ``ValueError`` naming the address (the commands exit 2), never a
hang.
"""
from __future__ import annotations

import contextlib
import logging
import time


class ClusterError(ValueError):
    """No cluster to run on: dask.distributed missing, or the scheduler unreachable (exit 2)."""


#: how long to try to reach a scheduler given by ``--scheduler``
CONNECT_TIMEOUT = "20s"
#: the bound on ``--workers`` (a local cluster larger than this is a typo)
MAX_WORKERS = 256


def check_workers(workers) -> int:
    """``workers`` as the number of local worker processes, or a ``ValueError``/``TypeError``."""
    if isinstance(workers, bool) or not isinstance(workers, int):
        raise TypeError(f"workers must be an int in [1, {MAX_WORKERS}], got {workers!r}")
    if not 1 <= workers <= MAX_WORKERS:
        raise ValueError(f"workers must be an int in [1, {MAX_WORKERS}], got {workers!r}")
    return workers


@contextlib.contextmanager
def client(scheduler=None, workers=2, *, given=None):
    """A ``distributed.Client``: ``given`` as it is (not closed here), else one on ``scheduler``,
    else one on a new ``LocalCluster(n_workers=workers, threads_per_worker=1)``; the ones made
    here are closed on exit."""
    if given is not None:
        yield given
        return
    try:
        from distributed import Client, LocalCluster
    except ModuleNotFoundError as exc:
        raise ClusterError("this command runs on dask.distributed: python -m pip install -e '.[atlas]'") from exc
    if scheduler:
        try:
            own = Client(scheduler, timeout=CONNECT_TIMEOUT)
        except (OSError, TimeoutError) as exc:
            raise ClusterError(f"cannot reach the dask scheduler at {scheduler!r} within "
                             f"{CONNECT_TIMEOUT} ({type(exc).__name__}: {exc})") from None
        with own:
            yield own
        return
    with LocalCluster(n_workers=check_workers(workers), threads_per_worker=1, processes=True,
                      dashboard_address=":0", silence_logs=logging.ERROR) as cluster, Client(cluster) as own:
        yield own


def as_done(futures, weights=None):
    """Yield ``(n, future, eta)`` as ``futures`` complete (any order): ``n`` the count so far,
    ``eta`` the seconds still to go at the rate so far, by ``weights`` (``{future: work}``, e.g.
    points) or one per future."""
    from distributed import as_completed

    futures = list(futures)
    weights = weights or dict.fromkeys(futures, 1)
    total, finished, t0 = sum(weights.values()), 0, time.perf_counter()
    for n, fut in enumerate(as_completed(futures), 1):
        finished += weights[fut]
        yield n, fut, (total - finished) * max(time.perf_counter() - t0, 1e-9) / max(finished, 1)
