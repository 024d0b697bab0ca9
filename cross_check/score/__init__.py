"""Score any integrator against the golden data: the conformance suite for this system.

THE ADAPTER PROTOCOL (the one place it is written down)
-------------------------------------------------------
An adapter is any object with

* ``name: str`` -- how the scorecard calls it;
* ``effects: set[str]`` -- the effects it models, a subset of ``reference.scene.EFFECTS``:
  ``walls``, ``forcing``, ``friction``, ``restitution``, ``damping``, ``position_forcing``.
  A scene that needs an effect the adapter does not declare is *skipped and listed*, never
  scored as a failure;
* ``step(params, x, v, periods) -> (x, v)`` -- required.  ``params`` is a dict of plain floats
  ``F, f, omega, l, r, restitution, damping`` and ``wavenumber`` (a float, or ``None`` without
  position forcing); the system is ``x'' + f sgn(x') + c x' = F cos(k x) cos(omega t)`` on
  ``l <= x <= r`` with ``v -> -e v`` at the walls, in Filippov's sense (stick while the force
  is within the friction).  ``x, v`` are float64 arrays of starts at ``t = 0``; the result is
  ``Phi^periods`` at ``t = periods T``, ``T = 2 pi / omega``, two float64 arrays of the same shape;
* ``jacobian(params, x, v) -> J`` -- optional: ``Phi'`` as an array ``(n, 2, 2)``;
* ``events(params, x, v) -> list`` -- optional: per start, the events of ``[0, T]`` as tuples
  ``(kind, t, x, v_after, v_before)`` with ``kind`` in ``impact, turn, stick, slip, contact,
  release, chatter`` (``cross_check.agreement.compare``'s kinds; the scorer brings both logs
  to ``compare.canonical`` form before comparing).

Plain floats and numpy arrays only: wrapping an engine takes a few lines (``adapters`` holds
``fast``, ``reference``, scipy's ``solve_ivp`` and heyoka.py as examples).  An exception or a
non-finite result on a start, or no result within the time budget, is a *failure* of that
start, recorded, not a crash (an adapter that timed a start out itself raises
``protocol.ReportedTimeout``: a failure of kind timeout); a result of the wrong type or shape is a
bad adapter (``protocol``).  An integrator in another language writes a results file instead
(``problems``: the problems as CSV/JSON; ``results``: the file read back as one more adapter).

* ``card``     -- ``score(adapter, scenes=..., periods=(1, 10), case_timeout=10, kind_timeouts=2)`` ->
  ``Scorecard`` (markdown, JSON), and the CLI ``python -m cross_check score MODULE:NAME [--scenes ...]
  [--out DIR] [--case-timeout S] [--kind-timeouts K] [--in-process]``;
* ``sheet``    -- the scorecard as data: rows, grades per kind, JSON and markdown;
* ``golden``   -- the golden cases as plain objects (``GoldenCase``), with their kind, and what
  usually makes an integrator time out on each kind;
* ``protocol`` -- the protocol checked: ``load_adapter``, ``BadAdapter`` (exit status 2);
* ``runner``, ``isolate`` -- the time budget: an adapter given by its spec runs in a worker
  process killed when a call runs over (``spawn``), one process per run, restarted only after a
  timeout; an adapter object runs in process, where the budget is checked after each call; after
  the adapter's first timeout, a short budget where no grade rides on it (``runner.Budget``);
* ``cutoff``   -- fail fast per kind: after K timeouts of a kind in a scene its other starts there
  are not run (failed, counted apart), with one probe per scene for a kind that keeps failing;
* ``adapters`` -- the shipped adapters;
* ``problems``, ``results`` -- the results-file protocol: ``score --export-problems DIR``, ``score
  --results FILE`` (``ResultsAdapter``), the example integrator in C in ``cross_check/data/examples``;
* ``plugin``   -- the pytest plugin (entry point ``pytest11``): a ``golden_case`` fixture, one
  test per golden case, each run in a worker process with ``--golden-timeout`` seconds.

May import ``cross_check.golden``, ``scenes``, ``agreement``, ``tolerances``, ``reference`` and
``fast``; the report imports it, nothing else does.  The names below are imported on first use,
so that a worker process importing ``cross_check.score.protocol`` starts light.
"""
import importlib

_EXPORTS = {"Scorecard": "cross_check.score.sheet", "score": "cross_check.score.card",
            "main": "cross_check.score.card", "load_adapter": "cross_check.score.protocol",
            "BadAdapter": "cross_check.score.protocol"}


def __getattr__(name):
    if name in _EXPORTS:
        return getattr(importlib.import_module(_EXPORTS[name]), name)
    raise AttributeError(f"module 'cross_check.score' has no attribute {name!r}")


__all__ = ["BadAdapter", "Scorecard", "load_adapter", "main", "score"]
