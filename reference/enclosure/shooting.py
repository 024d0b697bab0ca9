"""The parametric Krawczyk operator in multiple-shooting form (``boxes.prove_periodic_box``).

The period ``[phase T, (phase + k) T]`` is cut at sections ``s_0 = phase < s_1 < ... < s_n``
(every ``T / PIECES``, away from the events of the midpoint orbit); the unknowns are the states
``z_i`` at the sections, the equations ``F_i = P_i(z_i) - z_{i+1} = 0`` (``z_n = z_0``) with
``P_i`` the map from ``s_i T`` to ``s_{i+1} T``.  With ``C = (mid DF(z~, p~))^-1`` and the
boxes ``Z_i = z~_i +- rho_i``,

    K = z~ - C F(z~, p) + (I - C DF(Z, B)) (Z - z~),

``DF`` the block matrix (``P_i'`` on the diagonal, ``-I`` beside it) enclosed over ``Z x B``.
If ``K`` lies in the interior of ``Z`` then, for every ``p`` of the box ``B``, ``F_p`` has
exactly one zero in ``Z`` -- one periodic orbit whose states at the sections lie in the
``Z_i`` -- and it lies in ``K`` (Krawczyk's theorem at each ``p``: ``K`` contains the point
operator's image for every ``p``).  Pieces of half a period wrap far less than a whole period;
``C F(z~, p)`` is enclosed in mean-value form in ``p``,

    C F(z~, p) in C F(z~, p~) + (C F_p(z~, B)) (B - p~),

(``F_p`` from ``sensitivity``, the product ``C F_p`` keeping the cancellations a ball
``F(z~, B)`` loses), and ``DF`` in mean-value form in ``(z, p)`` (``centred``).  ``rho``
starts at ``2 |C F(z~, B)|`` and grows by epsilon-inflation (``rho <- 2 |K - z~|``) at most
``INFLATIONS`` times.

Uniqueness is the shooting one (one orbit through the ``Z_i``); ``unique_in_point`` says
whether it also holds in ``K_0`` alone (every orbit from ``K_0`` provably passes through the
``Z_i``).  The monodromy is the product of the pieces' ``P_i'`` over the ``K_i`` (the orbit's
states), so its trace and determinant hold for every ``p``.
"""
from __future__ import annotations

from fractions import Fraction

import mpmath
from flint import arb, arb_mat

import reference
from reference.enclosure.balls import BallModel, from_mpf, from_number, parameter, to_mpf
from reference.enclosure.maps import enclose_map
from reference.enclosure.params import PARAMS
from reference.enclosure.sensitivity import PARAMETERS
from reference.jacobian import mat_mul

#: Epsilon-inflations of the state boxes before the proof gives up.
INFLATIONS = 6
#: Sections are multiples of T / SECTION_GRID at least one grid step from every event.
SECTION_GRID = 64
#: Pieces per period (sections every T / PIECES): half periods, one impact each for the
#: paper's symmetric orbits.  ``MORE_PIECES`` is the second try of a box that fails with them
#: (a strongly hyperbolic orbit: short pieces keep each piece's derivative tame; measured on
#: x2 at w^2 R/F = 5: 191 sub-boxes instead of more than 1024).
PIECES, MORE_PIECES = 2, 8


def _vec(values):
    return arb_mat([[a] for a in values])


def _identity(N):
    return arb_mat([[arb(1) if i == j else arb(0) for j in range(N)] for i in range(N)])


def _radii(radii) -> str:
    return ", ".join(f"{r:.1e}" for r in radii)


def cuts(phase, periods, times, pieces=PIECES):
    """The sections (units of ``T``): ``phase``, then every ``1 / pieces`` of a period that is
    more than ``1 / SECTION_GRID`` away from every event time (``times``, units of ``T``),
    then ``phase + periods``."""
    margin = Fraction(1, SECTION_GRID)
    out = [phase]
    for k in range(1, int(pieces * periods)):
        s = phase + Fraction(k, pieces)
        if all(abs(s - e) > margin for e in times):
            out.append(s)
    return out + [phase + periods]


