"""Phase portraits of the stroboscopic map: orbits, their classes, islands, the area classes.

An orbit ``z_0, z_1 = Phi(z_0), ...`` is put in one of three classes:

* **dissipative**: some iterate lies in ``Omega_dissip`` (the trajectory reaches zero
  velocity within that period, ``fast.zero_velocity``), only when ``f > 0`` (with
  ``f = 0`` a turning point is area-preserving, ``(|A| - f)/(|A| + f) = 1``).  Its
  start belongs to the basin of an attractor: it is left white, and its last iterate
  is drawn as a point of the attractor it converged to.
* **regular** (quasi-periodic, on an invariant curve) or **chaotic**, decided by the
  convergence of weighted Birkhoff averages (Das, Saiki, Sander, Yorke, Nonlinearity
  30 (2017)): with the bump weight ``w(s) = exp(-1/(s(1-s)))`` normalised over ``N``
  iterates, ``WB_N(g) = sum_n w(n/N) g(z_n)`` converges faster than any power of
  ``1/N`` on a smooth invariant curve, but only like ``N^(-1/2)`` on a chaotic orbit.
  The indicator is the number of digits on which the averages over iterates
  ``[0, N)`` and ``[N, 2N)`` agree, relative to the spread of ``g`` on the orbit.
  The observables are ``x`` and ``v^2``: both are continuous across the impact
  identification ``(wall, v) ~ (wall, -v)``, where the map's ``(x, v)`` picture jumps.

Area classes (paper, Fig. fig:fig): ``Omega_pres`` = ``|det Phi'| = 1`` (no zero velocity on
``[0, T]``), ``Omega_dissip`` = ``|det Phi'| < 1``; ``undefined`` where ``Phi'`` is not finite
(grazing).  Everything runs on ``fast`` (imported lazily: this module imports without it).
"""
from __future__ import annotations

import numpy as np

from cross_check.dynamics.periodic import AREA_TOL, find_periodic_points
from cross_check.tolerances import tol


def engine():
    """The float64 engine ``fast`` (imported on first use)."""
    import fast
    return fast


def phi(scene, x, v, periods=1):
    """``Phi^periods`` on a batch as a pair of float arrays."""
    X, V = engine().stroboscopic_map(scene, np.asarray(x, float), np.asarray(v, float), periods=periods)
    return np.asarray(X, float), np.asarray(V, float)


def birkhoff_weights(n):
    """The normalised bump weights ``w(s) = exp(-1/(s (1 - s)))`` at ``s = (j + 1/2)/n``."""
    s = (np.arange(n) + 0.5) / n
    w = np.exp(-1.0 / (s * (1.0 - s)))
    return w / w.sum()


