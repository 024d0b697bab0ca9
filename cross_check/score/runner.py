"""Calling an adapter on a scene's starts under a time budget: in a worker process, or in process.

``Isolated`` loads the adapter by its ``MODULE:NAME`` spec (or from its pickle) in one long-lived
worker process (``isolate.Worker``) and kills it when a call runs over its budget: nothing the
adapter does -- a Python loop, a loop inside C -- survives that.  ``InProcess`` calls the
adapter here (for adapters that cannot be pickled or loaded by spec); there the budget is
checked after each call returns, so a call that never returns hangs the run.

``run_starts`` calls ``step`` or ``events`` on a scene's starts:

0. (``warm_up``, once per method and set of effects in a run) one call on a start of any scene
   with those effects that neither sticks nor chatters, within ``Budget.first``, its outcome
   thrown away: a JIT compiling a new code path is not the adapter's speed, nor a timeout;
1. one start alone (the scorer picks one that neither sticks nor chatters): its time sizes the
   batch's budget;
2. then the whole batch in one call (the timed one), with the budget of one start plus twice the
   first start's time for each start (a sound but slow adapter is not cut off);
3. where the first start ran out of time or the process died, or the batch raised or ran out of
   time: the others start by start, each with its own budget.  So a batch over its budget costs
   a rerun, never a grade, and each start's outcome is its own.
"""
from __future__ import annotations

import argparse
import math
import pickle
import threading
import time
from dataclasses import dataclass

import numpy as np

from cross_check.score import isolate, protocol

SLOW = 1.0        # seconds: a call running longer gets a progress line
#: seconds per call on a start (``score --case-timeout``, the plugin's ``--golden-timeout``): a
#: sound integrator does a period of any golden case in well under a second (the reference at 30
#: digits: < 1 s on the slowest chatter)
CASE_TIMEOUT = 10.0
#: seconds for the warm-up call of step and of events on each set of effects in a run
#: (``--first-call-timeout``; the plugin's warm-up of a test): a cold numba compile of ``fast``
#: takes ~20 s on one core
FIRST_CALL_TIMEOUT = 60.0


def positive_seconds(text) -> float:
    """A command-line budget: a positive finite number of seconds (else argparse's error, exit 2)."""
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be a positive number of seconds, got {text!r}")
    return value


@dataclass
class Outcome:
    """One call on one or more starts: ``value`` (checked result), or a ``failure`` of ``kind``
    ``exception`` | ``timeout`` | ``crash``."""

    value: object = None
    failure: str | None = None
    kind: str | None = None
    seconds: float = 0.0
    budget: float | None = None


class InProcess:
    """The adapter object called here; the budget checked after each call."""

    isolated = False
    note = ("in process (--in-process): the budget is checked after each call returns, so a start that "
            "never returns hangs the run")

    def __init__(self, adapter, who: str | None = None):
        self.adapter, self.who = adapter, who or protocol.label(adapter)
        self.meta = protocol.describe(adapter, self.who)
        self.restarts = 0

    def call(self, method, args, budget, on_slow=None) -> Outcome:
        timer = threading.Timer(SLOW, on_slow) if on_slow is not None and budget > SLOW else None
        if timer is not None:
            timer.daemon = True
            timer.start()
        t0 = time.perf_counter()
        try:
            value = protocol.call(self.adapter, self.who, method, *args)
        except protocol.BadAdapter:
            raise
        except Exception as exc:  # noqa: BLE001 -- an adapter's exception is its failure, recorded
            return Outcome(failure=f"{type(exc).__name__}: {str(exc)[:200]}", kind="exception",
                           seconds=time.perf_counter() - t0)
        finally:
            if timer is not None:
                timer.cancel()
        seconds = time.perf_counter() - t0
        if seconds > budget:
            return Outcome(failure=f"it took {seconds:.3g} s; in process the budget is checked after the call",
                           kind="timeout", seconds=seconds, budget=budget)
        return Outcome(value=value, seconds=seconds)

    def close(self):
        pass


class Isolated:
    """The adapter in a worker process, loaded there from ``source`` (a spec, or a pickled adapter)."""

    isolated = True
    note = ("worker process: a call over the budget is stopped (the process is killed and restarted), "
            "whatever the adapter is doing")

    def __init__(self, source, setup_budget: float = isolate.SETUP_BUDGET):
        self.source = source
        self.who = repr(source) if isinstance(source, str) else "the pickled adapter"
        self.worker = isolate.Worker([("cross_check.score.protocol:worker_load", (source,))],
                                     setup_budget=setup_budget)
        try:
            self.meta = self.worker.start()[0]
        except BaseException as exc:
            self.close()
            if isinstance(exc, isolate.RemoteError):
                raise _bad(exc, source) from None
            if isinstance(exc, (isolate.CallTimeout, isolate.WorkerDied)):
                raise protocol.BadAdapter(f"adapter {self.who}: could not be loaded in a worker process: "
                                          f"{exc}") from None
            raise

    @property
    def restarts(self) -> int:
        return self.worker.kills

    def call(self, method, args, budget, on_slow=None) -> Outcome:
        fn = "cross_check.score.protocol:worker_call"
        try:
            value, seconds = self.worker.call(fn, self.source, method, *args, budget=budget, on_slow=on_slow,
                                              slow_after=SLOW)
        except isolate.CallTimeout:
            return Outcome(failure="the worker process was stopped", kind="timeout", seconds=budget, budget=budget)
        except isolate.WorkerDied as exc:
            return Outcome(failure=str(exc), kind="crash")
        except isolate.RemoteError as exc:
            if isinstance(exc.original, protocol.BadAdapter) or exc.type_name == "BadAdapter":
                raise _bad(exc, self.source) from None
            return Outcome(failure=f"{exc.type_name}: {exc.message[:200]}", kind="exception")
        if len(args[1]) == 1:          # a call on one start that worked: warms a restarted process
            self.worker.warmups[method] = (fn, (self.source, method, *args))
        return Outcome(value=value, seconds=seconds)

    def close(self):
        self.worker.close()