def krawczyk(z, head, C, DF, rho):
    """``(K, inside)``: ``K = z - head + (I - C DF) (Z - z)`` for ``Z = z +- rho`` (``DF``
    enclosing the derivative over ``Z``), and whether it lies in the interior of ``Z``."""
    N = len(z)
    tail = ((_identity(N) - C * DF) * _vec([arb(0, r) for r in rho])).entries()
    K = [z[k] - head[k, 0] + tail[k] for k in range(N)]
    return K, all(arb(z[k], rho[k]).contains_interior(K[k]) for k in range(N))


def inflate(z, head, C, jacobian, floor):
    """The Krawczyk test with epsilon-inflation: ``Z = z +- rho``, ``rho`` from
    ``2 |head| + floor``, ``K = z - head + (I - C DF(Z)) (Z - z)`` (``head`` encloses
    ``C F(z, p)`` for every parameter, ``jacobian(rho)`` encloses ``DF`` over ``Z`` and the
    parameters, or says why it cannot), ``rho <- max(2 |K - z|, rho)`` at most ``INFLATIONS``
    times.  ``(K, rho, None)`` once ``K`` lies in the interior of ``Z`` (then, for every
    parameter, ``F`` has exactly one zero in ``Z``, and it lies in ``K``), else
    ``(None, rho, reason)``."""
    N = len(z)
    rho = tried = [(2 * abs(head[k, 0]) + floor[k]).upper() for k in range(N)]
    for _ in range(INFLATIONS + 1):
        tried = rho
        DF = jacobian(rho)
        if isinstance(DF, str):
            return None, rho, DF
        K, inside = krawczyk(z, head, C, DF, rho)
        if inside:
            return K, rho, None
        rho = [max((2 * abs(K[k] - z[k])).upper(), rho[k]) for k in range(N)]
        if not all(g.is_finite() for g in rho):
            break
    return None, tried, (f"K(Z) is not inside Z after {INFLATIONS} inflations (radii "
                         f"{_radii(float(r) for r in tried)}): the box is too wide for the contraction")


