"""The diffrax peer's event loop in ``jax.numpy`` (how and why: ``peers.jaxdiffrax``).

Imported by the adapter on its first call, never at the suite's import: importing this module
switches JAX to float64 (``jax_enable_x64``) in the process that runs the adapter.

``program(solver)`` is the jitted, vmapped ``run(P, tol, X, V, t_end, max_iter) -> {x, v,
status, n, kinds, t, x_event, v_after, v_before}``: per start the map (NaN unless ``status`` is
``OK``; else ``SOLVER_FAILED`` or ``LOOP_BOUND``), and the event log (``n`` events, their kind
codes into ``KINDS``).  ``P = [F, f, w, l, r, e, c, k]``, ``tol = [rtol, atol]``.
"""
from __future__ import annotations

import functools
import math

import jax

jax.config.update("jax_enable_x64", True)

import diffrax  # noqa: E402  (after float64 is on)
import jax.numpy as jnp  # noqa: E402
import optimistix as optx  # noqa: E402

#: events kept per start (an ``events`` call on a start that needs more raises)
LOG = 512
#: steps of one flight (diffeqsolve's max_steps)
MAX_STEPS = 200_000
#: the event root finder's tolerance (relative and absolute, in t)
ROOT_RTOL = 1e-14
#: the end-of-flight condition is ``s v + SPEED_SHIFT (F + f) / w`` (as heyoka's adapter does):
#: a flight starting at ``v = 0`` would otherwise start the combined condition at 0, and diffrax
#: fires a downward crossing only from a positive value (a wall one step away is then missed)
SPEED_SHIFT = 1e-13
#: the careful user's chatter cut-off (bounce below this many absolute tolerances), as in baseline
CHATTER_ATOLS = 100.0
KINDS = ("impact", "turn", "stick", "slip", "contact", "release", "chatter")
IMPACT, TURN, STICK, SLIP, CONTACT, RELEASE, CHATTER = range(7)
FLIGHT, STUCK, AT_R, AT_L = range(4)
#: a start's outcome
OK, SOLVER_FAILED, LOOP_BOUND = range(3)
TWO_PI = 2 * math.pi


def _field(t, y, args):
    P, s = args
    return jnp.stack([y[1], P[0] * jnp.cos(P[7] * y[0]) * jnp.cos(P[2] * t) - s * P[1] - P[6] * y[1]])


def _to_wall(y, P, s):
    return s * (jnp.where(s > 0, P[4], P[3]) - y[0])


def _first_event(t, y, args, **kw):
    P, s = args
    return jnp.minimum(_to_wall(y, P, s), s * y[1] + SPEED_SHIFT * (P[0] + P[1]) / P[2])


class BracketBisection(optx.Bisection):
    """``optimistix.Bisection`` that stops on the bracket's width alone.  The library's also asks
    ``|g| < atol`` of the same ``atol`` as the width; at a root of ``g`` of slope ~40 (the
    resonance scenes) ``|g|`` one ulp of ``t`` away is 4e-15, its rounding noise about as much,
    and the bisection ran out of its 256 steps (measured: ``fig:resonance/R=0.89/sticking`` at
    Dopri8 rtol 1e-9, a failed solve)."""

    def terminate(self, fn, y, args, options, state, tags):
        return jnp.abs(state.lower - state.upper) < self.atol + self.rtol * jnp.abs(y), optx.RESULTS.successful


EVENT = diffrax.Event(_first_event, BracketBisection(rtol=ROOT_RTOL, atol=ROOT_RTOL, flip=True), direction=False)


def _solve(solver, P, tol, t0, x0, v0, s, t_end, event):
    # a lane that has finished (t0 = t_end) still runs the vmapped body, its result thrown
    # away: an empty interval there would give the bisection an empty bracket, which raises
    t1 = jnp.where(t_end > t0, t_end, t0 + 1.0)
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(_field), solver, t0, t1, None, jnp.stack([x0, v0]), args=(P, s),
        stepsize_controller=diffrax.PIDController(rtol=tol[0], atol=tol[1]), event=event,
        max_steps=MAX_STEPS, adjoint=diffrax.ForwardMode(), throw=False)
    ok = (sol.result == diffrax.RESULTS.successful) | (sol.result == diffrax.RESULTS.event_occurred)
    return sol, ok