def birkhoff_digits(xs, vs, walls=None):
    """Digits of agreement of weighted Birkhoff averages over the two halves of each orbit.

    ``xs, vs`` have shape ``(n + 1, m)`` (iterates first); the halves are iterates
    ``[0, N)`` and ``[N, 2N)`` with ``N = (n + 1) // 2``.  Returns ``(m,)`` digits:
    ``-log10(max_g |WB_1(g) - WB_2(g)| / spread(g))``, ``inf`` for exact agreement.
    Observables: ``v^2`` and, given ``walls = (l, r)``, ``cos(pi (x - l)/R)`` -- smooth
    functions of the paper's lift ``x = R W(q) + l`` (eq. ``map``): ``cos(pi W(q)) =
    cos(pi q)``, ``v^2 = R^2 q'^2`` -- so the averages see the smooth lifted dynamics,
    not the fold of ``W`` at the walls; without ``walls``, ``x`` itself.
    """
    n2 = (xs.shape[0] // 2) * 2
    if n2 < 20:
        raise ValueError(f"birkhoff_digits: need at least 20 iterates, got {xs.shape[0]}")
    N = n2 // 2
    w = birkhoff_weights(N)[:, None]
    worst = np.zeros(xs.shape[1])
    if walls is None:
        gx = xs[:n2]
    else:
        gx = np.cos(np.pi * (xs[:n2] - walls[0]) / (walls[1] - walls[0]))
    for g in (gx, vs[:n2] ** 2):
        a = (w * g[:N]).sum(0)
        b = (w * g[N:n2]).sum(0)
        spread = g.max(0) - g.min(0)
        scale = np.maximum(spread, 1e-12 * np.maximum(1.0, np.abs(g).max(0)))
        worst = np.maximum(worst, np.abs(a - b) / scale)
    with np.errstate(divide="ignore"):
        return -np.log10(worst)


def _step(scene, x, v, zero_velocity=True, steps=None):
    """One period for a flat batch: ``(x1, v1, zero_velocity)`` (one engine pass when it offers one).
    ``zero_velocity=False``: the map alone, ``zero_velocity`` all False (issue 33: fast's map with
    its Jacobian costs 1.33 times the map alone under position forcing, and gives the same map bit
    for bit; a portrait of a frictionless scene, which needs no ``Omega_dissip``, 32 -> 25 CPU s).
    With ``zero_velocity``, fast's map and zero-velocity flags in one pass without the Jacobian
    (``fast.map_and_zero_velocity``: 81 states of a drawn scene, 60 periods at ``steps = 32``,
    0.65 -> 0.41 CPU s, the same numbers bit for bit), else the Jacobian's pass where an engine
    offers no such pass.  ``steps``: ``fast``'s ``steps_per_period`` (position forcing; None: its
    default map)."""
    fe = engine()
    opt = {} if steps is None else {"steps_per_period": steps}
    if not zero_velocity:
        x1, v1 = fe.stroboscopic_map(scene, x, v, **opt)
        return np.asarray(x1, float), np.asarray(v1, float), np.zeros(np.shape(x), bool)
    if hasattr(fe, "map_and_zero_velocity"):
        x1, v1, zv = fe.map_and_zero_velocity(scene, x, v, **opt)
        return np.asarray(x1, float), np.asarray(v1, float), np.asarray(zv, bool)
    if hasattr(fe, "map_and_jacobian"):
        x1, v1, _J, zv = fe.map_and_jacobian(scene, x, v, **opt)
        return np.asarray(x1, float), np.asarray(v1, float), np.asarray(zv, bool)
    x1, v1 = fe.stroboscopic_map(scene, x, v, **opt)
    return np.asarray(x1, float), np.asarray(v1, float), np.asarray(fe.zero_velocity(scene, x, v), bool)


def run_orbits(scene, x0, v0, n, track_dissip=None, steps=None):
    """Iterate a batch of starts ``n`` times.

    Returns ``(xs, vs, first_dissip)``: iterates of shape ``(n + 1, m)`` and, per
    orbit, the first index ``k`` with ``z_k`` in ``Omega_dissip`` (``n + 1`` if none
    in ``z_0 .. z_{n-1}``).  ``track_dissip`` defaults to ``f > 0``; when False every
    orbit gets ``n + 1``.  A dissipative orbit that has reached a fixed point
    (``Phi(z) = z`` exactly: after sticking the state repeats bit for bit) is frozen
    there instead of being iterated further (it would not move).  ``steps``: ``fast``'s
    ``steps_per_period`` under position forcing (None: the default map; ``_step``).
    """
    x = np.asarray(x0, float).ravel().copy()
    v = np.asarray(v0, float).ravel().copy()
    if track_dissip is None:
        track_dissip = scene.float("f") > 0
    xs = np.empty((n + 1, x.size))
    vs = np.empty_like(xs)
    xs[0], vs[0] = x, v
    first = np.full(x.shape, n + 1)
    live = np.ones(x.shape, bool)
    for k in range(n):
        idx = np.nonzero(live)[0]
        if idx.size:
            x1, v1, zv = _step(scene, x[idx], v[idx], track_dissip, steps)
            if track_dissip:
                new = zv & (first[idx] > n)
                first[idx[new]] = k
                frozen = (first[idx] <= k) & (x1 == x[idx]) & (v1 == v[idx])
                live[idx[frozen]] = False
            x[idx], v[idx] = x1, v1
        xs[k + 1], vs[k + 1] = x, v
    return xs, vs, first


def classify_orbits(xs, vs, first_dissip, threshold, walls=None):
    """Per orbit: 'dissip' (reaches ``Omega_dissip``), 'regular' or 'chaotic' (Birkhoff digits)."""
    digits = birkhoff_digits(xs, vs, walls)
    n1 = xs.shape[0]
    cls = np.where(digits >= threshold, "regular", "chaotic").astype(object)
    cls[first_dissip < n1] = "dissip"
    return cls, digits


def line_starts(z_from, z_to, m):
    """``m`` starts on the segment from ``z_from`` to ``z_to`` (end points excluded)."""
    s = (np.arange(m) + 1.0) / (m + 1)
    return (z_from[0] + s * (z_to[0] - z_from[0]), z_from[1] + s * (z_to[1] - z_from[1]))


def grid_starts(window, mx, mv, l, r):
    """An ``mx`` by ``mv`` cell-centred grid of starts in ``window`` clipped to ``[l, r]``."""
    x0, x1 = max(window[0], l), min(window[1], r)
    xs = x0 + (np.arange(mx) + 0.5) / mx * (x1 - x0)
    vs = window[2] + (np.arange(mv) + 0.5) / mv * (window[3] - window[2])
    X, V = np.meshgrid(xs, vs)
    return X.ravel(), V.ravel()


def no_impact_segment(scene):
    """End points ``(x_a, x_b)`` of the segment ``v = 0`` of fixed points without impacts, or None.

    With ``f = 0`` the motion from rest at ``t = 0`` is ``x(t) = x_0 + (F/omega^2)(1 - cos omega t)``
    (paper eq. ``noimpacts``), which stays off the walls iff ``l <= x_0 <= r - 2F/omega^2``.
    """
    F, w = scene.float("F"), scene.float("omega")
    l, r = scene.float("l"), scene.float("r")
    top = r - 2 * F / w ** 2
    return (l, top) if top > l else None


def unstable_manifold(scene, z, J, n_seeds=200, n_iter=40, delta=1e-6, sign=(1, -1)):
    """Points of the unstable manifold of a saddle fixed point ``z`` with ``D Phi = J``.

    Seeds fill a fundamental domain ``z + delta lambda_u^s e_u``, ``s`` in ``[0, 1)``,
    on both branches (``sign``); each is iterated ``n_iter`` times.  Returns
    ``(xs, vs, first_dissip)`` as ``run_orbits`` (columns: seeds).
    """
    lam, vec = np.linalg.eig(np.asarray(J, float))
    iu = int(np.argmax(np.abs(lam)))
    lu, eu = float(np.real(lam[iu])), np.real(vec[:, iu])
    if abs(lu) <= 1:
        raise ValueError(f"unstable_manifold: J has no multiplier outside the unit circle ({lam})")
    s = np.arange(n_seeds) / n_seeds
    d = delta * np.abs(lu) ** s
    x0 = np.concatenate([z[0] + sg * d * eu[0] for sg in sign])
    v0 = np.concatenate([z[1] + sg * d * eu[1] for sg in sign])
    l, r = scene.float("l"), scene.float("r")
    return run_orbits(scene, np.clip(x0, l, r), v0, n_iter)


# ----------------------------------------------------------------- islands and periodic points
def regular_threshold():
    """Birkhoff digits above which an orbit counts as regular (tolerance ``fig_birkhoff_regular``)."""
    return -np.log10(tol("fig_birkhoff_regular").rtol)


def orbit_classes(scene, xs, vs, first):
    """``classify_orbits`` with the scene's walls and the tolerance table's threshold."""
    return classify_orbits(xs, vs, first, regular_threshold(), (scene.float("l"), scene.float("r")))


def periodic_points(scene, window, newton_seeds, k=1, grid=True):
    """Period-``k`` orbits (``PeriodicPoint``) seeded in ``window``, flagged ``dissip`` when the
    orbit reaches zero velocity.  Newton seeds: an ``newton_seeds = (mx, mv)`` grid over
    ``window`` (unless ``grid`` is False) and ``4 mx`` seeds on ``v = 0`` (the ``t = 0`` section
    of the time-reversal symmetric orbits, ``f = 0``); orbits whose representative leaves the
    window are dropped.
    """
    # a grid of seeds plus a line on v = 0 (the t = 0 section of time-reversal symmetric orbits, f = 0)
    mx, mv = newton_seeds
    gx = window[0] + (np.arange(mx) + 0.5) / mx * (window[1] - window[0])
    gv = window[2] + (np.arange(mv) + 0.5) / mv * (window[3] - window[2])
    X, V = np.meshgrid(gx, gv)
    lx = window[0] + (np.arange(4 * mx) + 0.5) / (4 * mx) * (window[1] - window[0])
    if not grid:
        X, V = X[:0], V[:0]
    seeds = (np.concatenate([X.ravel(), lx]), np.concatenate([V.ravel(), np.zeros_like(lx)]))
    span = window[3] - window[2]
    found = find_periodic_points(scene, period=k, seeds=seeds, v_range=(window[2] - span / 2, window[3] + span / 2))
    orbits = [o for o in found if window[0] <= o.x <= window[1] and window[2] <= o.v <= window[3]]
    for o in orbits:
        o.dissip = bool(np.asarray(engine().zero_velocity(scene, o.points[:, 0], o.points[:, 1])).any())
    return orbits


def nonsticking(orbits, kind):
    """The orbits of type ``kind`` (``saddle`` includes flip saddles) that never reach zero velocity."""
    match = (lambda o: o.kind in ("saddle", "flip saddle")) if kind == "saddle" else (lambda o: o.kind == kind)
    return [o for o in orbits if not o.dissip and match(o)]


def centre_line_starts(scene, centre, window, m):
    """Probes of an island: ``m // 2`` starts on each side of ``centre`` on the line ``v = v_c``,
    at geometrically growing distances ``1e-5 R`` .. the window edge or wall (ordered outwards)."""
    l, r = scene.float("l"), scene.float("r")
    c = np.asarray(centre, float)
    R = r - l
    xs = []
    for edge in (min(r, window[1]), max(l, window[0])):
        span = edge - c[0]
        if abs(span) <= 2e-5 * R:
            continue
        xs.append(c[0] + np.sign(span) * np.geomspace(1e-5 * R, 0.999 * abs(span), max(2, m // 2)))
    x = np.clip(np.concatenate(xs), l, r) if xs else np.array([c[0]])
    return x, np.full(x.shape, c[1])


def island_box(xs, vs, cls, c, pad=0.15):
    """Bounding box of the invariant curves nested around ``c``: for the probe columns of a
    run (``centre_line_starts``' order, each side outwards), the contiguous regular ones."""
    side = np.sign(xs[0] - c[0])
    keep = []
    for sg in (1, -1):
        cols = np.nonzero(side == sg)[0]
        cols = cols[np.argsort(np.abs(xs[0, cols] - c[0]))]
        for j in cols:
            if cls[j] != "regular":
                break
            keep.append(j)
    if not keep:
        h = 1e-5
        return (c[0] - h, c[0] + h, c[1] - h, c[1] + h)
    bx, bv = xs[:, keep], vs[:, keep]
    wx = max(bx.max() - bx.min(), 1e-9)
    wv = max(bv.max() - bv.min(), 1e-9)
    return (bx.min() - pad * wx, bx.max() + pad * wx, bv.min() - pad * wv, bv.max() + pad * wv)


def island_window(scene, centre, n_line, n_iter, pad=0.15):
    """Bounding box of the invariant curves nested around ``centre`` (Birkhoff-regular, contiguous)."""
    l, r = scene.float("l"), scene.float("r")
    x0, v0 = centre_line_starts(scene, centre, (l, r, -np.inf, np.inf), n_line)
    xs, vs, first = run_orbits(scene, x0, v0, n_iter)
    cls, _ = orbit_classes(scene, xs, vs, first)
    return island_box(xs, vs, cls, np.asarray(centre, float), pad)


def saddle_centre_pair(scene, win, newton_seeds):
    """The non-sticking centre and the saddle closest to it (the pair born in the fold)."""
    fps = periodic_points(scene, win, newton_seeds)
    cen, sad = nonsticking(fps, "centre"), nonsticking(fps, "saddle")
    if not cen or not sad:
        raise RuntimeError(f"no non-sticking centre/saddle in {win} for {scene!r}: {len(cen)}, {len(sad)}")
    return (*min(((c, s) for c in cen for s in sad), key=lambda cs: np.abs(cs[0].points[0] - cs[1].points[0]).sum()),
            fps)


# ------------------------------------------------------------------------------ area classes
def area_classes(scene, x, v, steps=None):
    """``(labels, det)``: per state ``"pres"`` (|det Phi'| = 1), ``"dissip"`` (< 1) or ``"undefined"``.

    ``steps``: first on ``fast``'s coarse map (its ``steps_per_period``; position forcing,
    closed-form flights ignore it), for a picture that needs the classes, not ``Phi'``: a state
    whose coarse ``det`` is clearly in a class (``claim_unit_det_clear``: within a quarter of
    ``AREA_TOL`` of 1, or far below 1) keeps it, every other one (near a class's edge, or
    ``Phi'`` undefined) is classed again on the default map.  So the coarse map decides only
    where the default map decides the same way, unless the two ``det`` differ by more than
    ~1e-3 (``tests/test_verify_portrait.py``)."""
    x, v = np.atleast_1d(np.asarray(x, float)), np.atleast_1d(np.asarray(v, float))
    det = _det(scene, x, v, steps)
    if steps is not None:
        clear = tol("claim_unit_det_clear")
        again = ~((np.abs(np.abs(det) - 1) <= clear.atol) | (np.abs(det) < 1 - clear.rtol))
        if again.any():
            det[again] = _det(scene, x[again], v[again], None)
    labels = np.full(x.shape, "undefined", dtype=object)
    labels[np.abs(np.abs(det) - 1) <= AREA_TOL] = "pres"
    labels[np.abs(det) < 1 - AREA_TOL] = "dissip"
    return labels, det


def _det(scene, x, v, steps):
    """``det Phi'`` per state (NaN where ``Phi'`` is undefined), on ``fast``'s map with ``steps``
    steps per period (None: the default)."""
    if steps is None:
        J = engine().jacobian(scene, x, v)
    else:
        J = engine().map_and_jacobian(scene, x, v, steps_per_period=steps)[2]
    J = np.asarray(J, float).reshape(x.shape + (2, 2))
    with np.errstate(invalid="ignore"):
        det = np.linalg.det(np.where(np.isfinite(J), J, 0.0))
    return np.where(np.isfinite(J).all(axis=(-1, -2)), det, np.nan)


def dissipative_invariance(scene, x, v):
    """Counts for ``Phi(Omega_dissip) subset Omega_dissip`` on the given states (paper, Fig. fig:regs).

    Membership is by definition (``fast.zero_velocity``: the velocity vanishes somewhere on
    ``[0, T]``).  Returns a dict: ``n``, ``n_dissip``, ``n_violations`` (dissip states whose image is
    not dissip), the violating states, and ``n_det_mismatch`` (states where the definition and
    the ``|det Phi'| < 1`` test disagree, grazing excluded).
    """
    x, v = np.atleast_1d(np.asarray(x, float)), np.atleast_1d(np.asarray(v, float))
    zero = np.asarray(engine().zero_velocity(scene, x, v), bool)
    X, V = phi(scene, x, v)
    zero_img = np.asarray(engine().zero_velocity(scene, X, V), bool)
    labels, _ = area_classes(scene, x, v)
    defined = labels != "undefined"
    viol = zero & ~zero_img
    return {"n": int(x.size), "n_dissip": int(zero.sum()), "n_violations": int(viol.sum()),
            "violations": list(zip(x[viol].tolist(), v[viol].tolist())),
            "n_det_mismatch": int((defined & (zero != (labels == "dissip"))).sum())}
