"""The adapter protocol, checked: loading an adapter by its spec, its attributes, its results.

Two ways an adapter can go wrong, kept apart:

* a **start** fails: ``step`` raises, returns a non-finite number, or runs over its time budget.
  That is the adapter's score on that start (``card``), and the run goes on;
* the **adapter** breaks the protocol (``cross_check.score``): its module raises on import, it
  has no ``name``, ``effects`` or ``step``, or ``step`` returns ``None``, a wrong shape or a
  non-float array.  That is a ``BadAdapter``: scoring stops and ``python -m cross_check score``
  exits with status 2 and a message naming the adapter and what is wrong.

This module is light (numpy and the standard library): the scorer's worker process
(``isolate``) imports it to load an adapter by its ``MODULE:NAME`` spec and to call it, so a
worker starts in a fraction of a second.
"""
from __future__ import annotations

import importlib
import pickle
import traceback

import numpy as np

#: the adapter's attributes the protocol requires
REQUIRED = ("name", "effects", "step")
PROTOCOL = ("an adapter needs name (str), effects (set of str) and step(params, x, v, periods) -> (x, v); "
            "protocol: cross_check.score")


class ReportedTimeout(Exception):
    """Raised by an adapter to report that a start ran out of time where it was computed (a results
    file's status ``timeout``): the start fails with kind ``timeout``, as if the budget had run out."""


class BadAdapter(TypeError):
    """The adapter breaks the protocol; ``detail`` is the traceback behind it, if any (shown
    with ``--debug``)."""

    def __init__(self, message: str, detail: str | None = None):
        super().__init__(message, detail)
        self.message, self.detail = message, detail

    def __str__(self) -> str:
        return self.message


def label(adapter) -> str:
    """How messages name an adapter: its spec, or its ``name``, or its type."""
    if isinstance(adapter, str):
        return repr(adapter)
    name = getattr(adapter, "name", None)
    return repr(name) if isinstance(name, str) else f"<{type(adapter).__name__} object>"


def load_adapter(spec: str):
    """An adapter from ``MODULE:NAME`` (an object, or a class/function called without arguments)
    or a shipped short name (``fast``, ``reference``, ``scipy``, ``heyoka``).  A spec that is not
    of this form is a ``ValueError``; a module that cannot be imported or raises on import, a
    missing name, a constructor that raises, or an object that is not an adapter is a
    ``BadAdapter``."""
    module, sep, name = spec.partition(":")
    if not sep:
        from cross_check.score import adapters     # the shipped names: imported only when asked for

        if spec in adapters.SHIPPED:
            out = adapters.SHIPPED[spec]()
            if out is None:
                raise BadAdapter(f"adapter {spec!r} is not available here (pip install {spec})")
            return out
        raise ValueError(f"adapter must be MODULE:NAME or one of {', '.join(adapters.SHIPPED)}, got {spec!r}")
    if not module or not name:
        raise ValueError(f"adapter must be MODULE:NAME, got {spec!r}")
    try:
        mod = importlib.import_module(module)
    except ModuleNotFoundError as exc:
        if exc.name and (module == exc.name or module.startswith(exc.name + ".")):
            raise BadAdapter(f"adapter {spec!r}: no module {exc.name!r} (is its directory on PYTHONPATH?)") from None
        raise _raised(spec, "raised on import", exc) from None
    except BaseException as exc:  # noqa: BLE001 -- any exception of the user's module names the adapter
        if isinstance(exc, KeyboardInterrupt):
            raise
        raise _raised(spec, "raised on import", exc) from None
    if not hasattr(mod, name):
        raise BadAdapter(f"adapter {spec!r}: module {module!r} has no {name!r}")
    obj = getattr(mod, name)
    if isinstance(obj, type) or (callable(obj) and not hasattr(obj, "step")):
        try:
            obj = obj()
        except Exception as exc:  # noqa: BLE001
            raise _raised(spec, f"{name}() raised", exc) from None
    describe(obj, repr(spec))
    return obj


def _raised(spec, what, exc) -> BadAdapter:
    return BadAdapter(f"adapter {spec!r}: {what}: {type(exc).__name__}: {str(exc)[:300]}",
                      "".join(traceback.format_exception(exc)))