def _bad(exc: isolate.RemoteError, source) -> protocol.BadAdapter:
    if isinstance(exc.original, protocol.BadAdapter):
        return protocol.BadAdapter(exc.original.message, exc.original.detail or exc.traceback)
    if exc.type_name == "BadAdapter":
        return protocol.BadAdapter(exc.message, exc.traceback)
    who = repr(source) if isinstance(source, str) else "the pickled adapter"
    return protocol.BadAdapter(f"adapter {who}: loading it raised {exc.type_name}: {exc.message[:300]}",
                               exc.traceback)


def runner(adapter, in_process: bool | None = None, setup_budget: float = isolate.SETUP_BUDGET):
    """The runner for ``adapter`` (an object or a ``MODULE:NAME`` spec): a spec runs in a worker
    process unless ``in_process``; an object runs in process unless ``in_process=False`` (then it
    must pickle)."""
    if isinstance(adapter, str):
        if in_process:
            return InProcess(protocol.load_adapter(adapter), repr(adapter))
        return Isolated(adapter, setup_budget)
    if in_process is False:
        try:
            blob = pickle.dumps(adapter)
        except Exception as exc:  # noqa: BLE001
            raise ValueError(f"in_process=False needs a MODULE:NAME spec or an adapter that pickles; "
                             f"{protocol.label(adapter)} does not ({type(exc).__name__}: {exc})") from None
        return Isolated(blob, setup_budget)
    return InProcess(adapter)


class Budget:
    """``per_start`` seconds per call on a start; ``first`` for the warm-up call of each method on
    each set of effects (a JIT such as ``fast``'s compiles a kernel per code path: one per set of
    effects, e.g. position forcing; the first call on a new one includes that compilation)."""

    def __init__(self, per_start: float, first: float):
        for name, value in (("case_timeout", per_start), ("first_call_timeout", first)):
            if not (isinstance(value, (int, float)) and np.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a positive number of seconds, got {value!r}")
        self.per_start, self.first = float(per_start), max(float(first), float(per_start))
        self._seen: set = set()

    def first_time(self, key) -> bool:
        """Whether ``key`` (method, effects) comes for the first time (and note that it came)."""
        new = key not in self._seen
        self._seen.add(key)
        return new


def warm_up(run, method, params, x: float, v: float, budget: Budget, label: str, say=None) -> Outcome:
    """One call of ``method`` on the start ``(x, v)`` within ``budget.first``, its outcome thrown
    away: the first call on a new set of effects, made on a start that neither sticks nor chatters
    (``golden.warmup_case``), so that a JIT compiling there eats no start's budget."""
    say = say or (lambda m: None)
    out = run.call(method, (params, np.array([x]), np.array([v]), 1 if method == "step" else None), budget.first,
                   on_slow=lambda: say(f"  warm-up on {label}: {method} still running after {SLOW:g} s "
                                       f"(budget {budget.first:g} s: a JIT may compile)"))
    if out.seconds > SLOW or out.failure:
        say(f"  warm-up on {label}: {method} " + (f"{out.kind}: {out.failure}" if out.failure
                                                  else f"done in {out.seconds:.1f} s"))
    return out


def run_starts(run, method, params, X, V, periods, budget: Budget, names, say=None, first=0):
    """``method`` on the starts ``X, V`` (module docstring) -> ``(outcomes per start, seconds of the
    timed call or the sum of the single calls, "batch" | "start by start")``.  ``names``: the
    starts' labels for progress lines; ``say(message)`` prints one; ``first``: the start to begin
    with (the one least likely to hang: the scorer picks one that neither sticks nor chatters)."""
    n = len(X)
    say = say or (lambda m: None)

    def one(i, b):
        out = run.call(method, (params, X[i:i + 1], V[i:i + 1], periods), b,
                       on_slow=lambda: say(f"  {names[i]}: {method} still running after {SLOW:g} s (budget {b:g} s)"))
        if out.seconds > SLOW or out.kind == "timeout":
            say(f"  {names[i]}: {method} " + (f"{out.kind}: {out.failure}" if out.failure else f"done in {out.seconds:.1f} s"))
        if out.failure is None:
            out.value = _part(out.value, 0)
        return out

    outs = [None] * n
    outs[first] = warm = one(first, budget.per_start)
    if n > 1 and warm.kind not in ("timeout", "crash"):
        b = min(n * budget.per_start, budget.per_start + 2 * n * warm.seconds)
        batch = run.call(method, (params, X, V, periods), b,
                         on_slow=lambda: say(f"  batch of {n} starts: {method} still running after {SLOW:g} s "
                                             f"(budget {b:g} s)"))
        if batch.failure is None:
            return [Outcome(value=_part(batch.value, i), seconds=batch.seconds / n) for i in range(n)], \
                batch.seconds, "batch"
        say(f"  batch of {n} starts: {method} {batch.kind} ({batch.failure}): start by start")
    for i in range(n):
        if i != first:
            outs[i] = one(i, budget.per_start)
    return outs, sum(o.seconds for o in outs if o.failure is None), "start by start"


def _part(value, i):
    """Start ``i`` of a checked batch result (a pair of arrays, or a list of event logs)."""
    if isinstance(value, tuple):
        return value[0][i], value[1][i]
    return value[i]


__all__ = ["Budget", "CASE_TIMEOUT", "FIRST_CALL_TIMEOUT", "InProcess", "Isolated", "Outcome", "positive_seconds",
           "run_starts", "runner", "warm_up"]
