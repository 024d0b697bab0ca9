"""Certified location of the next event of a flight (float64, one state).

For an event function ``g`` with known ``g, g', g''`` at a point ``b`` and bounds
``|g''| <= M`` (everywhere) and ``|g'''| <= M3``:

* forward certificate: ``g(b+h) >= g + g' h - M h^2/2`` for all ``h`` (global minorant),
  first positive root ``hg = (g' + sqrt(g'^2 + 2 M g)) / M`` (written ``2 g / (sqrt(.) -
  g')`` when ``g' <= 0``: no cancellation); on ``[0, H]`` also ``g(b+h) >= g + g' h +
  m h^2/2`` with ``m = max(g'' - M3 H, -M)`` (local minorant), ``H = min(max(2 hg,
  |g''| / (2 M3)), H_cap)``; ``safe`` = the first root of the local one, capped by ``H``
  (>= ``hg``).  No root of ``g`` lies in ``[b, b + safe)``.
* backward certificate: the same global minorant run backwards from ``b`` gives a window
  ``(b - back, b)`` free of roots when ``g(b) > 0``; when ``g(b) <= 0`` (the trial
  overshot a crossing), ``g`` is strictly decreasing on ``(b - |g'|/M, b]`` and positive
  at its left end if ``g >= -g'^2/(2M)``: exactly one root there.
* prediction: the root of the exact-curvature quadratic ``g + g' d + g'' d^2/2`` nearest
  to 0 in the crossing direction (``d < 0`` after an overshoot); error
  ``<= M3 |d|^3 / (6 |g'|)`` near a simple root.  It is *accepted* when the model has a real
  root there (without one, ``g / |g'|`` is only an estimate), that bound is
  below ``tol`` and ``|d| <= d_acc`` (the state is then carried over ``d`` by the flight's
  local model, ``fast.precise``), or when ``|g|`` is below its noise floor while ``g' <= 0``
  (a tangential zero at working precision: ``d = 0``).

``plan`` runs this for the two event functions of a flight with sign ``s``: the wall ahead,
``g1 = s (W_s - x)`` (``g1' = -s v``, ``g1'' = -s x''``), and the velocity, ``g2 = s v``
(only with friction or forcing).  It jumps to predictions (speculative trials) and keeps a
trial only when the backward windows at it reach back to the certified ends ``C1, C2`` of
the last certified point, so no root is ever skipped; otherwise it retreats to the
certified step.  A predicted root that falls inside its own function's certified
root-free interval (the quadratic model of ``v`` over a long flight often predicts a zero
the certificate has just excluded) is replaced by that interval's end; after an overshoot
the root is bracketed between the certified end and the trial.  A function whose
certificate covers a trial is not analysed there again.  Typical cost: 1-2 evaluations
per impact, 2-3 per turn.

Two shortcuts save rounds and work without touching what certifies (issue 27): ``refine``
moves a prediction made from far away (a segment start) by Newton steps on the float64
flight before it is tried, so that the first trial is usually accepted; and a function
falling steeply towards its predicted root, when that root becomes the next trial, skips
its forward step (``analyze(lazy=True)``, ``_settle``): the backward window at the trial
certifies the way there (after a refuted trial, ``plan`` computes every step again).
"""
from __future__ import annotations

import math

from . import params as p
from . import state as q
from .flight import acceleration_hi, evaluate
from .jit import kernel

EPS = 2.0 ** -52
TINY = 1e-300
#: rounds of one segment after which ``plan`` widens its certified steps by ``_crawl``
CRAWL_ROUNDS = 64
#: ``analyze(..., lazy=True)`` leaves out the forward step of a function falling this steeply
#: (``-g' >= LAZY_SLOPE M est``) towards its predicted root
LAZY_SLOPE = 2.5
#: ``refine`` moves a speculative trial predicted from farther than this (in periods) ...
REFINE_FROM = 1e-2
#: ... by at most this many Newton steps
REFINE_STEPS = 2