def describe(adapter, who=None) -> dict:
    """``{"name", "effects", "events"}`` of an adapter (``events``: whether it gives event logs),
    or ``BadAdapter`` naming what is missing or of the wrong type; ``who``: how to name it."""
    who = label(adapter) if who is None else who
    missing = [a for a in REQUIRED if not hasattr(adapter, a)]
    if missing:
        raise BadAdapter(f"adapter {who} is not an adapter: {type(adapter).__name__} has no "
                         f"{', '.join(repr(a) for a in missing)} ({PROTOCOL})")
    if not isinstance(adapter.name, str):
        raise BadAdapter(f"adapter {who}: name must be a str, got {type(adapter.name).__name__}")
    if isinstance(adapter.effects, str) or not all(isinstance(e, str) for e in _iter(adapter.effects)):
        raise BadAdapter(f"adapter {who}: effects must be a set of effect names (str), got {adapter.effects!r}")
    for method in ("step", "events", "jacobian"):
        if hasattr(adapter, method) and not callable(getattr(adapter, method)):
            raise BadAdapter(f"adapter {who}: {method} must be callable, got {type(getattr(adapter, method)).__name__}")
    return {"name": adapter.name, "effects": sorted(set(adapter.effects)), "events": hasattr(adapter, "events")}


def _iter(x):
    try:
        return list(x)
    except TypeError:
        return [None]


def step_result(out, n: int, who: str):
    """``(x, v)`` float64 arrays of shape ``(n,)`` from an adapter's ``step``, or ``BadAdapter``
    saying what came back instead (``None``, not a pair, a wrong shape, a non-float dtype).
    Non-finite values pass: they are a failure of their start, not of the adapter."""
    expected = f"expected a pair (x, v) of float arrays of shape ({n},)"
    if out is None:
        raise BadAdapter(f"adapter {who}: step returned None; {expected}")
    if isinstance(out, (str, bytes)) or not hasattr(out, "__len__") or len(out) != 2:
        raise BadAdapter(f"adapter {who}: step returned {_what(out)}; {expected}")
    try:
        x, v = (np.asarray(a) for a in out)
    except Exception as exc:  # noqa: BLE001 -- ragged or odd objects: say what came back
        raise BadAdapter(f"adapter {who}: step returned {_what(out)} ({exc}); {expected}") from None
    if x.shape != (n,) or v.shape != (n,):
        raise BadAdapter(f"adapter {who}: step returned arrays of shape {x.shape} and {v.shape} for {n} "
                         f"start(s); {expected}")
    if not (np.issubdtype(x.dtype, np.floating) and np.issubdtype(v.dtype, np.floating)):
        raise BadAdapter(f"adapter {who}: step returned arrays of dtype {x.dtype} and {v.dtype}; {expected}")
    return x.astype(float), v.astype(float)


def events_result(out, n: int, who: str) -> list:
    """An adapter's event logs: one list per start of tuples ``(kind, t, x, v_after, v_before)``,
    or ``BadAdapter``."""
    expected = f"expected one list of (kind, t, x, v_after, v_before) tuples per start ({n})"
    if out is None or not hasattr(out, "__len__") or len(out) != n:
        raise BadAdapter(f"adapter {who}: events returned {_what(out)}; {expected}")
    rows = [list(row) for row in out]
    for row in rows:
        for e in row:
            if not hasattr(e, "__len__") or len(e) < 5 or not isinstance(e[0], str):
                raise BadAdapter(f"adapter {who}: events returned an event {e!r}; {expected}")
    return rows


def _what(out) -> str:
    if out is None or not hasattr(out, "__len__"):
        return repr(out)[:80] if out is None else f"a {type(out).__name__}"
    return f"a {type(out).__name__} of length {len(out)}"


def call(adapter, who: str, method: str, params: dict, x, v, periods=None):
    """``adapter.step`` (``method="step"``) or ``adapter.events`` on the starts ``x, v``, the
    result checked (``step_result``, ``events_result``).  Exceptions of the adapter pass through."""
    if method == "step":
        return step_result(adapter.step(params, x, v, periods), len(x), who)
    if method == "events":
        return events_result(adapter.events(params, x, v), len(x), who)
    raise ValueError(f"method must be 'step' or 'events', got {method!r}")


# --- the worker process's side (cross_check.score.isolate runs these by name) --------------
_LOADED: dict = {}


def worker_load(source) -> dict:
    """Load an adapter in the worker (``source``: a spec, or a pickled adapter) and describe it."""
    if isinstance(source, bytes):
        adapter = pickle.loads(source)
        key = source
    else:
        adapter, key = load_adapter(source), source
    _LOADED[key] = adapter
    return describe(adapter, label(source) if isinstance(source, str) else label(adapter))


def worker_call(source, method: str, params: dict, x, v, periods=None):
    """``call`` on the adapter that ``worker_load`` loaded from ``source``."""
    if source not in _LOADED:
        worker_load(source)
    adapter = _LOADED[source]
    return call(adapter, label(source if isinstance(source, str) else adapter), method, params, x, v, periods)


__all__ = ["BadAdapter", "REQUIRED", "ReportedTimeout", "call", "describe", "events_result", "label", "load_adapter",
           "step_result", "worker_call", "worker_load"]