def _flight(solver, P, tol, t0, x0, v0, s, t_end):
    """``(t, x, v, hit wall, hit v = 0, ok)`` at the flight's first event (or its end)."""
    sol, ok = _solve(solver, P, tol, t0, x0, v0, s, t_end, EVENT)
    y, hit = sol.ys[-1], sol.event_mask
    hit_wall = hit & (_to_wall(y, P, s) <= s * y[1])
    return sol.ts[-1], y[0], y[1], hit_wall, hit & ~hit_wall, ok


def _crossing(theta0, c, up):
    """The first ``theta >= theta0`` where ``cos`` crosses ``c`` upward (``up``) or downward;
    ``inf`` if ``|c| >= 1`` (never crossed)."""
    a = jnp.arccos(jnp.clip(c, -1.0, 1.0))
    base = jnp.where(up, -a, a)
    theta = base + TWO_PI * jnp.ceil((theta0 - base) / TWO_PI)
    return jnp.where(jnp.abs(c) < 1.0, theta, jnp.inf)


def _passes(theta0, a, b, rising):
    """First ``theta >= theta0`` where ``a cos(theta)`` passes ``b`` upward (``rising``) or downward."""
    c = jnp.where(a != 0, b / jnp.where(a != 0, a, 1.0), jnp.inf)
    return _crossing(theta0, c, (a > 0) == rising)


def release(P, t, x, mode, t_end):
    """``(time, s)`` of the end of a stick or a wall contact at ``x`` from ``t`` (closed form:
    ``|a cos(w t)|`` rising through ``f`` for a stick, ``a cos(w t)`` falling through ``-f`` at
    ``r`` and rising through ``f`` at ``l``, ``a = F cos(k x)``); ``t_end`` if none before it."""
    F, f, w = P[0], P[1], P[2]
    a, theta0 = F * jnp.cos(P[7] * x), w * t
    th = jnp.where(mode == STUCK, jnp.minimum(_passes(theta0, a, f, True), _passes(theta0, a, -f, False)),
                   jnp.where(mode == AT_R, _passes(theta0, a, -f, False), _passes(theta0, a, f, True)))
    te = jnp.minimum(th / w, t_end)
    s_stick = jnp.where(a * jnp.cos(w * te) > 0, 1.0, -1.0)
    return te, jnp.where(mode == STUCK, s_stick, jnp.where(mode == AT_R, -1.0, 1.0))


def _record(c, kind, t, x, v, vb):
    i = c["n"]
    return dict(c, n=i + 1, kinds=c["kinds"].at[i].set(kind, mode="drop"),
                log=tuple(a.at[i].set(b, mode="drop") for a, b in zip(c["log"], (t, x, v, vb))))


def _where(pred, a, b):
    return jax.tree_util.tree_map(lambda u, v: jnp.where(pred, u, v), a, b)


def _after_flight(solver, P, tol, c, t_end):
    """The loop state after the flight from ``c`` and its event (``peers.jaxdiffrax``: per kind).
    A flight without an event leaves ``c`` as it was, marked ``last``: the final flight is
    solved after the loop without an event (``_one``)."""
    F, f, w, l, r, e, k = P[0], P[1], P[2], P[3], P[4], P[5], P[7]
    R = r - l
    atol_x, atol_v = tol[0] * R, tol[0] * jnp.maximum(jnp.maximum(F, f) / w, 1e-300)
    s = c["s"]
    tf, xf, vf, hit_wall, hit_v0, ok = _flight(solver, P, tol, c["t"], c["x"], c["v"], s, t_end)
    Af = F * jnp.cos(k * xf) * jnp.cos(w * tf)
    push = jnp.where(s > 0, Af >= -f, Af <= f)
    chatter = push & ((jnp.abs(vf) <= CHATTER_ATOLS * atol_v)
                      | (vf * vf <= 2 * (jnp.abs(Af) + f) * CHATTER_ATOLS * atol_x))
    at_r, at_l = (xf >= r - 1e-12 * R) & (Af >= -f), (xf <= l + 1e-12 * R) & (Af <= f)
    kind = jnp.where(hit_wall, jnp.where(chatter, CHATTER, IMPACT),
                     jnp.where(s * Af < -f, TURN, jnp.where(at_r | at_l, CONTACT, STICK)))
    moving = (kind == IMPACT) | (kind == TURN)
    wall = jnp.where(hit_wall, jnp.where(s > 0, r, l), jnp.where(at_r, r, l))
    x_new = jnp.where(hit_wall | (kind == CONTACT), wall, xf)
    v_new = jnp.where(kind == IMPACT, -e * vf, 0.0)
    mode_new = jnp.where(moving, FLIGHT, jnp.where(kind == STICK, STUCK, jnp.where(wall == r, AT_R, AT_L)))
    event = (hit_wall | hit_v0) & ok
    moved = _record(dict(c, t=tf, x=x_new, v=v_new, s=jnp.where(moving, -s, 0.0), mode=mode_new), kind, tf,
                    x_new, v_new, vf)
    return _where(event, moved, dict(c, done=True, last=ok, bad=c["bad"] | ~ok))