@kernel
def _crawl(res, g, g1, g2, M3, H_cap):
    """``res`` of ``analyze`` with its root-free step widened by the cubic minorant
    ``g + g1 h + g2 h^2/2 - M3 h^3/6`` (``g > 0``, the third derivative bounded by ``M3``): each
    of ``min(g1, 0) h``, ``min(g2, 0) h^2/2`` and ``M3 h^3/6`` stays below ``g/3`` under the step,
    so the minorant stays positive.  Where ``g``, ``g'`` and ``g''`` are all near zero together --
    a slip toward a wall a hair away, ``|A| = f`` at its start -- the quadratic certificate's
    steps shrink with ``g`` and the search crawls (the threshold pairs of issue 18 found it: over
    1e5 rounds at a distance of 1e-19); this step is ``(2 g/M3)^(1/3)`` there.  ``plan`` asks
    for it only once a segment has taken ``CRAWL_ROUNDS`` rounds (``plan_crawl``, chosen by
    ``fast.loop``): the usual path, ``plan``, never calls it."""
    safe, est, acc, back = res
    if acc or not g > 0.0:
        return res
    h = ((g + g) / M3) ** (1.0 / 3.0) if M3 > 0.0 else math.inf
    if g1 < 0.0:
        h = min(h, g / (3.0 * -g1))
    if g2 < 0.0:
        h = min(h, math.sqrt((g + g) / (3.0 * -g2)))
    return max(safe, min(0.999 * h, H_cap)), est, acc, back


@kernel
def _forward(g1, g2, M, M3, H_cap, gp, g1sq, sq):
    """The root-free step ``safe`` from ``g = gp > 0`` (module docstring: the local minorant
    on ``[0, H]``, capped by ``H``; ``sq = sqrt(g'^2 + 2 M g)``)."""
    up = g1 > 0.0
    fwd = (g1 + sq) * (1.0 / M) if up else (gp + gp) / max(sq - g1, TINY)
    H = min(max(fwd + fwd, abs(g2) * (0.5 / M3)), H_cap)
    m = max(g2 - M3 * H, -M)
    dl = g1sq - (m + m) * gp
    sl = math.sqrt(max(dl, 0.0))
    if (m < 0.0) or (g1 < 0.0 and dl >= 0.0):
        hl = (g1 + sl) / max(-m, TINY) if up else (gp + gp) / max(sl - g1, TINY)
    else:
        hl = math.inf
    return min(hl, H)


@kernel
def _predict(g, g1, g2, g3, pos, neg):
    """``(est, disc)``: the quadratic model's root nearest to 0 in the crossing direction,
    refined by one safeguarded Newton step on the cubic model (``inf``: none)."""
    disc = g1 * g1 - (g2 + g2) * g
    sd = math.sqrt(max(disc, 0.0))
    if neg:
        est = (g + g) / (sd - g1) if disc >= 0.0 else g / (-g1)
    elif pos and g2 < 0.0:
        est = (g1 + sd) / max(-g2, TINY)
    else:
        est = math.inf
    if est != 0.0 and abs(est) < math.inf:
        d = est
        c = g + d * (g1 + d * (0.5 * g2 + d * (g3 * (1.0 / 6.0))))
        step = c / (g1 + d * (g2 + d * (0.5 * g3)))
        if abs(step) < 0.5 * abs(d):                # a safeguarded refinement
            est = d - step
    return est, disc


