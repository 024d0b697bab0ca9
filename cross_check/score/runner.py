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

With the scene's per-kind cut-off (``cutoff``) and once the adapter has timed out in the run, a
suspect kind's probe runs before the batch, the starts with the short budget (``Budget``) leave
the batch, and a start of a kind that was cut is not run (``run_starts``).
"""
from __future__ import annotations

import argparse
import math
import pickle
import threading
import time
from dataclasses import dataclass

import numpy as np

from cross_check.score import cutoff, isolate, protocol

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
        except protocol.ReportedTimeout as exc:
            return Outcome(failure=str(exc)[:200], kind="timeout", seconds=time.perf_counter() - t0, budget=budget)
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
            if exc.type_name == "ReportedTimeout":
                return Outcome(failure=exc.message[:200], kind="timeout", budget=budget)
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


#: the short budget (issue 37): ``max(BUDGET_FLOOR, BUDGET_MULTIPLE x median)`` seconds, the median
#: of the adapter's own completed starts per period (``score --budget-multiple``, ``--budget-floor``).
#: It is given only where a timeout cannot change a grade (``Budget``).  No multiple of the median
#: would be safe where a grade rides on it: the spread of a correct adapter's start times is wide
#: (one call per golden case, measured on this machine: slowest / median = 120 for the reference at
#: 30 digits -- chatter and position forcing --, 6 for scipy's DOP853, 361 for heyoka -- sticking,
#: turns at a wall).  Where none rides on it, 20 x the median lets a start 20 times the typical one
#: finish (the most scipy's DOP853 needs is 6 times), and the floor, 1 s, covers what any short call
#: costs whatever the adapter: a worker restart, a pipe round trip, a garbage collection, a loaded
#: machine (the naive solve_ivp of the tests has a median of 15 ms, 33 ms at load 7: the floor is 30
#: to 65 times that).  What it saves is the budget of every start of a failing kind after its
#: first failure: 1 s instead of the 10 s cap.
BUDGET_MULTIPLE = 20.0
BUDGET_FLOOR = 1.0
#: completed starts of a method before its median is trusted (about one scene's worth)
BUDGET_MIN_STARTS = 10


class Budget:
    """``per_start`` seconds per call on a start (the cap, ``--case-timeout``); ``first`` for the
    warm-up call of each method on each set of effects (a JIT such as ``fast``'s compiles a kernel
    per code path: one per set of effects, e.g. position forcing; the first call on a new one
    includes that compilation).

    **The short budget** (issue 37).  Until the adapter's first timeout in the run, every start
    has the cap and batches are sized as before: an adapter that never runs out of time -- a
    correct one, however slow -- is scored exactly as without it.  From its first timeout on, a
    start whose outcome cannot change a grade gets ``short(method) = min(cap, max(floor,
    multiple x median))`` (``median``: seconds per start and period of the method's completed
    calls, once ``min_starts`` completed; the cap until then): a start in the near-grazing band
    (never graded), a start of a kind that already has a graded failure in the run (graded F
    whatever follows), and a call of a kind in ``ungraded`` (the scorer's ten-period calls; the
    short budget is per call, not per period: at the default multiple twice a typical ten-period
    call, or the floor).  A graded start of any other kind keeps the cap.  ``multiple=0``
    switches the short budget off."""

    def __init__(self, per_start: float, first: float, *, multiple: float = BUDGET_MULTIPLE,
                 floor: float = BUDGET_FLOOR, min_starts: int = BUDGET_MIN_STARTS, ungraded=()):
        for name, value in (("case_timeout", per_start), ("first_call_timeout", first), ("budget_floor", floor)):
            if not (isinstance(value, (int, float)) and np.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a positive number of seconds, got {value!r}")
        if not (isinstance(multiple, (int, float)) and np.isfinite(multiple) and multiple >= 0):
            raise ValueError(f"budget_multiple must be a number >= 0 (0: no short budget), got {multiple!r}")
        self.per_start, self.first = float(per_start), max(float(first), float(per_start))
        self.multiple, self.floor, self.min_starts = float(multiple), float(floor), int(min_starts)
        self._seen: set = set()
        self.times: dict = {}           # method -> seconds per start and period of completed calls
        self.failed: set = set(ungraded)    # kinds with a graded failure in the run, or never graded
        self.hung = False               # the adapter has run out of time once in the run

    def first_time(self, key) -> bool:
        """Whether ``key`` (method, effects) comes for the first time (and note that it came)."""
        new = key not in self._seen
        self._seen.add(key)
        return new

    def note(self, method: str, out: "Outcome", periods, starts: int = 1, kind=None, graded=False) -> None:
        """Learn from an outcome of ``method`` on ``starts`` start(s) of ``kind``."""
        if out.failure is None:
            self.times.setdefault(method, []).extend([out.seconds / starts / (periods or 1)] * starts)
            return
        self.hung = self.hung or out.kind == "timeout"
        if graded and kind is not None and (method == "step" or out.kind in ("timeout", "crash")):
            self.failed.add(kind)     # a failure the card counts (an exception in events is not one)

    def median(self, method: str) -> float | None:
        """Seconds per start and period of ``method``'s completed calls (``None``: too few yet)."""
        times = self.times.get(method, ())
        return float(np.median(times)) if len(times) >= self.min_starts else None

    def short(self, method: str) -> float:
        """The short budget of a call of ``method`` (class docstring)."""
        median = self.median(method)
        if not self.multiple or median is None:
            return self.per_start
        return min(self.per_start, max(self.floor, self.multiple * median))

    def full(self, kind=None, graded=True) -> bool:
        """Whether a start of ``kind`` (``graded``: outside the band) has the cap: always until the
        adapter's first timeout, then where a grade rides on it (class docstring)."""
        return not self.hung or (graded and (kind is None or kind not in self.failed))

    def start(self, method: str, periods=1, kind=None, graded=True) -> float:
        """The budget of a call of ``method`` on one start of ``kind`` over ``periods``: the cap, or
        the short budget where no grade rides on it (``full``)."""
        return self.per_start if self.full(kind, graded) else self.short(method)

    def describe(self) -> dict:
        """The budgets for the scorecard."""
        median = self.median("step")
        return {"case_timeout": self.per_start, "first_call_timeout": self.first,
                "budget_multiple": self.multiple, "budget_floor": self.floor,
                "median_seconds": median, "short_budget": self.short("step") if self.hung else None}


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


