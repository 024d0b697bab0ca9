"""Constructed events in bulk: many starts whose first event is known, built independently of
both integrators (issue 13: 1e4 cases in the default test run, 1e6 in a ``slow`` test).

``cross_check.agreement.hardcases`` builds a handful of cases at 60 digits with mpmath; this module
builds them by the thousand in float64 numpy on the same idea: choose the state *at* the
event -- time ``t*``, position, velocity, flight sign ``s`` -- and evaluate the base model's
closed-form flight backwards at ``t = 0`` (``h = t - t*``)::

    v(t) = v* + (F/w)(sin wt - sin wt*) - s f h
    x(t) = x* + v* h + (F/w^2)(cos wt* - cos wt - w h sin wt*) - s f h^2 / 2.

A case is kept only if its forward flight from ``t = 0`` has no event before ``t*`` (the
certificate of ``_no_earlier_event``): the velocity function ``g2 = s v`` stays positive on
``[0, t*)`` -- on a grid of spacing ``D``, a function with ``|g''| <= M`` lies above its chord
minus ``M D^2 / 8``, so samples above that margin exclude a root between them; on the last
interval either the chord argument holds or ``g2`` decreases into a zero at ``t*`` (``s A -
f + F w D < 0``, since ``|A'| <= F w``) -- and the wall function ``g1 = s (W_s - x)`` likewise,
its last interval before an impact at ``t*`` being covered by ``g1' = -g2 < 0``.

Kinds (``KINDS``), for the base model (restitution 1, no damping) with ``F > 0``:

* ``crossing_pair``: an impact at ``t*`` while the flight decelerates towards the wall
  (``s A - f < 0``), with speed ``|s A - f| delta``: without the wall the wall function would
  cross back ``2 delta`` later (``delta`` log-uniform in [1e-13, 1e-1]); ``tangency``: the same
  with ``delta = 0`` (the wall touched at zero speed); ``impact_at_T``: an impact at exactly
  ``t* = T`` (a root at the period's end);
* ``turn``: ``v = 0`` at ``t*`` mid-gap with ``s A(t*) = -f (1 + delta)`` (``delta = 0``: on the
  stick-slip boundary ``|A| = f``; ``delta`` log-uniform in [1e-10, 1]); ``stick``: ``|A(t*)|
  = f (1 - delta)``;
* ``chatter``: a start just off a wall the force pushes into (``s A > f``), whose bounces
  accumulate well within the push: impacts, then a ``chatter`` event.

Each case carries its *margin* -- the distance of its event from its regime's boundary in
the event function's units: a crossing pair's penetration ``|s A - f| delta^2 / 2``, a turn's
or stick's ``f delta`` of force -- and ``in_band``: whether the margin is within
``BAND_FACTOR`` times what the rounding of the start to float64 moves (``start_error``).
Inside the band the construction does not decide the kind (a float64 integrator may take
either side); outside it the constructed event must be found: the same kind, first, at
``t*`` within the start's rounding propagated to the event (``time_tol``).
"""
from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from reference.scene import Scene

EPS = 2.0 ** -52
KINDS = ("crossing_pair", "tangency", "impact_at_T", "turn", "stick", "chatter")
#: the first event each kind must show (the kinds of ``reference.integrator``)
FIRST_EVENT = {"crossing_pair": "impact", "tangency": "impact", "impact_at_T": "impact",
               "turn": "turn", "stick": "stick", "chatter": "impact"}
#: grid of the certificate on ``[0, t*]``
SAMPLES = 128
#: a margin within this many times the start's rounding effect is in the band
BAND_FACTOR = 64.0
#: the event time must match ``t*`` to this many times the start's rounding effect (plus a
#: few ulp of ``t*``): the rounding moves the event by at most that, fast's own event
#: location adds a few ulp (measured: at most 3e-3 of ``BAND_FACTOR`` times it)
TIME_FACTOR = 4.0
#: candidates drawn per round, per requested case (most survive the certificate)
_OVERDRAW = 3
_MAX_ROUNDS = 50
_BARREN_ROUNDS = 4