@kernel
def analyze(g, g1, g2, g3, M, M3, H_cap, tol, noise, d_acc, fresh, need_back, lazy):
    """``(safe, est, acc, back)`` for one event function at a point (module docstring):
    ``g`` has no root on ``[b, b + safe)``; ``est`` is the predicted root offset (``inf``
    where the model has none); ``acc`` whether ``b + est`` is accepted as the event;
    ``back`` a root-free window ``(b - back, b)`` when ``g > 0`` (only where
    ``need_back``: a speculative trial; else 0), ``-|g'|/M`` when ``g <= 0`` (one crossing
    in ``(b - |g'|/M, b]``) or ``nan`` (no certificate).  ``fresh``: ``g = 0`` at a segment
    start that the flight leaves (``v = 0`` from rest).  With ``g3``, the third derivative,
    the prediction is the quadratic model's root refined by one Newton step on the cubic
    model: a trial then lands within ``~M4 d^4/24`` of the root instead of ``M3 d^3/6``.

    ``lazy``: where ``g`` falls towards a predicted root at ``0 < est < H_cap`` steeply,
    ``-g' >= LAZY_SLOPE M est``, the forward step is left out (``safe = -1``): a trial at that
    root has a backward window (``>= 2 |g'(root)| / M`` or ``|g'(root)| / M``, ``|g'(root)| >=
    |g'| - M est``) that reaches back to ``b`` by itself (``plan`` decides, ``_settle``)."""
    pos = g > 0.0 or fresh
    gp = max(g, 0.0)
    g1sq = g1 * g1
    sq = math.sqrt(g1sq + (2.0 * M) * gp)
    neg = g1 < 0.0
    if pos:
        back = 0.0
        if need_back:
            back = (sq - g1) * (1.0 / M) if neg else (gp + gp) / max(sq + g1, TINY)
    elif neg and g * (2.0 * M) >= -g1sq:
        back = g1 * (1.0 / M)
    else:
        back = math.nan
    est, acc = math.inf, False
    if not fresh:
        est, disc = _predict(g, g1, g2, g3, pos, neg)
        ae = abs(est)
        acc = neg and disc >= 0.0 and ae <= d_acc and M3 * ae * ae * ae <= (6.0 * tol) * (-g1)
        if not acc and g1 <= 0.0 and abs(g) <= noise:
            est, acc = 0.0, True                      # a tangential zero: the event is here
        elif lazy and pos and neg and not acc and 0.0 < est < H_cap and -g1 >= LAZY_SLOPE * M * est:
            return -1.0, est, acc, back
    return (_forward(g1, g2, M, M3, H_cap, gp, g1sq, sq) if pos else 0.0), est, acc, back


@kernel
def _forward_at(g, g1, g2, M, M3, H_cap):
    """``analyze``'s forward step alone (``g > 0``; the same operations, the same step)."""
    g1sq = g1 * g1
    return _forward(g1, g2, M, M3, H_cap, g, g1sq, math.sqrt(g1sq + (2.0 * M) * g))


@kernel
def _settle(b, t_end, r1, r2, lazy1, lazy2, g1, d1, dd1, M1, M1_3, g2, d2, dd2, M2, M2_3):
    """``plan``'s outcomes ``r1, r2`` once a function was analysed lazily (``analyze``): it
    keeps its forward step out only where its predicted root is the next trial and no other
    root is accepted -- the backward window at that trial certifies the way there; otherwise
    it gets its step back (a positive function with ``est > 0``: ``c = b + step``, ``p =
    max(t, c)``, as ``_outcome``).  Compiled once."""
    if lazy1:
        keep = not r2[3] and r1[4] <= (r2[4] if lazy2 else r2[2])
        c = b + (0.0 if keep else _forward_at(g1, d1, dd1, M1, M1_3, t_end - b))
        r1 = (c, r1[1], max(r1[4], c), r1[3], r1[4], True)
        lazy1 = keep
    if lazy2:
        keep = not lazy1 and not r1[3] and r2[4] < r1[2]
        c = b + (0.0 if keep else _forward_at(g2, d2, dd2, M2, M2_3, t_end - b))
        r2 = (c, r2[1], max(r2[4], c), r2[3], r2[4], True)
    return r1, r2