def _after_rest(P, c, t_end):
    tr, sr = release(P, c["t"], c["x"], c["mode"], t_end)
    moved = _record(dict(c, t=tr, s=sr, mode=FLIGHT), jnp.where(c["mode"] == STUCK, SLIP, RELEASE),
                    tr, c["x"], 0.0, 0.0)
    return _where(tr < t_end, moved, dict(c, t=t_end, done=True))


def _start(P, x0, v0):
    """The loop state at ``t = 0``: the mode and the direction of the first phase."""
    f, l, r = P[1], P[3], P[4]
    A0 = P[0] * jnp.cos(P[7] * x0)
    mode0 = jnp.where(v0 != 0, FLIGHT, jnp.where((x0 >= r) & (A0 >= -f), AT_R, jnp.where(
        (x0 <= l) & (A0 <= f), AT_L, jnp.where(jnp.abs(A0) > f, FLIGHT, STUCK))))
    s0 = jnp.where(v0 > 0, 1.0, jnp.where(v0 < 0, -1.0, jnp.where(A0 > 0, 1.0, -1.0)))
    false = jnp.asarray(False)
    return dict(t=jnp.asarray(0.0), x=x0, v=v0, s=s0, mode=mode0, done=false, last=false, bad=false,
                iters=jnp.asarray(0), n=jnp.asarray(0), kinds=jnp.zeros(LOG, jnp.int32),
                log=tuple(jnp.zeros(LOG) for _ in range(4)))


def _one(solver, P, tol, x0, v0, t_end, max_iter):
    def body(c):
        out = _where(c["mode"] == FLIGHT, _after_flight(solver, P, tol, c, t_end), _after_rest(P, c, t_end))
        return dict(out, iters=c["iters"] + 1)

    c = jax.lax.while_loop(lambda c: ~c["done"] & (c["iters"] < max_iter), body, _start(P, x0, v0))
    # the last flight, solved without an event: with one, diffrax root-finds on every lane of the
    # batch as soon as one lane has an event, and a lane without one then ends at the bisection's
    # approximation of t_end (its result would depend on the other starts)
    sol, ok = _solve(solver, P, tol, c["t"], c["x"], c["v"], c["s"], t_end, None)
    status = jnp.where(c["bad"] | (c["last"] & ~ok), SOLVER_FAILED, jnp.where(c["done"], OK, LOOP_BOUND))
    x = jnp.where(status == OK, jnp.where(c["last"], sol.ys[-1, 0], c["x"]), jnp.nan)
    v = jnp.where(status == OK, jnp.where(c["last"], sol.ys[-1, 1], c["v"]), jnp.nan)
    return dict(x=x, v=v, status=status, n=c["n"], kinds=c["kinds"], t=c["log"][0], x_event=c["log"][1],
                v_after=c["log"][2], v_before=c["log"][3])


def program(solver_name: str):
    """The jitted, vmapped event loop for diffrax's ``solver_name`` (module docstring)."""
    one = functools.partial(_one, getattr(diffrax, solver_name)())
    return jax.jit(jax.vmap(one, in_axes=(None, None, 0, 0, None, None)))


__all__ = ["KINDS", "LOG", "LOOP_BOUND", "OK", "SOLVER_FAILED", "BracketBisection", "program", "release"]
