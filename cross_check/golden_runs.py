"""The reference's runs of a golden input and what ``golden`` checks and writes of them: one
integration over ``[0, T]`` at ``dps`` digits gives the map, the Jacobian (Table 1's product) and
the event log (``compute``); two runs agree when their itineraries match and every value lies
within ``golden_self_agreement`` (the Jacobian within that times its conditioning ``kappa``:
``disagreement``); ``record`` writes a result at ``DIGITS`` significant digits (``fmt``).
"""
from __future__ import annotations

import math

import mpmath

from cross_check.agreement import compare
from cross_check.tolerances import tol

GOLDEN_DPS = 90
CHECK_DPS = GOLDEN_DPS + 20
DIGITS = 40


def fmt(value, digits: int = DIGITS) -> str | None:
    """``digits`` significant digits, deterministic (``None`` stays ``None``)."""
    if value is None:
        return None
    with mpmath.workdps(DIGITS + 10):
        return mpmath.nstr(mpmath.mpf(value), digits, strip_zeros=False)


class _KeptFlights:
    """The reference's model with the flights its integrator makes kept by their start, so that
    Table 1's flight factors (``reference.jacobian``'s ``flow_derivative`` hook) are the
    variational equations on *those* Taylor steps, not on a flight integrated again per factor
    (``reference.taylor.flight_matrix``: the same steps from the same start and sign, so the
    same numbers)."""

    def __init__(self, model):
        self.model, self.kept = model, {}

    def __getattr__(self, name):
        return getattr(self.model, name)

    def flight(self, t0, x0, v0, s):
        made = self.model.flight(t0, x0, v0, s)
        self.kept[(t0, x0, v0, s)] = made
        return made

    def flow_derivative(self, start, t):
        from reference import taylor

        t0, x0, v0 = start
        s = 0 if not self.model.friction else (
            (1 if v0 > 0 else -1) if v0 != 0 else (1 if self.model.force(x0, t0) > 0 else -1))
        made = self.kept.get((t0, x0, v0, s))
        if made is None:
            return taylor.flight_matrix(self.model, t0, x0, v0, t)
        J = made.jacobian(t)
        return [[J[0, 0], J[0, 1]], [J[1, 0], J[1, 1]]]


def compute(sc, case, dps: int, jacobian: bool = True) -> dict:
    """Map, Jacobian and one-period event log of ``reference`` at ``dps`` (mpf values).

    One integration over ``[0, T]`` gives all three (what ``reference.stroboscopic_map``,
    ``jacobian`` and ``trajectory`` each integrate again; issue 33: under position forcing the
    three runs, each Jacobian factor a fresh Taylor flight, were ~70% of a golden input's cost),
    each value rounded to ``dps`` digits as those calls round it.  ``jacobian=False``: no
    Jacobian (``None``, with the note saying so; ``proved_values`` takes it from the proof).
    ``"points"``: the run's point log (a proof's guide); ``"dps"``: its digits.
    """
    from reference import api, integrator

    with mpmath.workdps(dps + 10):
        x, v = case.mpf()                            # as compare.ref_map & co. read a case
    with mpmath.workdps(api._work_dps(sc, dps)):
        model = _KeptFlights(api._model_here(sc))
        x, v = api._state(model, x, v)
        log = integrator.integrate(model, mpmath.mpf(0), x, v, model.T)
        out = {"phi": api._rounded(dps, log.x_end, log.v_end)}
        out["jacobian"], out["jacobian_note"] = _jacobian(model, log, dps) if jacobian else (None, "not computed")
        with mpmath.workdps(dps):
            out["events"] = [compare.Event(e.kind, +e.t, +e.x, +e.v, None if e.v_before is None else +e.v_before,
                                           e.count) for e in log]
        out["points"] = (log, (model.l, model.r))   # the point log an enclosure may be guided by
        out["dps"] = dps
    return out


def _jacobian(model, log, dps):
    """``(Phi', None)`` of the run (Table 1's product, ``dps`` digits), or ``(None, why)`` where
    it is undefined (grazing: the reference says why)."""
    from reference.jacobian import product_of_table1

    try:
        J = product_of_table1(model, log)
    except (ValueError, ArithmeticError) as exc:
        return None, f"{type(exc).__name__}: {exc}"
    with mpmath.workdps(dps):
        return [[+J[0][0], +J[0][1]], [+J[1][0], +J[1][1]]], None