@kernel
def _outcome(b, pos, res, c_old):
    """An analysed function in ``plan``'s terms, ``res = analyze(...)``: ``(c, ok, p, acc,
    t, pos)`` -- its new certified end, whether its backward window reaches its old
    certified end ``c_old`` (a speculative trial skipped nothing), its next trial
    candidate (the predicted root, or the end of the root-free interval where the model
    predicts a root inside it: a function is analysed again only once a trial reaches its
    certified end), the acceptance, the predicted root and whether the function is
    positive at ``b``.  After an overshoot (``g(b) <= 0``) with a certified window, the root lies in
    ``(c, b]`` with ``c = max(b - |g'|/M, c_old)``; a model prediction outside that bracket
    (a quadratic model extrapolated far back) is replaced by the bracket's middle."""
    safe, est, acc, back = res
    lo = b - abs(back)
    t = b + est
    if pos:                     # a predicted root inside the root-free interval: its end
        c = b + safe
        return c, lo <= c_old, (math.inf if est <= 0.0 else max(t, c)), acc, t, pos
    if math.isnan(lo):
        return b, False, t, acc, t, pos
    c = max(lo, c_old)
    p = t if c < t <= b else 0.5 * (c + b)
    return c, lo <= c_old, p, acc, t, pos


@kernel
def bounds(P, av0):
    """``(M1, M1_3, M2, M2_3, d_acc)``: derivative bounds of the segment's event functions.

    Undamped: the scene's (``fast.params``).  Damped (``c > 0``): with start speed
    ``|v0| = av0``, ``|v(t)| <= V = max(|v0|, (F + f)/c)`` on the flight (where ``|v| >
    (F + f)/c``, ``v'`` has the sign of ``-v``), so ``|x''| <= M1 = F + f + c V``,
    ``|x'''| <= M2 = F w + c M1``, ``|v'''| <= M2_3 = F w^2 + c M2``; ``d_acc = 0.5 (eps /
    M2_3)^(1/3)`` (the local model omits ``<= M2_3 d^3 / 6``)."""
    c = P[p.DAMP]
    if c == 0.0:
        return P[p.M1], P[p.M1_3], P[p.M2], P[p.M2_3], P[p.D_ACC]
    Ff = P[p.F] + P[p.FF]
    M1 = max(Ff + max(c * av0, Ff), TINY)
    M2 = P[p.F] * P[p.W] + c * M1
    M2_3 = P[p.F] * P[p.W] * P[p.W] + c * M2
    return M1, M2, M2, M2_3, min(0.5 * math.pow(EPS / M2_3, 1.0 / 3.0), P[p.D_ACC])


@kernel
def plan(P, st, dx, v, cs, sn, t_end, tol):
    """``_plan`` on the usual path (no ``_crawl``).

    ``_plan`` is one compiled function shared by ``plan`` and ``plan_crawl`` (``crawl`` a
    run-time flag), not inlined into each: numba's IR inlining typed its body twice, and the
    copy with ``crawl = True`` took 59% of the engine's whole compile time (35 CPU s cold on
    the 2-core machine; 15 s with one shared body).  The run time is unchanged (one call per
    round, which LLVM sees through) and so is every result, bit for bit: the operations are
    the same in the same order (``fastmath`` is off, ``fast.jit``)."""
    return _plan(P, st, dx, v, cs, sn, t_end, tol, False)


@kernel
def plan_crawl(P, st, dx, v, cs, sn, t_end, tol):
    """``_plan`` for a segment past ``CRAWL_ROUNDS`` rounds: certified steps widened by ``_crawl``."""
    return _plan(P, st, dx, v, cs, sn, t_end, tol, True)


