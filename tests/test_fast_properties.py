"""fast: metamorphic properties (hypothesis): energy balance, half-period symmetry,
semigroup, translation of both walls, the Jacobian against finite differences.

Tolerances come from ``cross_check.tolerances`` (``fast_*``); where a property moves an
input, the tolerance is scaled by ``1 + |Phi'|`` of the state (the conditioning).
"""
import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

import fast
from cross_check.tolerances import tol
from tests.strategies import fast_batches, scenes

N = 24
_GL_X, _GL_W = np.polynomial.legendre.leggauss(30)


def _scene_and_batch(draw_scene, data, vmax=2.0):
    scene = data.draw(draw_scene)
    return scene, data.draw(fast_batches(scene, N, vmax))


def _work_and_distance(scene, x0, v0, log_events, t_end):
    """Work of F cos(w t) and distance over [0, t_end] from the event list, with the
    flight closed form written out here (direct form) and 30-point Gauss-Legendre."""
    F, f, w = scene.float("F"), scene.float("f"), scene.float("omega")
    pts = [(0.0, x0, v0)] + [(e.t, e.x, e.v) for e in log_events]
    kinds = [None] + [e.kind for e in log_events]
    work = dist = 0.0
    for k, (ta, xa, va) in enumerate(pts):
        tb = pts[k + 1][0] if k + 1 < len(pts) else t_end
        if tb <= ta or kinds[k] in ("stick", "contact", "chatter"):
            continue
        tt = 0.5 * (tb - ta) * _GL_X + 0.5 * (tb + ta)
        # direction of motion in this segment: sign of v just after ta
        s = math.copysign(1.0, va) if va != 0 else math.copysign(1.0, F * math.cos(w * ta))
        vt = va + (F / w) * (np.sin(w * tt) - math.sin(w * ta)) - s * f * (tt - ta)
        work += 0.5 * (tb - ta) * np.dot(_GL_W, F * np.cos(w * tt) * vt)
        dist += 0.5 * (tb - ta) * np.dot(_GL_W, np.abs(vt))
    return work, dist


@settings(max_examples=15)
@given(st.data())
def test_energy_balance(data):
    """v(T)^2/2 - v0^2/2 = work of the forcing - f * distance (elastic impacts)."""
    scene, (x, v) = _scene_and_batch(scenes(), data)
    T = scene.period
    log = fast.events(scene, x, v)
    f = scene.float("f")
    t = tol("fast_energy_balance")
    for i in range(x.size):
        evs = log[i]
        if any(e.kind == "chatter" for e in evs):
            continue          # the summed tail's dissipation is not in the event list
        work, dist = _work_and_distance(scene, x[i], v[i], evs, T)
        dE = 0.5 * log.v_end[i] ** 2 - 0.5 * v[i] ** 2
        vmax = max([abs(v[i])] + [abs(e.v_before) for e in evs] + [abs(log.v_end[i])])
        assert abs(dE - (work - f * dist)) <= (t.atol + t.rtol) * (1 + vmax ** 2), (i, dE, work, dist)


def _mirror(scene, x, v):
    return scene.float("l") + scene.float("r") - x, -v


@settings(max_examples=10)
@given(st.data())
def test_half_period_symmetry(data):
    """sigma(x, v) = (l + r - x, -v): sigma o phi(0 -> T) o sigma = phi(T/2 -> 3T/2)."""
    scene, (x, v) = _scene_and_batch(scenes(), data)
    T = scene.period
    xh, vh = fast.flow(scene, x, v, 0.5 * T)
    x3, v3 = fast.flow(scene, x, v, 1.5 * T)
    X, V = fast.stroboscopic_map(scene, *_mirror(scene, xh, vh))
    Xm, Vm = _mirror(scene, X, V)
    J = fast.jacobian(scene, *_mirror(scene, xh, vh))
    _assert_close_scaled(Xm, x3, Vm, v3, J, "fast_metamorphic")


@settings(max_examples=10)
@given(st.data())
def test_semigroup(data):
    scene, (x, v) = _scene_and_batch(scenes(), data)
    X2, V2 = fast.stroboscopic_map(scene, x, v, periods=2)
    Xf, Vf = fast.flow(scene, x, v, 2 * scene.period)
    X1, V1 = fast.stroboscopic_map(scene, x, v)
    _assert_close_scaled(X2, Xf, V2, Vf, fast.jacobian(scene, X1, V1), "fast_metamorphic")


@settings(max_examples=10)
@given(st.data(), st.sampled_from(["0.5", "-1.25", "3"]))
def test_translation_of_both_walls(data, shift):
    scene, (x, v) = _scene_and_batch(scenes(), data)
    a = float(shift)
    moved = scene.replace(l=f"{float(scene.l) + a:.2f}", r=f"{float(scene.r) + a:.2f}")
    xm = np.clip(x + a, moved.float("l"), moved.float("r"))
    X, V = fast.stroboscopic_map(scene, x, v)
    Xm, Vm = fast.stroboscopic_map(moved, xm, v)
    J = fast.jacobian(scene, x, v)
    # moving x by a rounds x + a and the walls: an input change of ~eps (|x| + |a|)
    _assert_close_scaled(Xm - a, X, Vm, V, J, "fast_metamorphic", scale=1 + abs(a))


def _assert_close_scaled(xa, xd, va, vd, J, name, scale=1.0):
    t = tol(name)
    cond = 1 + np.abs(J).max(axis=(-2, -1))
    bound_x = (t.atol + t.rtol * np.abs(xd)) * cond * scale
    bound_v = (t.atol + t.rtol * np.abs(vd)) * cond * scale
    bad = (np.abs(xa - xd) > bound_x) | (np.abs(va - vd) > bound_v)
    assert not bad.any(), list(zip(xa[bad], xd[bad], va[bad], vd[bad], cond[bad]))


@settings(max_examples=8)
@given(st.data())
def test_jacobian_matches_finite_differences(data):
    """Central differences, d = 1e-6, on states whose itinerary is the same at +-d."""
    scene, (x, v) = _scene_and_batch(scenes(), data)
    d = 1e-6
    l, r = scene.float("l"), scene.float("r")
    inside = (x > l + 2 * d) & (x < r - 2 * d)
    x, v = x[inside], v[inside]
    J = fast.jacobian(scene, x, v)
    t = tol("fast_jacobian_fd")
    base = fast.events(scene, x, v).kind
    for j, (dx, dv) in enumerate(((d, 0.0), (0.0, d))):
        Xp, Vp = fast.stroboscopic_map(scene, x + dx, v + dv)
        Xm, Vm = fast.stroboscopic_map(scene, x - dx, v - dv)
        kp = fast.events(scene, x + dx, v + dv).kind
        km = fast.events(scene, x - dx, v - dv).kind
        same = np.array([np.array_equal(base[i], kp[i]) and np.array_equal(base[i], km[i])
                         for i in range(x.size)])
        stick_free = ~np.any(np.isin(base, [fast.KINDS.index(k) for k in ("stick", "contact", "chatter")]), axis=1)
        ok = same & stick_free
        fd = np.stack([(Xp - Xm) / (2 * d), (Vp - Vm) / (2 * d)], axis=-1)
        scale = np.maximum(1, np.abs(J).max(axis=(-2, -1)))
        err = np.abs(fd - J[:, :, j]).max(axis=-1)
        assert np.all(err[ok] <= (t.atol + t.rtol) * scale[ok]), (err[ok].max(), scale[ok])
