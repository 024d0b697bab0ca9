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
#: Dask settings of the local clusters made here.  Dask's statistical profiler is off: in every
#: worker it samples the running task's stack every 10 ms (and the event loop's), for the
#: dashboard's profile page, which these commands never serve, and the sampling thread takes the
#: GIL from the task each time.  Issue 33, the issue's first scene (``F=1 f=0.15 omega=1.7 l=-0.4
#: r=0.9 wavenumber=1.3``) on a loaded 2-core machine: its period-2 orbits task in a one-worker
#: cluster took 5.94 CPU s with the profiler and 5.55 without (means of six runs each, alternating;
#: 4.90 in a plain process), and a whole ``verify`` 55.5 and 51.3 CPU s (means of three).  A
#: cluster given by ``--scheduler`` keeps its own settings (``DASK_DISTRIBUTED__WORKER__PROFILE__ENABLED
#: =False`` in the workers' environment does the same there).
#:
#: Dask's other clocks of a local cluster tick slower here: the event loops' watchdog (``admin.tick``,
#: 20 ms: a warning when a loop was blocked), the memory monitor (``worker.memory.monitor-interval``,
#: 100 ms: pause, spill or restart a worker near its memory limit; a second is soon enough for
#: these tasks, whose memory grows slowly) and the dashboard's system monitor (500 ms).  Each wakes
#: a thread that takes the GIL, in the worker (whose process time is what ``verify`` counts as a
#: task's CPU) and in the caller (the scheduler and the client).  Issue 33, a one-worker cluster, a
#: task that sleeps 15 s, three runs: the worker spent 0.44 to 0.52 CPU s with Dask's clocks and
#: 0.07 with these (~3% of a task's wall time, then 0.5%), and the caller 1.7 to 2.0 against 1.1
#: to 1.2 for the whole run; the tick alone was 0.28 of the worker's.
#:
#: The workers start from a fork server (``multiprocessing``'s ``forkserver``) that has imported
#: ``PRELOAD`` and the caller's modules once, instead of each one a fresh interpreter (Dask's
#: ``spawn``) that imports them again (``_forked_workers``), where the platform has one; on Linux,
#: from a one-thread caller, that server is a fork of the caller (``_fork_server``).
LOCAL_CONFIG = {"distributed.worker.profile.enabled": False,
                "distributed.admin.tick.interval": "1s",
                "distributed.worker.memory.monitor-interval": "1s",
                "distributed.admin.system-monitor.interval": "10s"}
#: what the fork server of a local cluster imports for every command (the caller adds its own)
PRELOAD = ("distributed", "numpy", "mpmath", "flint", "fast", "reference")
#: the local clusters open now (``_forked_workers``): the fork server is theirs until the last closes
_ACTIVE = 0


def check_workers(workers) -> int:
    """``workers`` as the number of local worker processes, or a ``ValueError``/``TypeError``."""
    if isinstance(workers, bool) or not isinstance(workers, int):
        raise TypeError(f"workers must be an int in [1, {MAX_WORKERS}], got {workers!r}")
    if not 1 <= workers <= MAX_WORKERS:
        raise ValueError(f"workers must be an int in [1, {MAX_WORKERS}], got {workers!r}")
    return workers


@contextlib.contextmanager
def client(scheduler=None, workers=2, *, given=None, preload=()):
    """A ``distributed.Client``: ``given`` as it is (not closed here), else one on ``scheduler``,
    else one on a new ``LocalCluster(n_workers=workers, threads_per_worker=1)`` with the settings
    ``LOCAL_CONFIG``, its workers forked from a server that has imported ``PRELOAD`` and the
    modules ``preload`` (``_forked_workers``); the ones made here are closed on exit."""
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
    import dask

    n = check_workers(workers)
    with _forked_workers(preload) as start:
        with dask.config.set({**LOCAL_CONFIG, **start}):    # the workers take it at their start; nothing else here
            local = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0",
                                 silence_logs=logging.ERROR)
        with local, Client(local) as own:
            yield own


