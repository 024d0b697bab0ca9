"""A time budget that cannot be ignored: untrusted code runs in a worker process that is killed.

A loop inside C code (a compiled kernel, a long numpy or scipy call) never returns to the
interpreter, so it cannot see a signal, and a thread cannot be stopped at all.  What always
works is a separate process that the caller kills.  ``Worker`` is one such process, started
with ``multiprocessing``'s ``spawn`` context and kept for a whole run: it runs calls named by
``"module:function"`` strings (those pickle; the objects they act on are built in the worker
itself, e.g. an adapter loaded by its ``MODULE:NAME`` spec), one at a time, each with a budget.
A call over its budget is a ``CallTimeout``; the worker is killed and the next call gets a
fresh one.

Keeping it cheap:

* one long-lived process per run, not one per call: a call costs a pipe round trip (tens of
  microseconds plus pickling the arrays), the process start and the imports are paid once;
* ``setup`` calls (loading the adapter) run in every fresh process *before* its first call, and
  ``warmups`` (the last call that succeeded, by key) are replayed there, their results thrown
  away: a restarted worker has imported its modules and loaded its JIT caches before the next
  budget starts to run;
* from the second kill on, a *spare* process is started and warmed in the background, so a run
  with many timeouts (a scene where every start sticks) pays for a restart once, not per timeout.

A worker dies with its parent (``PR_SET_PDEATHSIG`` on Linux, which also covers a worker
spinning inside C, and a watcher thread elsewhere) and ignores SIGINT: Ctrl-C goes to the run,
which stops its workers.
"""
from __future__ import annotations

import importlib
import multiprocessing
import os
import pickle
import signal
import sys
import threading
import time
import traceback
from multiprocessing.connection import wait as _wait_ready

#: a fresh process's setup calls (imports, loading an adapter): this long before a start is
#: declared unloadable.  A cold numba compile of ``fast`` takes ~20 s on one core.
SETUP_BUDGET = 120.0


class CallTimeout(Exception):
    """A call ran over its budget; its worker process was killed."""

    def __init__(self, budget: float):
        super().__init__(f"no result within {budget:g} s")
        self.budget = budget


class WorkerDied(Exception):
    """The worker process ended during a call (a crash in C code, ``os._exit``, out of memory)."""


class RemoteError(Exception):
    """The call raised in the worker: ``type_name``, ``message``, the worker's ``traceback`` text and
    the ``original`` exception where it could be pickled (else ``None``)."""

    def __init__(self, type_name, message, tb, original):
        super().__init__(f"{type_name}: {message}")
        self.type_name, self.message, self.traceback, self.original = type_name, message, tb, original


def _resolve(fn: str):
    module, _, name = fn.partition(":")
    return getattr(importlib.import_module(module), name)


def _die_with_parent(parent_pid: int):
    """End this process when the parent ends, even while it spins in C (Linux: the kernel's
    parent-death signal) and elsewhere from a watcher thread (needs the GIL now and then)."""
    if sys.platform.startswith("linux"):
        try:
            import ctypes
            ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)     # PR_SET_PDEATHSIG
        except (OSError, AttributeError):
            pass
    if os.getppid() != parent_pid:           # the parent died before prctl took effect
        os._exit(1)
    parent = multiprocessing.parent_process()
    if parent is not None:
        threading.Thread(target=lambda: (_wait_ready([parent.sentinel]), os._exit(1)), daemon=True).start()