def kappa(sc, res) -> float:
    """Conditioning of the Jacobian: ``max(1, max over impacts of (F/w) / |v-|)``.

    The saltation entry ``2A/v-`` carries the relative error of ``v-``, whose absolute error
    is of the order of the velocity unit ``F/w`` times the working precision.
    """
    unit = max(sc.float("F") / sc.float("omega"), sc.float("f") / sc.float("omega"), 1e-300)
    k = 1.0
    for e in compare.canonical(res["events"], sc):   # bounces of a chatter run: not physics
        if e.kind == "impact" and e.v_before is not None and e.v_before != 0:
            k = max(k, unit / abs(float(e.v_before)))
    return k


def jacobian_digits(sc, res) -> int:
    """Significant digits written for the Jacobian: ``DIGITS - ceil(log10 kappa)``."""
    return max(1, DIGITS - math.ceil(math.log10(kappa(sc, res))))


def _values(res, jacobian: bool) -> list:
    vals = list(res["phi"])
    for e in res["events"]:
        vals += [e.t, e.x, e.v] + ([] if e.v_before is None else [e.v_before])
    if jacobian and res["jacobian"] is not None:
        return [res["jacobian"][i][j] for i in range(2) for j in range(2)]
    return vals


def _beyond(va, vb, rtol) -> bool:
    va, vb = mpmath.mpf(va), mpmath.mpf(vb)
    return abs(va - vb) > rtol * max(1, abs(vb))


def disagreement(a: dict, b: dict, sc=None) -> str | None:
    """Why the runs ``a`` (dps) and ``b`` (dps + 20) disagree, or ``None``.

    Map and events: within ``golden_self_agreement``; the Jacobian within that times
    ``kappa`` (the digits it can carry near grazing; only those digits are written).
    Itineraries are compared in ``compare.canonical`` form (the number of chatter bounces
    simulated one by one depends on the precision).
    """
    if sc is not None:
        a = {**a, "events": compare.canonical(a["events"], sc)}
        b = {**b, "events": compare.canonical(b["events"], sc)}
    ka, kb = [e.kind for e in a["events"]], [e.kind for e in b["events"]]
    if ka != kb:
        first = next((i for i, (x, y) in enumerate(zip(ka, kb)) if x != y), min(len(ka), len(kb)))
        return (f"itineraries differ at event {first}: {' '.join(ka[first:first + 4])} ... ({len(ka)} events) "
                f"vs {' '.join(kb[first:first + 4])} ... ({len(kb)} events)")
    if (a["jacobian"] is None) != (b["jacobian"] is None):
        return f"Jacobian defined in one run only ({a['jacobian_note']} / {b['jacobian_note']})"
    rtol = tol("golden_self_agreement").rtol
    k = 1.0 if sc is None else kappa(sc, b)
    with mpmath.workdps(CHECK_DPS):
        for jac, scale in ((False, 1.0), (True, k)):
            for va, vb in zip(_values(a, jac), _values(b, jac)):
                if _beyond(va, vb, rtol * scale):
                    return f"value {mpmath.nstr(va, 45)} != {mpmath.nstr(vb, 45)} beyond {rtol * scale:g}"
    return None


def record(sc, res: dict) -> dict:
    """The JSON form of one result (strings at ``DIGITS`` digits; the Jacobian at its own).

    Events are stored in ``compare.canonical`` form (a chatter run as its first impact and
    the ``chatter`` event; the number of bounces the reference simulated one by one is an
    implementation detail and is not stored).
    """
    jac = res["jacobian"]
    nd = jacobian_digits(sc, res)
    return {
        "phi": [fmt(res["phi"][0]), fmt(res["phi"][1])],
        "jacobian": None if jac is None else [[fmt(jac[i][j], nd) for j in range(2)] for i in range(2)],
        "jacobian_digits": None if jac is None else nd,
        "jacobian_note": res["jacobian_note"],
        "events": [[e.kind, fmt(e.t), fmt(e.x), fmt(e.v), fmt(e.v_before)]
                   for e in compare.canonical(res["events"], sc)],
    }