@dataclass
class Cases:
    """Constructed starts (float64) with their known first event (module docstring)."""

    kind: np.ndarray          # index into KINDS
    x: np.ndarray
    v: np.ndarray
    t_star: np.ndarray        # the constructed event (chatter: an upper bound of the accumulation)
    margin: np.ndarray
    in_band: np.ndarray
    time_tol: np.ndarray

    def __len__(self):
        return self.x.size

    def select(self, mask):
        return Cases(*(getattr(self, f.name)[mask] for f in fields(self)))

    @staticmethod
    def join(parts):
        return Cases(*(np.concatenate([getattr(c, f.name) for c in parts])
                       for f in fields(Cases)))


def _params(scene: Scene):
    if any(scene.has(e) for e in ("restitution", "damping", "position_forcing")) or not scene.has("forcing"):
        raise ValueError("construct: scene must be the base model with forcing (F > 0, "
                         "restitution 1, no damping, no position forcing: construct_position builds "
                         f"those), got {scene!r}")
    return tuple(scene.float(k) for k in ("F", "f", "omega", "l", "r"))


def flight(scene: Scene, t_star, x_star, v_star, s, t):
    """The closed-form flight through ``(t*, x*, v*)`` with sign ``s``: ``(x, v)`` at ``t``."""
    F, f, w, _, _ = _params(scene)
    h = t - t_star
    sw = np.sin(w * t_star)
    v = v_star + (F / w) * (np.sin(w * t) - sw) - s * f * h
    x = x_star + v_star * h + (F / w ** 2) * (np.cos(w * t_star) - np.cos(w * t) - w * h * sw)
    return x - s * f * h * h / 2, v


def _no_earlier_event(scene, t_star, x_star, v_star, s):
    """The certificate of the module docstring: no event of the flight before ``t*``."""
    F, f, w, l, r = _params(scene)
    u = np.linspace(0.0, 1.0, SAMPLES + 1)[None, :]
    x, v = flight(scene, t_star[:, None], x_star[:, None], v_star[:, None], s[:, None],
                  t_star[:, None] * u)
    D = t_star / SAMPLES
    g1 = s[:, None] * (np.where(s > 0, r, l)[:, None] - x)
    g2 = s[:, None] * v
    floor1, floor2 = (F + f) * D * D / 8, F * w * D * D / 8
    decreasing = s * (F * np.cos(w * t_star)) - f + F * w * D < 0
    last2 = ((g2[:, -2] > floor2) & (g2[:, -1] > floor2)) | (decreasing & (g2[:, -1] >= 0))
    ok = np.all(g2[:, :-1] > floor2[:, None], axis=1) & last2
    ok &= np.all(g1[:, :-1] > floor1[:, None], axis=1)
    ok &= (x[:, 0] >= l) & (x[:, 0] <= r)
    return ok


def start_error(scene, x0, v0, t):
    """``(dx, dv)``: the move of the flight at time ``t`` caused by rounding the start (and by
    the float64 construction): a few ulp of the largest terms of the flight formulas."""
    F, f, w, l, r = _params(scene)
    dv = 4 * EPS * (np.abs(v0) + 2 * F / w + f * t)
    dx = 4 * EPS * (np.abs(x0) + max(abs(l), abs(r)) + np.abs(v0) * t + 2 * F / w ** 2
                    + F * t / w + f * t * t) + dv * t
    return dx, dv


def phase_times(scene, c, rng):
    """Random times in ``(0, T]`` where ``|cos w t| = c`` (one of the four phases of a
    period, drawn at random) and the sign of ``cos w t`` there."""
    w = scene.float("omega")
    alpha = np.arccos(np.clip(c, 0.0, 1.0))
    pick = rng.integers(0, 4, c.size)
    phase = np.choose(pick, [alpha, np.pi - alpha, np.pi + alpha, 2 * np.pi - alpha])
    phase = np.where(phase <= 0, 2 * np.pi, phase)
    return phase / w, np.where((pick == 0) | (pick == 3), 1.0, -1.0)