@kernel
def _plan(P, st, dx, v, cs, sn, t_end, tol, crawl):
    """Certify the trial point ``st[TT]``, detect an accepted event, choose the next trial.

    A function whose certified end lies beyond the trial (``TT < C_i``) has no root up to
    there and is not analysed again: its certificate and last prediction stand (unless the
    other function's accepted root lies beyond that end).  Returns ``(code, est)``:
    ``IMPACT`` / ``VZERO`` at ``TT + est``; ``NONE`` with the next trial stored in
    ``st[TT]``; or ``ATWALL`` as "finished": certified at ``t_end`` with no event before.
    """
    b = st[q.TT]
    s = st[q.S]
    av0 = abs(st[q.V0])
    M1, M1_3, M2, M2_3, d_acc = bounds(P, av0)
    a = s * (P[p.F] * cs) - P[p.FF]                  # s x'' = s A - f (- c s v)
    a3 = -s * (P[p.F] * P[p.W]) * sn                 # the rate of s x'': s A' (- c s x'')
    a4 = -s * (P[p.F] * P[p.W] * P[p.W]) * cs        # and its rate: s A'' (- c s x''')
    if P[p.DAMP] > 0.0:
        a = a - P[p.DAMP] * (s * v)
        a3 = a3 - P[p.DAMP] * a
        a4 = a4 - P[p.DAMP] * a3
    h = b - st[q.T0]                                 # for the noise floors only
    spec = st[q.SPEC] != 0.0
    no_v = P[p.F] == 0.0 and P[p.FF] == 0.0          # v constant: no velocity event
    do1, do2 = b >= st[q.C1], b >= st[q.C2] and not no_v
    if do2 and b == st[q.T0] and P[p.DAMP] == 0.0:
        # undamped: |s v(t) - s v0| <= (F/w)|sin wt - sin wt0| + f h <= 2 F/w + f (t_end - t0),
        # so a segment that starts faster than that has no velocity zero before t_end
        margin = s * st[q.V0] - 2.0 * P[p.FW] - P[p.FF] * (t_end - b)
        if margin > 1e-12 * (abs(st[q.V0]) + 2.0 * P[p.FW]):
            st[q.C2], st[q.P2], do2 = math.inf, math.inf, False
    r1 = (st[q.C1], True, st[q.P1], False, math.inf, True)
    r2 = (math.inf, True, math.inf, False, math.inf, True) if no_v else (
        st[q.C2], True, st[q.P2], False, math.inf, True)
    lazy = st[q.NFAIL] == 0.0 and not crawl         # after a refuted trial: every step
    lazy1 = lazy2 = False
    g1 = g2 = 0.0
    for _ in range(2):
        if do1:
            g1 = st[q.D0] - s * dx
            n1 = min((8 * EPS) * (st[q.D0] + av0 * h + (0.5 * M1) * (h * h)), P[p.NOISE1])
            res1 = analyze(g1, -s * v, -a, -a3, M1, M1_3, t_end - b, tol, n1, d_acc, False, spec,
                           lazy)
            if crawl:
                res1 = _crawl(res1, g1, -s * v, -a, M1_3, t_end - b)
            lazy1 = res1[0] < 0.0
            r1 = _outcome(b, g1 > 0.0, res1, st[q.C1])
        if do2:
            g2 = s * v
            n2 = min((8 * EPS) * (av0 + M1 * h), P[p.NOISE2])
            fresh = g2 <= 0.0 and b == st[q.T0] and st[q.V0] == 0.0 and st[q.V0LO] == 0.0
            d2 = max(a, 0.0) if fresh else a
            res2 = analyze(g2, d2, a3, a4, M2, M2_3, t_end - b, tol, n2, d_acc, fresh, spec, lazy)
            if crawl:
                res2 = _crawl(res2, g2, d2, a3, M2_3, t_end - b)
            lazy2 = res2[0] < 0.0
            r2 = _outcome(b, g2 > 0.0 or fresh, res2, st[q.C2])
            if fresh and not r2[0] > b and b < t_end:    # it cannot leave rest in float64
                r2 = (b, True, b, True, b, True)
        # an accepted root beyond the other function's old certified end: analyse that
        # function here too (else the event would wait one round)
        do1 = not do1 and r2[3] and r2[4] > r1[0]
        do2 = not do2 and not no_v and r1[3] and r1[4] > r2[0]
        if not (do1 or do2):
            break
    if lazy1 or lazy2:
        r1, r2 = _settle(b, t_end, r1, r2, lazy1, lazy2, g1, -s * v, -a, M1, M1_3, g2, a, a3, M2,
                         M2_3)
    return _choose(st, b, t_end, r1, r2)