def run_starts(run, method, params, X, V, periods, budget: Budget, names, say=None, first=0, *, tags=None, cut=None):
    """``method`` on the starts ``X, V`` (module docstring) -> ``(outcomes per start, seconds of the
    timed call or the sum of the single calls, "batch" | "start by start")``.  ``names``: the
    starts' labels for progress lines; ``say(message)`` prints one; ``first``: the start to begin
    with (the one least likely to hang: the scorer picks one that neither sticks nor chatters).

    ``tags``: ``(kind, graded)`` per start (default: no kind, graded: every start has the cap);
    ``cut``: the scene's ``cutoff.SceneCut``.  With them, a start of a kind the cut-off stopped is
    not run (an ``Outcome`` of kind ``cutoff.NOT_RUN`` with the budget it would have had), a suspect
    kind's probe runs alone before the batch, and the starts with the short budget
    (``Budget.start``: only once the adapter has timed out in the run) run start by start, not in
    the batch; the batch's budget is then the short one plus twice the first start's time each
    (a batch over it costs a rerun start by start, never a grade)."""
    n = len(X)
    say = say or (lambda m: None)
    tags = list(tags) if tags is not None else [(None, True)] * n

    def one(i):
        b = budget.start(method, periods, *tags[i])
        out = run.call(method, (params, X[i:i + 1], V[i:i + 1], periods), b,
                       on_slow=lambda: say(f"  {names[i]}: {method} still running after {SLOW:g} s (budget {b:g} s)"))
        out.budget = b
        if out.seconds > SLOW or out.kind == "timeout":
            say(f"  {names[i]}: {method} " + (f"{out.kind}: {out.failure}" if out.failure else f"done in {out.seconds:.1f} s"))
        if out.failure is None:
            out.value = _part(out.value, 0)
        budget.note(method, out, periods, 1, *tags[i])
        if cut is not None:
            cut.record(*tags[i], out.kind == "timeout")
        return out

    def stopped(i):
        reason = cut.reason(*tags[i]) if cut is not None else None
        return reason and Outcome(failure=reason, kind=cutoff.NOT_RUN, budget=budget.start(method, periods, *tags[i]))

    outs = [None] * n
    outs[first] = warm = one(first)
    for i in range(n):
        if outs[i] is None and cut is not None and cut.is_probe(*tags[i]):
            outs[i] = one(i)
    batch = [i for i in range(n) if budget.full(*tags[i]) and not stopped(i) and (outs[i] is None or i == first)]
    if len(batch) > 1 and warm.kind not in ("timeout", "crash"):
        m = len(batch)
        b = min(m * budget.per_start, (budget.short(method) if budget.hung else budget.per_start)
                + 2 * m * warm.seconds)
        got = run.call(method, (params, X[batch], V[batch], periods), b,
                       on_slow=lambda: say(f"  batch of {m} starts: {method} still running after {SLOW:g} s "
                                           f"(budget {b:g} s)"))
        budget.note(method, got, periods, m)
        if got.failure is None:
            for j, i in enumerate(batch):
                outs[i] = Outcome(value=_part(got.value, j), seconds=got.seconds / m, budget=budget.per_start)
            if m == n:
                return outs, got.seconds, "batch"
        else:
            say(f"  batch of {m} starts: {method} {got.kind} ({got.failure}): start by start")
    for i in range(n):
        if outs[i] is None:
            outs[i] = stopped(i) or one(i)
    return outs, sum(o.seconds for o in outs if o.failure is None), "start by start"


def _part(value, i):
    """Start ``i`` of a checked batch result (a pair of arrays, or a list of event logs)."""
    if isinstance(value, tuple):
        return value[0][i], value[1][i]
    return value[i]


__all__ = ["BUDGET_FLOOR", "BUDGET_MIN_STARTS", "BUDGET_MULTIPLE", "Budget", "CASE_TIMEOUT", "FIRST_CALL_TIMEOUT",
           "InProcess", "Isolated", "Outcome", "positive_seconds",
           "run_starts", "runner", "warm_up"]