@contextlib.contextmanager
def _forked_workers(preload=()):
    """Start the local workers from one fork server that imports ``PRELOAD + preload`` once;
    stop it (and reap it) on exit.  Yields the Dask setting that says so, or ``{}`` on a
    platform without a fork server (Windows: Dask's ``spawn`` then, as before).

    Why: a worker that Dask spawns is a fresh interpreter, which imports Dask (~0.8 CPU s) and
    then, at its first task, the engines and the rooms (~1.5 to 2 CPU s: numba's LLVM binding,
    scipy, python-flint); a forked one has them already.  Issue 33, a cluster of two workers that
    run one task importing ``verify``'s rooms (machine-wide busy CPU, ``/proc/stat``, one run each):
    9.2 CPU s with ``spawn``, 4.1 with the fork server; one worker 5.7 and 4.1.  The server itself
    is a fork of the caller where that is safe (``_fork_server``): a ``verify --quick`` of the
    issue's first scene spent 6.1 and 6.1 CPU s besides its tasks with a spawned server, 3.7 and
    3.4 with a forked one (two runs each, alternating; the same report but for its times).

    Stopping the server here (``multiprocessing.forkserver``'s own stop, which waits for it) is
    what makes its CPU and its workers' count in the caller's ``getrusage(RUSAGE_CHILDREN)``: the
    server reaps each worker as it exits (the cluster has closed them all by then), and the
    caller reaps the server.  An interpreter without that stop leaves the server to exit with the
    caller, unreaped: the work is the same, only the caller's account of it misses the workers.
    Dask's own preload list (set once, on first use) would import ``pandas`` into the caller as
    well; the flag that says it is set is set here instead.  Clusters made while another is open
    (a test's inside a module's) share its server, which stops with the last of them."""
    import multiprocessing

    if "forkserver" not in multiprocessing.get_all_start_methods():
        yield {}
        return
    from multiprocessing import forkserver

    from distributed import utils

    global _ACTIVE
    stop = getattr(forkserver._forkserver, "_stop", None)
    if _ACTIVE == 0:
        if stop is not None:
            stop()                       # a server from before would not have this preload
        multiprocessing.get_context("forkserver").set_forkserver_preload([*PRELOAD, *preload])
        utils._forkserver_preload_set = True
        _fork_server([*PRELOAD, *preload])
    _ACTIVE += 1
    try:
        yield {"distributed.worker.multiprocessing-method": "forkserver"}
    finally:
        _ACTIVE -= 1
        if _ACTIVE == 0 and stop is not None:
            stop()


def _fork_server(preload) -> bool:
    """Start ``multiprocessing``'s fork server as a fork of this process, which has imported the
    engines and the rooms already, rather than as a fresh interpreter that imports ``preload``
    again; ``True`` if it did.  The server then imports what of ``preload`` this process lacks,
    and the workers are forked from it as before.

    Why: the spawned server's imports were ~2.5 of the ~6.7 CPU s that a ``verify`` run spent
    besides its tasks (issue 33), and the caller had made the same imports already.

    Only where that is safe and the protocol is the one known here: Linux (no Objective-C runtime
    to trip over a fork), one thread in this process (a fork copies no other thread, nor the locks
    they might hold: the commands make their cluster before any thread starts; a test run may not
    have one), no server running, and ``multiprocessing.forkserver`` as in Python 3.11 to 3.13
    (3.14's server takes an authentication key).  Elsewhere ``False``, and the server is spawned as
    before.  The workers then share the caller's hash seed (each other's, as Dask's fixed one
    made them)."""
    import os
    import socket
    import sys
    import threading
    from multiprocessing import connection, forkserver, resource_tracker, util

    fs = forkserver._forkserver
    known = all(hasattr(fs, a) for a in ("_forkserver_address", "_forkserver_alive_fd", "_forkserver_pid", "_stop"))
    if (not sys.platform.startswith("linux") or threading.active_count() != 1 or not known
            or hasattr(fs, "_forkserver_authkey") or fs._forkserver_pid is not None):
        return False
    resource_tracker.ensure_running()    # as ``ensure_running`` does: the workers are handed its fd
    with socket.socket(socket.AF_UNIX) as listener:
        address = connection.arbitrary_address("AF_UNIX")
        listener.bind(address)
        if not util.is_abstract_socket_namespace(address):
            os.chmod(address, 0o600)
        listener.listen()
        alive_r, alive_w = os.pipe()     # the server stops when the write end closes (``_stop``)
        try:
            pid = os.fork()
        except OSError:                  # no process to spare: spawned as before, or refused there
            os.close(alive_r), os.close(alive_w)
            return False
        if pid == 0:                     # the server: it never returns here
            code = 1
            try:
                os.close(alive_w)
                _fresh_state()
                forkserver.main(listener.fileno(), alive_r, list(preload))
            except SystemExit as exc:    # its way out once no client is left
                code = exc.code if isinstance(exc.code, int) else 0
            finally:
                os._exit(code)
        os.close(alive_r)
    fs._forkserver_address, fs._forkserver_alive_fd, fs._forkserver_pid = address, alive_w, pid
    return True


def _fresh_state():
    """What a fresh interpreter would have, in a server forked from the caller (``_fork_server``),
    which would otherwise hand its workers whatever the caller had set: mpmath's and
    python-flint's process-wide precisions at their defaults, and the signal handlers at
    Python's (a handler the caller installed, e.g. one that cleans up its files on SIGTERM,
    would run in a worker that Dask stops)."""
    import signal
    import sys

    if "mpmath" in sys.modules:
        sys.modules["mpmath"].mp.prec = 53
    if "flint" in sys.modules:
        sys.modules["flint"].ctx.default()
    for sig in signal.valid_signals():
        handler = signal.getsignal(sig)
        if callable(handler) and handler is not signal.default_int_handler:
            signal.signal(sig, signal.default_int_handler if sig == signal.SIGINT else signal.SIG_DFL)


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