def _wall_candidates(scene, rng, n, kind):
    F, f, w, l, r = _params(scene)
    T = 2 * np.pi / w
    s = rng.choice([-1.0, 1.0], n)
    t = np.full(n, T) if kind == "impact_at_T" else rng.uniform(0.05, 1.0, n) * T
    a = s * F * np.cos(w * t) - f                       # s x'' at t*
    if kind == "impact_at_T":
        speed = 10 ** rng.uniform(-2, 0.5, n) * (F / w + f * T + (r - l) / T)
        keep, margin = np.ones(n, bool), np.full(n, np.nan)
    else:
        delta = 10 ** rng.uniform(-13, -1, n) if kind == "crossing_pair" else np.zeros(n)
        keep = a < -0.02 * (F + f)                      # clearly decelerating into the wall
        speed, margin = np.abs(a) * delta, np.abs(a) * delta * delta / 2
    return t[keep], np.where(s > 0, r, l)[keep], (s * speed)[keep], s[keep], margin[keep], speed[keep]


def _velocity_candidates(scene, rng, n, kind):
    F, f, w, l, r = _params(scene)
    delta = 10 ** rng.uniform(-10, 0, n)
    if kind == "turn":
        delta[rng.random(n) < 0.1] = 0.0                # on the stick-slip boundary exactly
    c = f * (1 + delta) / F if kind == "turn" else np.minimum(f * (1 - delta) / F, 1.0)
    t, sign_cos = phase_times(scene, c, rng)
    keep = (c <= 1) & (t > 0.02 * 2 * np.pi / w)
    if kind == "stick":
        delta = np.where(c >= 1, 1 - F * np.abs(np.cos(w * t)) / f, delta)   # F < f: any phase
    s = -sign_cos if kind == "turn" else rng.choice([-1.0, 1.0], n)
    x = l + (r - l) * rng.uniform(0.1, 0.9, n)
    return (t[keep], x[keep], np.zeros(keep.sum()), s[keep], (f * delta)[keep],
            np.abs(s * F * np.cos(w * t) - f)[keep])


def _chatter_candidates(scene, rng, n):
    """Starts at ``x0 = r - h`` with a small speed ``u`` either way while ``A = F cos wt > f``
    pushes into ``r``; the frozen-force accumulation estimate (``fast.modes`` has the same
    closed form, derived independently in ``reference.chatter``) must lie within the first
    fifth of the push."""
    F, f, w, l, r = _params(scene)
    if not F > f:
        return (np.zeros(0),) * 6
    h = (r - l) * 10 ** rng.uniform(-9, -4, n)
    a, b = F + f, F - f
    u = rng.uniform(-1, 1, n) * np.sqrt(2 * b * h)
    v1 = np.sqrt(u * u + 2 * b * h)                     # speed at the first impact
    t1 = (v1 - u) / b
    rho = np.sqrt(b / a)
    t_inf = t1 + v1 * (1 / a + 1 / np.sqrt(a * b)) / (1 - rho)
    push = np.arccos(f / F) / w
    keep = t_inf < 0.2 * push
    return t_inf[keep], (r - h)[keep], u[keep], np.ones(keep.sum()), (push - t_inf)[keep], v1[keep]


def _build(scene, rng, n, kind):
    if kind == "chatter":
        t, x0, v0, s, margin, speed = _chatter_candidates(scene, rng, n)
        ok = np.ones(t.size, bool)
        band = np.zeros(t.size, bool)
        dx, dv = start_error(scene, x0, v0, t)
        tol = t.copy()                                  # chatter: an upper bound, checked apart
    else:
        wall = kind in ("crossing_pair", "tangency", "impact_at_T")
        gen = _wall_candidates if wall else _velocity_candidates
        t, x_s, v_s, s, margin, slope = gen(scene, rng, n, kind)
        x0, v0 = flight(scene, t, x_s, v_s, s, np.zeros(t.size))
        ok = _no_earlier_event(scene, t, x_s, v_s, s) & np.isfinite(x0) & np.isfinite(v0)
        dx, dv = start_error(scene, x0, v0, t)
        F, w = scene.float("F"), scene.float("omega")
        dt = (dx if wall else dv) / np.maximum(slope, 1e-300)
        band = ~(margin > BAND_FACTOR * (dx if wall else F * w * dt))  # nan margin: in band
        tol = TIME_FACTOR * dt + 8 * EPS * t
    k = np.full(t.size, KINDS.index(kind))
    return Cases(k, x0, v0, t, margin, band, tol).select(ok)