@kernel
def _choose(st, b, t_end, r1, r2):
    """The bookkeeping of ``plan``: speculation, acceptance, the next trial."""
    c1, ok1, p1, acc1, t1, pos1 = r1
    c2, ok2, p2, acc2, t2, pos2 = r2
    cert = st[q.SPEC] == 0.0 or (ok1 and ok2)
    e1 = cert and acc1 and t1 <= min(c2, t_end)
    e2 = cert and acc2 and t2 <= min(c1, t_end) and not (e1 and t1 <= t2)
    st[q.NIT] += 1.0
    st[q.SPEC] = 0.0
    if e2:
        return q.VZERO, t2 - b
    if e1:
        return q.IMPACT, t1 - b
    if cert and pos1 and pos2 and (t_end - b <= 0.0 or min(c1, c2) > t_end):
        return q.ATWALL, 0.0                          # finished: certified through t_end
    pred = min(min(p1, p2), t_end)
    cmin = min(c1, c2)
    if st[q.NFAIL] >= 2.0:
        pred = min(pred, min(cmin, t_end))
    if cert:
        st[q.TT] = pred
        st[q.SPEC] = 1.0 if pred > cmin else 0.0
        st[q.C1], st[q.C2], st[q.P1], st[q.P2] = c1, c2, p1, p2
    else:
        st[q.TT] = min(min(st[q.C1], st[q.C2]), t_end)
        st[q.NFAIL] += 1.0
    return q.NONE, 0.0


@kernel
def refine(P, st, b, t_end):
    """Move the speculative trial ``TT`` that ``plan`` predicted from ``b`` closer to its root.

    A prediction from ``d = TT - b`` away (the cubic model refined by one Newton step) errs by
    about ``|g^(4)| d^4 / (24 |g'|)``: from a segment start (``d`` a good part of a period) far
    more than a trial that ``plan`` accepts (``d_acc``), so the round at ``TT`` would only
    predict again.  Here the predicting function gets up to ``REFINE_STEPS`` Newton steps on
    the exact float64 flight (``fast.flight.evaluate``, no certificate): each squares the
    error, ``e -> |g''| e^2 / (2 |g'|)``; they stop once that is below ``d_acc / 2``, and a step
    is not taken unless it converges (under half the distance before) and stays inside
    ``(C_i, t_end)``.  The result is still only a trial: ``plan`` certifies it like any other
    (its backward windows must reach the certified ends), so no event is skipped; a refined
    trial only saves the round at the unrefined one.  Only where ``d > REFINE_FROM T``."""
    tt = st[q.TT]
    if st[q.SPEC] == 0.0 or not tt < t_end or not tt - b > REFINE_FROM * P[p.T]:
        return
    wall = tt == st[q.P1]
    if not wall and tt != st[q.P2]:
        return
    s = st[q.S]
    lo = max(st[q.C1] if wall else st[q.C2], b)
    span = tt - b
    for _ in range(REFINE_STEPS):
        h = (tt - st[q.T0]) - st[q.T0LO]
        dx, v, cs, sn = evaluate(P, h, st[q.V0], s, st[q.SN0], st[q.CS0])
        a = s * acceleration_hi(P, s, cs, v)                            # s x''
        if wall:
            g, g1, g2 = st[q.D0] - s * dx, -s * v, -a
        else:
            g, g1, g2 = s * v, a, -s * (P[p.F] * P[p.W]) * sn - P[p.DAMP] * a
        if not g1 < 0.0:
            break
        step = g / -g1
        t2 = tt + step
        if not (abs(step) < 0.5 * span and lo < t2 < t_end):
            break
        tt, span = t2, abs(step)
        if abs(g2) * (step * step) <= P[p.D_ACC] * -g1:
            break
    st[q.TT] = tt
    st[q.SPEC] = 1.0 if tt > min(st[q.C1], st[q.C2]) else 0.0