class Shooting:
    """One multiple-shooting proof over ``box`` around the midpoint orbit through ``z`` (module
    docstring).  ``prove(fail, done)`` returns ``fail(reason, radii)`` or ``done(...)``."""

    def __init__(self, box, mid, z, periods, phase, prec, enc_mid, pieces=PIECES):
        self.box, self.mid, self.periods, self.prec = box, mid, periods, prec
        varying = [name for name in PARAMS if box.width(name) > 0]
        self.names = tuple(varying) if all(n in PARAMETERS for n in varying) else ()
        T = 2 * arb.pi() / BallModel(mid).w
        times = [Fraction((ev.t / T).mid().str(30, radius=False)) for ev in enc_mid.events]
        self.cuts = cuts(phase, Fraction(periods), times, pieces)
        self.z = [z]
        for s in self.cuts[1:-1]:
            enc = enclose_map(mid, z[0], z[1], periods=s - phase, phase=phase, prec=prec, max_prec=prec)
            self.z.append([enc.phi[0].mid(), enc.phi[1].mid()])
        self.n = len(self.z)
        self.hint = None

    def piece(self, i, X, V, xr=0, vr=0, names=(), scene=None):
        """``P_i`` enclosed over ``(X +- xr, V +- vr)`` and the box (or ``scene``)."""
        s, e = self.cuts[i], self.cuts[i + 1]
        return enclose_map(self.box if scene is None else scene, X, V, x_radius=xr, v_radius=vr,
                           periods=e - s, phase=s - (s.numerator // s.denominator), prec=self.prec,
                           max_prec=self.prec, parameters=names, centred=True)

    def _flat(self):
        return [c for zi in self.z for c in zi]

    def _jacobian(self, encs):
        """The block matrix ``DF``: ``P_i'`` on the diagonal blocks, ``-I`` right of them."""
        N = 2 * self.n
        rows = [[arb(0)] * N for _ in range(N)]
        for i, enc in enumerate(encs):
            j = 2 * ((i + 1) % self.n)
            for a in range(2):
                for b in range(2):
                    rows[2 * i + a][2 * i + b] += enc.jacobian[a][b]
                rows[2 * i + a][j + a] -= 1
        return arb_mat(rows)

    def head(self, C, centre):
        """An enclosure of ``C F(z~, p)`` for every ``p`` of the box (module docstring); sets
        ``hint``, the parameter whose spread weighs most (where a split helps most)."""
        n = self.n
        if not self.names or any(c.dparams is None for c in centre):
            res = [centre[i].phi[a] - self.z[(i + 1) % n][a] for i in range(n) for a in range(2)]
            return C * _vec(res)
        at_mid = [self.piece(i, *self.z[i], scene=self.mid) for i in range(n)]
        if not all(c.proved for c in at_mid):
            return None
        res = [at_mid[i].phi[a] - self.z[(i + 1) % n][a] for i in range(n) for a in range(2)]
        Dp = arb_mat([[centre[i].dparams[j][a] for j in range(len(self.names))]
                      for i in range(n) for a in range(2)])
        dp = _vec([parameter(self.box, name) - parameter(self.mid, name) for name in self.names])
        CD = C * Dp
        weight = [max(float((abs(CD[k, j]) * abs(dp[j, 0])).upper()) for k in range(2 * n))
                  for j in range(len(self.names))]
        self.hint = self.names[max(range(len(weight)), key=weight.__getitem__)]
        return C * _vec(res) + CD * dp

    def prove(self, fail, done):
        n, flat = self.n, self._flat()
        centre = [self.piece(i, *self.z[i], names=self.names) for i in range(n)]
        bad = next((c for c in centre if not c.proved), None)
        if bad is not None:
            return fail(f"the itinerary at the centre state is not proved the same for every "
                        f"parameter of the box: {bad.reason}", ())
        try:
            C = self._jacobian(centre).mid().inv().mid()
        except ZeroDivisionError:
            return fail("DF is singular at the centre: the fixed point is not isolated (a family, "
                        "or the fold itself)", ())
        head = self.head(C, centre)
        if head is None:
            return fail("the residual at the midpoint parameters is not proved", ())
        floor = [(abs(c) + 1) * arb(2) ** (-self.prec // 2) for c in flat]

        def jacobian(rho):
            encs = [self.piece(i, *self.z[i], rho[2 * i], rho[2 * i + 1]) for i in range(n)]
            bad = next((e for e in encs if not e.proved), None)
            if bad is not None:
                return (f"the itinerary is not proved the same on the state boxes of radii "
                        f"{_radii(float(r) for r in rho)} for every parameter of the box: {bad.reason}")
            return self._jacobian(encs)

        K, rho, why = inflate(flat, head, C, jacobian, floor)
        if K is None:
            return fail(why, tuple(float(r) for r in rho))
        return self._classified(K, rho, fail, done)

    def _classified(self, K, rho, fail, done):
        """The pieces over the ``K_i`` (the orbit's states, for every ``p``): the monodromy
        ``P_{n-1}' ... P_0'``, the itinerary, whether uniqueness holds in ``K_0`` alone."""
        tight = [self.piece(i, K[2 * i].mid(), K[2 * i + 1].mid(), K[2 * i].rad(), K[2 * i + 1].rad())
                 for i in range(self.n)]
        bad = next((t for t in tight if not t.proved), None)
        if bad is not None:     # K_i lies in Z_i, where it was proved: should not happen
            return fail(f"the pieces over K are not proved: {bad.reason}", ())
        J = tight[0].jacobian
        for enc in tight[1:]:
            J = mat_mul(enc.jacobian, J)
        kinds = [e.kind for enc in tight for e in enc.events]
        return done(K, rho, J, kinds, self.cuts[:-1], self._chain(rho, tight))

    def _chain(self, rho, tight):
        """Whether every orbit from ``K_0`` passes through the ``Z_i`` (``W_1 = P_0(K_0)`` in
        ``Z_1``, ``W_{i+1} = P_i(W_i)`` in ``Z_{i+1}``): then a fixed point of ``Phi^k`` in
        ``K_0`` is a zero of the shooting equations in ``Z``, of which there is one."""
        flat, W = self._flat(), tight[0].phi
        for i in range(1, self.n):
            if not all(arb(flat[2 * i + a], rho[2 * i + a]).contains(W[a]) for a in range(2)):
                return False
            if i + 1 < self.n:
                enc = self.piece(i, W[0].mid(), W[1].mid(), W[0].rad(), W[1].rad())
                if not enc.proved:
                    return False
                W = enc.phi
        return True


#: event kinds after which the motion rests (sticking, wall contact) until the next event
RESTS = frozenset({"stick", "contact", "chatter"})


def rest_stretches(kinds, at_rest) -> list:
    """For the stretches between ``0``, the events of ``kinds`` and the end: whether each is a
    rest -- after a kind of ``RESTS``, or from the start if the motion starts at rest
    (``at_rest``) and its first event ends a rest (a slip or a release; none: it rests)."""
    first = at_rest and (not kinds or kinds[0] in ("slip", "release"))
    return [first] + [k in RESTS for k in kinds]


def quiet_middle(times, rests):
    """The middle of the longest stretch between consecutive ``times`` that is not a rest
    (``rests``, :func:`rest_stretches`), or of the longest stretch if all are.  A section in a
    rest puts the fixed point at ``v = 0``, where no box of starts has one itinerary (half of it
    starts moving the other way): issue 33, an unseen scene's four period-1 orbits that stick
    (``F=1.072 f=0.0075 omega=1.332 l=0.21 r=3.56 wavenumber=0.8216 restitution=0.6``)
    failed every rung there, "the start's velocity encloses 0", 7 CPU s each."""
    spans = [(b - a, (a + b) / 2) for a, b in zip(times, times[1:])]
    moving = [sp for sp, rest in zip(spans, rests) if not rest]
    return max(moving or spans)[1]


def section(scene, x, v, periods, prec):
    """``(phase, x, v)``: the section ``t = phase T`` (a multiple of ``T / SECTION_GRID``) in
    the middle of the longest quiet stretch of flight (:func:`quiet_middle`) of the orbit
    through ``(x, v)`` at ``t = 0`` over ``periods`` periods, and the state there.  The stretch may lie in a later period ``j``: the
    state is then the orbit's at ``(j + phase) T``, i.e. the state at ``phase T`` of the orbit
    shifted by ``j T`` (the forcing has period ``T``), whose events are away from the section.
    One choice for the point proofs (``orbits.prove_periodic``) and the box proofs (``boxes``):
    a box there has one itinerary."""
    dps = int(prec / 3.33) + 12
    with mpmath.workdps(dps):
        T = 2 * mpmath.pi / scene.mpf("omega")
        x = min(max(to_mpf(from_number(x)), scene.mpf("l")), scene.mpf("r"))    # a state on a wall, rounded out
        v = to_mpf(from_number(v))
        log = reference.trajectory(scene, x, v, periods * T, dps=dps)
        times = [mpmath.mpf(0)] + [e.t for e in log] + [periods * T]
        mid = quiet_middle(times, rest_stretches([e.kind for e in log], v == 0))
        ticks = int(mpmath.floor(SECTION_GRID * mid / T))
        phase = Fraction(ticks % SECTION_GRID, SECTION_GRID)
        if ticks == 0:
            return phase, from_mpf(x), from_mpf(v)
        state = reference.trajectory(scene, x, v, T * ticks / SECTION_GRID, dps=dps)
        return phase, from_mpf(state.x_end), from_mpf(state.v_end)