def _serve(conn, parent_pid: int):
    """The worker's loop: receive ``(fn, args)``, reply ``("ok", result)`` or ``("error", ...)``."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _die_with_parent(parent_pid)
    while True:
        try:
            fn, args = conn.recv()
        except (EOFError, OSError):
            return
        try:
            reply = ("ok", _resolve(fn)(*args))
        except BaseException as exc:  # noqa: BLE001 -- every outcome goes back to the caller
            reply = ("error", _error(exc))
        try:
            conn.send(reply)
        except Exception as exc:  # noqa: BLE001 -- e.g. a result that does not pickle
            conn.send(("error", _error(exc)))


def _error(exc):
    try:
        original = pickle.loads(pickle.dumps(exc))
    except Exception:  # noqa: BLE001
        original = None
    return type(exc).__name__, str(exc)[:2000], "".join(traceback.format_exception(exc)), original


def _start_without_main(proc):
    """Start ``proc`` without telling spawn about the caller's ``__main__``: the worker needs nothing
    from it, and spawn would otherwise re-run the caller's script in the worker (a script without
    the ``if __name__ == "__main__"`` guard would start the whole run again there)."""
    main = sys.modules.get("__main__")
    saved = {k: main.__dict__[k] for k in ("__spec__", "__file__") if main is not None and k in main.__dict__}
    try:
        if main is not None:
            main.__spec__ = None
            main.__dict__.pop("__file__", None)
        proc.start()
    finally:
        if main is not None:
            main.__dict__.update(saved)


class _Process:
    """One spawned worker and its pipe; ``pending``: replies still owed for setup and warm-up."""

    def __init__(self, calls):
        ctx = multiprocessing.get_context("spawn")
        self.conn, child = ctx.Pipe()
        self.proc = ctx.Process(target=_serve, args=(child, os.getpid()), daemon=True,
                                name="cross_check-worker")
        _start_without_main(self.proc)
        child.close()
        self.pending = []
        for kind, fn, args, budget in calls:       # pipelined: the process works through them alone
            self.conn.send((fn, args))
            self.pending.append((kind, budget))

    def receive(self, budget: float):
        if not self.conn.poll(budget):
            raise CallTimeout(budget)
        try:
            return self.conn.recv()
        except (EOFError, OSError, ConnectionError):
            self.proc.join(1.0)
            raise WorkerDied(f"the worker process ended (exit code {self.proc.exitcode})") from None

    def kill(self):
        if self.proc.is_alive():
            self.proc.kill()
        self.proc.join(5.0)
        self.conn.close()


class Worker:
    """A long-lived worker process for ``"module:function"`` calls with a budget each (module
    docstring).  ``setup``: ``(fn, args)`` calls every fresh process runs first; ``setup_budget``
    their budget, and the budget of replaying a warm-up."""

    def __init__(self, setup=(), *, setup_budget: float = SETUP_BUDGET):
        self.setup = list(setup)
        self.setup_budget = setup_budget
        self.warmups: dict = {}         # key -> (fn, args): replayed in a fresh process
        self.setup_results: list = []   # what the setup calls returned in the current process
        self.kills = 0
        self._live: _Process | None = None
        self._spare: _Process | None = None

    def _spawn(self) -> _Process:
        calls = [("setup", fn, args, self.setup_budget) for fn, args in self.setup]
        calls += [("warmup", fn, args, self.setup_budget) for fn, args in self.warmups.values()]
        return _Process(calls)

    def start(self) -> list:
        """Make sure a ready process is live; return its setup results.  A setup call that raises
        is a ``RemoteError``, one over ``setup_budget`` a ``CallTimeout`` (the process killed)."""
        while self._live is None:
            proc, self._spare = (self._spare or self._spawn()), None
            if self.kills >= 2 and self._spare is None:   # timeouts come in runs: warm the next one meanwhile
                self._spare = self._spawn()
            results, kind = [], "setup"
            try:
                for kind, budget in proc.pending:
                    status, payload = proc.receive(budget)
                    if kind == "setup":
                        if status != "ok":
                            raise RemoteError(*payload)
                        results.append(payload)
            except (CallTimeout, WorkerDied):
                proc.kill()
                if kind == "setup":
                    raise
                self.warmups.clear()    # a warm-up that no longer finishes: start without any
                continue
            except BaseException:
                proc.kill()
                raise
            proc.pending = []
            self._live, self.setup_results = proc, results
        return self.setup_results

    def call(self, fn: str, *args, budget: float, on_slow=None, slow_after: float = 1.0):
        """``fn(*args)`` in the worker -> ``(result, seconds)``.  Over ``budget`` seconds:
        ``CallTimeout`` (the process killed); raised there: ``RemoteError``; the process gone:
        ``WorkerDied``.  ``on_slow()`` is called once if the call is still running after
        ``slow_after`` seconds (a progress line)."""
        self.start()
        proc = self._live
        t0 = time.perf_counter()
        try:
            try:
                proc.conn.send((fn, args))
            except OSError:             # the process ended since its last call
                proc.proc.join(1.0)
                raise WorkerDied(f"the worker process ended (exit code {proc.proc.exitcode})") from None
            if on_slow is not None and budget > slow_after and not proc.conn.poll(slow_after):
                on_slow()
            status, payload = proc.receive(max(0.0, budget - (time.perf_counter() - t0)))
        except BaseException:           # over budget, died, or Ctrl-C mid-call: the call is abandoned
            self._drop()
            raise
        seconds = time.perf_counter() - t0
        if status != "ok":
            raise RemoteError(*payload)
        return payload, seconds

    def _drop(self):
        self.kills += 1
        if self._live is not None:
            self._live.kill()
        self._live = None

    def close(self):
        """Stop the processes (live and spare)."""
        for proc in (self._live, self._spare):
            if proc is not None:
                proc.kill()
        self._live = self._spare = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


__all__ = ["CallTimeout", "RemoteError", "SETUP_BUDGET", "Worker", "WorkerDied"]
