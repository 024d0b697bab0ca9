"""The local clusters' fork server (``cross_check.cluster._forked_workers``): the workers have the
preload, and their CPU counts in the caller's.  A module of its own: no cluster may be open
around these tests (a cluster made inside another shares that one's server)."""
import pytest

from cross_check import cluster

pytest.importorskip("distributed", reason="the cluster needs the atlas extra (dask.distributed)")


def _seen(module):
    """What a worker has: ``module`` imported, the hash seed, and its parent's pid."""
    import os
    import sys

    return module in sys.modules, os.environ.get("PYTHONHASHSEED"), os.getppid()


def _burn(seconds):
    """Spin on the CPU for ``seconds`` of this process's CPU time."""
    import time

    t0 = time.process_time()
    while time.process_time() - t0 < seconds:
        pass
    return time.process_time() - t0


def test_local_workers_are_forked_from_one_server_that_has_the_preload():
    """``_forked_workers``: both workers have the caller's ``preload`` before any task imports it
    (a module nothing else here imports), share one parent (the fork server, not the caller) and
    Dask's fixed hash seed; a cluster without it in ``preload`` lacks it (the check can fail)."""
    import os

    module = "xml.dom.minidom"
    with cluster.client(workers=2, preload=(module,)) as c:
        seen = set(c.run(_seen, module).values())
    assert len(seen) == 1
    has, seed, parent = seen.pop()
    assert has and seed == "6640" and parent != os.getpid()
    with cluster.client(workers=1) as c:
        assert [has for has, _, _ in c.run(_seen, module).values()] == [False]


def test_the_workers_cpu_counts_in_the_callers_children_once_the_cluster_closes():
    """The fork server is stopped and reaped on exit, after it reaped the workers: a task's CPU in
    a worker shows in the caller's ``getrusage(RUSAGE_CHILDREN)``, as it did with ``spawn``.  A
    cluster that leaves its server running would show none of it (the check can fail)."""
    import resource

    def children():
        r = resource.getrusage(resource.RUSAGE_CHILDREN)
        return r.ru_utime + r.ru_stime

    before = children()
    with cluster.client(workers=1) as c:
        burnt = c.submit(_burn, 1.0, pure=False).result()
    assert burnt >= 1.0
    assert children() - before >= burnt


def test_without_a_fork_server_the_workers_are_spawned_as_before(monkeypatch):
    """A platform without ``forkserver`` (Windows) gets Dask's ``spawn``: the workers are the
    caller's own children and import the preload themselves, at their first task."""
    import multiprocessing
    import os

    monkeypatch.setattr(multiprocessing, "get_all_start_methods", lambda: ["spawn"])
    module = "xml.dom.minidom"
    with cluster.client(workers=1, preload=(module,)) as c:
        [(has, seed, parent)] = c.run(_seen, module).values()
    assert parent == os.getpid() and not has and seed == "6640"


#: run in a fresh interpreter (one thread, as the commands are when they make their cluster): the
#: workers of a cluster made there, then of one made with a second thread running
_FORKED_FROM_CALLER = r"""
import os, resource, sys, threading, types
from cross_check import cluster

def seen():
    import os, signal, sys
    import flint, mpmath
    return ("_made_by_the_caller" in sys.modules, hash("abc"), os.getppid(), mpmath.mp.prec, flint.ctx.prec,
            signal.getsignal(signal.SIGTERM) == signal.SIG_DFL)

def burn(seconds):
    import time
    t0 = time.process_time()
    while time.process_time() - t0 < seconds:
        pass
    return time.process_time() - t0

def children():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime

sys.modules["_made_by_the_caller"] = types.ModuleType("_made_by_the_caller")
import flint, mpmath
mpmath.mp.prec, flint.ctx.prec = 200, 300         # the caller's; a fresh interpreter's are 53
import signal
signal.signal(signal.SIGTERM, lambda *_: None)     # the caller's; a fresh interpreter has none
before = children()
with cluster.client(workers=2) as c:
    forked = sorted(c.run(seen).values())
    burnt = c.submit(burn, 1.0, pure=False).result()
print("forked", forked, hash("abc"), os.getpid(), burnt, children() - before)
stop = threading.Event()
waiter = threading.Thread(target=stop.wait)
waiter.start()
with cluster.client(workers=1) as c:
    print("threaded", sorted(c.run(seen).values()))
stop.set()
"""


def test_the_fork_server_is_a_fork_of_a_one_thread_caller_and_its_workers_cpu_still_counts():
    """``_fork_server``: in a one-thread caller on Linux the server is a fork of the caller, so
    the workers have what the caller had made (a module no file holds) and the caller's hash seed,
    but mpmath's and python-flint's default precisions and Python's SIGTERM handler, not the
    caller's, and their parent is the server, not the caller; a task's CPU in a worker still shows in the
    caller's ``getrusage(RUSAGE_CHILDREN)``.  With a second thread running the server is spawned
    and the workers lack that module (the check can fail)."""
    import ast
    import subprocess
    import sys

    if not sys.platform.startswith("linux"):
        pytest.skip("the server is a fork of the caller on Linux only (cluster._fork_server)")
    out = subprocess.run([sys.executable, "-c", _FORKED_FROM_CALLER], capture_output=True, text=True,
                         timeout=240, check=True).stdout.splitlines()
    forked = next(line for line in out if line.startswith("forked "))
    rows, seed, pid, burnt, counted = forked[len("forked "):].rsplit(" ", 4)
    rows = ast.literal_eval(rows)
    assert len(rows) == 2 and all(has and h == int(seed) and parent != int(pid) for has, h, parent, *_ in rows), out
    assert rows[0][2] == rows[1][2]              # one server
    assert all(row[3:] == (53, 53, True) for row in rows), out     # the precisions and SIGTERM's handler
    assert float(burnt) >= 1.0 and float(counted) >= float(burnt), out
    threaded = ast.literal_eval(next(line for line in out if line.startswith("threaded "))[len("threaded "):])
    assert [row[0] for row in threaded] == [False], out