def construct(scene: Scene, n: int, *, seed: int = 0, kinds=KINDS) -> Cases:
    """Up to ``n`` cases of each kind in ``kinds``, drawn from ``default_rng(seed)``: the same
    cases on every run.  Turns and sticking need friction, chatter ``F > f > 0``; a kind whose
    constructions keep failing (e.g. an impact at exactly ``T`` as a single flight, where the
    forcing's swing exceeds the gap) yields what ``_MAX_ROUNDS`` rounds of draws give, and
    none after ``_BARREN_ROUNDS`` barren ones.  (Position forcing: ``construct_position``.)"""
    check_count(n)
    F, f, _, _, _ = _params(scene)

    def admitted(kind):
        return not ((kind in ("turn", "stick", "chatter") and f == 0) or (kind in ("turn", "chatter") and F <= f))

    return draw(scene, n, seed, kinds, _build, admitted)


def check_count(n):
    if not (isinstance(n, int) and n >= 1):
        raise ValueError(f"construct: n must be an integer >= 1, got {n!r}")


def draw(scene, n, seed, kinds, build, admitted) -> Cases:
    """The rounds of draws of ``construct``: ``build(scene, rng, count, kind)`` gives certified
    cases of a kind, ``admitted(kind)`` whether the scene has it at all."""
    rng = np.random.default_rng(seed)
    out = []
    for kind in kinds:
        if kind not in KINDS:
            raise ValueError(f"construct: unknown kind {kind!r}; known: {', '.join(KINDS)}")
        if not admitted(kind):
            continue
        got, have = [], 0
        for rounds in range(1, _MAX_ROUNDS + 1):
            part = build(scene, rng, _OVERDRAW * n, kind)
            got.append(part)
            have += len(part)
            if have >= n or (have == 0 and rounds >= _BARREN_ROUNDS):
                break
        out.append(Cases.join(got).select(np.arange(min(n, have))))
    return Cases.join(out)


def first_events(scene, cases: Cases, run_ends=("chatter",), chunk: int = 50_000):
    """fast's first event (kind, time) for each constructed start, and the time of the first
    event of a kind in ``run_ends`` (the end of a chatter run; ``inf``: none): ``verify``'s input."""
    import fast

    names = np.array(list(fast.KINDS) + [""])
    ends = [fast.KINDS.index(k) for k in run_ends]
    kinds, times, stops = [], [], []
    for i in range(0, len(cases), chunk):
        log = fast.events(scene, cases.x[i:i + chunk], cases.v[i:i + chunk])
        k = log.kind.reshape(-1, log.kind.shape[-1]) if log.kind.size else np.full((log.n.size, 1), -1)
        t = log.t.reshape(k.shape) if log.t.size else np.full(k.shape, np.inf)
        kinds.append(names[k[:, 0]])
        times.append(np.where(k[:, 0] >= 0, t[:, 0], np.inf))
        stops.append(np.where(np.isin(k, ends), t, np.inf).min(axis=1))
    return np.concatenate(kinds), np.concatenate(times), np.concatenate(stops)


def verify(cases: Cases, first_kind, first_t, chatter_t):
    """Check an integrator's events against the constructed ones.

    ``first_kind`` (strings), ``first_t``: each start's first event (``""`` and ``inf`` where
    there is none); ``chatter_t``: the time of its first ``chatter`` event (``inf``: none).
    Returns ``{"missed": idx, "invented": idx, "wrong_time": idx, "band": n_band}``: outside the
    band the constructed event must come first, of its kind, at ``t*`` within ``time_tol`` (a
    chatter case: impacts and turns first, then its accumulation before the push ends);
    everywhere no event may come before ``t* - time_tol``.
    """
    kinds = np.array(KINDS)[cases.kind]
    expect = np.array([FIRST_EVENT[k] for k in kinds])
    first_kind, first_t = np.asarray(first_kind), np.asarray(first_t, float)
    chat = kinds == "chatter"
    early = ~chat & (first_t < cases.t_star - cases.time_tol)
    out = ~cases.in_band & ~chat
    missed = out & (first_kind != expect)
    wrong_t = out & ~missed & (np.abs(first_t - cases.t_star) > cases.time_tol)
    chat_missed = chat & ~(np.asarray(chatter_t) <= cases.t_star + cases.margin)
    return {"missed": np.flatnonzero(missed | chat_missed), "invented": np.flatnonzero(early),
            "wrong_time": np.flatnonzero(wrong_t), "band": int(cases.in_band.sum())}
