"""The certificates of ``reference.enclosure.certify`` refuse false statements (issue 24).

A proof checker is trusted only once it has been seen to say no.  Each test poses a false
(or undecidable) statement on a *test double* of the motion interface: ``Closed`` gives the
derivative stack ``[g, g', g'', ...]`` of a closed-form function (a polynomial with exact
rational coefficients, or ``exp``), evaluated in Arb on a point or a whole interval -- the
contract of ``reference.enclosure.motion`` (a motion has ``stack(u)``; an event function is
a linear form of it).  So the zeros are known exactly:

* exclusion (``certify.exclude``: ``g > 0`` on ``(lo, hi]``) must refuse a zero pair just
  inside either end (``g`` positive at both ends), a zero that the centre value and slope of
  the piece hide and only the second-order (Lagrange) term reveals, a remainder as tight as
  Taylor's theorem allows, a double zero (tangency), a structural zero left downward, and a
  box of starts of which only some have a zero;
* the Krawczyk root (``certify.root``) must refuse a ball with two zeros (or return a
  uniqueness ball holding one of them only), a function with no zero, and a slope that
  encloses 0; and its enclosure must contain the closed-form zero.

Each false statement has a true twin one step away that the same call proves: the refusals
are the certificate's, not a prover that says no to everything.  Last, the real motions'
stacks (``motion.Flight``, ``motion.Rest``) are checked to be what the certificates assume: each
entry the derivative of the one before (mean value theorem on short intervals).
"""
from __future__ import annotations

from fractions import Fraction

import mpmath
import pytest
from flint import arb, ctx

from reference.enclosure import certify
from reference.enclosure.balls import from_fraction, from_mpf, workprec
from reference.enclosure.certify import Unproved
from reference.enclosure.motion import EventFunction

PREC = 320


class Closed:
    """A motion with a closed-form event function: ``stack(u) = [g(u), g'(u), ...]``.

    ``coeffs`` are the polynomial's coefficients, lowest first (rationals, or arb balls for a
    box of starts: the function is then uncertain as the start state of a box is);
    ``exp_sign``: add ``exp(exp_sign u)`` (a transcendental term whose derivatives are
    ``exp_sign^k exp(exp_sign u)``).  Horner's rule on a ball encloses the range.
    """

    DEPTH = 5

    def __init__(self, coeffs, exp_sign=0):
        self.coeffs = [c if isinstance(c, arb) else from_fraction(Fraction(c)) for c in coeffs]
        self.exp_sign = exp_sign

    @staticmethod
    def _derive(coeffs):
        return [k * c for k, c in enumerate(coeffs)][1:]

    def stack(self, u):
        out, coeffs = [], self.coeffs
        for k in range(self.DEPTH):
            value = arb(0)
            for c in reversed(coeffs):
                value = value * u + c
            if self.exp_sign:
                value += self.exp_sign ** k * (self.exp_sign * u).exp()
            out.append(value)
            coeffs = self._derive(coeffs)
        return out


def poly_from_roots(roots, lead=1):
    """Coefficients (lowest first) of ``lead * prod (u - z)`` (exact rationals)."""
    coeffs = [Fraction(lead)]
    for z in roots:
        z = Fraction(z)
        shifted = [Fraction(0)] + coeffs                      # u * p
        coeffs = [a - z * b for a, b in zip(shifted, coeffs + [Fraction(0)])]
    return coeffs


def g(order=0):
    """The event function ``g = stack[0]`` with ``order`` structural zeros at ``u = 0``."""
    return EventFunction("g", 0, 1, 0, order)


def ball(value):
    return from_fraction(Fraction(value))


def exclude(motion, lo, hi, order=0):
    return certify.exclude(motion, g(order), ball(lo), ball(hi), "test")


# --- exclusion ---------------------------------------------------------------------------
DELTAS = (Fraction(1, 2 ** 20), Fraction(1, 2 ** 60))


@pytest.mark.parametrize("delta", DELTAS, ids=["2^-20", "2^-60"])
@pytest.mark.parametrize("end", ["left", "right"])
def test_a_zero_pair_just_inside_either_end_is_not_excluded(end, delta):
    """``g = (u - z1)(u - z2)`` is positive at both ends of ``[1, 3]`` and negative between
    two zeros a hair inside one end; moved a hair outside, the same pair is excluded."""
    lo, hi = Fraction(1), Fraction(3)
    inside = (lo + delta, lo + 2 * delta) if end == "left" else (hi - 2 * delta, hi - delta)
    outside = (lo - 2 * delta, lo - delta) if end == "left" else (hi + delta, hi + 2 * delta)
    with workprec(PREC):
        false = Closed(poly_from_roots(inside))
        assert false.stack(ball(lo))[0] > 0 and false.stack(ball(hi))[0] > 0
        with pytest.raises(Unproved, match="g (may vanish|not excluded)"):
            exclude(false, lo, hi)
        assert exclude(Closed(poly_from_roots(outside)), lo, hi) > 0


@pytest.mark.parametrize("end", ["left", "right"])
def test_a_sign_change_just_inside_either_end_is_not_excluded(end):
    """A simple zero ``2^-50`` inside an end (the function's sign at that end is wrong)."""
    lo, hi, d = Fraction(0), Fraction(1), Fraction(1, 2 ** 50)
    coeffs = poly_from_roots([lo + d]) if end == "left" else poly_from_roots([hi - d], lead=-1)
    with workprec(PREC):
        with pytest.raises(Unproved):
            exclude(Closed(coeffs), lo, hi)


def _hidden(slope):
    """``g(c + d) = 1 + slope d - 6 d^2 + 6 d^4`` on the piece ``c +- 1``, ``c = 2``: ``g(c) = 1``,
    ``g(c) - |g'(c)| r = 1 - |slope| > 0``, ``g(c +- 1) = 1 +- slope > 0``, yet
    ``g(c + d) = 1 + slope d - 1.5 < 0`` at ``d^2 = 1/2``: only the second-order term
    (``g''(c) = -12``) shows the zero."""
    c = Fraction(2)
    # expand in u = c + d: d = u - c
    d_powers = [[Fraction(1)], poly_from_roots([c])]
    for _ in range(3):
        p, q = d_powers[-1], d_powers[1]
        prod = [Fraction(0)] * (len(p) + len(q) - 1)
        for i, a in enumerate(p):
            for j, b in enumerate(q):
                prod[i + j] += a * b
        d_powers.append(prod)
    weights = {0: Fraction(1), 1: Fraction(slope), 2: Fraction(-6), 4: Fraction(6)}
    coeffs = [Fraction(0)] * 5
    for k, wk in weights.items():
        for i, a in enumerate(d_powers[k]):
            coeffs[i] += wk * a
    return coeffs


@pytest.mark.parametrize("slope", ["0", "1/4", "-3/4"])
def test_a_zero_hidden_from_centre_value_and_slope_is_not_excluded(slope):
    with workprec(PREC):
        motion = Closed(_hidden(Fraction(slope)))
        c, r = ball(2), arb(1)
        g0, g1 = motion.stack(c)[0], motion.stack(c)[1]
        assert g0 + g1 * arb(0, r) > 0                               # first order: positive
        assert motion.stack(ball(1))[0] > 0 and motion.stack(ball(3))[0] > 0
        assert motion.stack(ball(2) + arb(2).sqrt() / 2)[0] < 0        # and yet a zero
        with pytest.raises(Unproved):
            exclude(motion, 1, 3)


@pytest.mark.parametrize("a, proved", [("3/4", False), ("1/2 + 1/2**40", False), ("5/4", True)])
def test_the_remainder_is_as_tight_as_taylor_allows_and_no_tighter(a, proved):
    """``g = a - (u - 1)^2`` on ``[0, 2]`` (one piece, ``r = 1``, ``g'' = -2``): the Lagrange
    bound ``g >= a - 2 r^2/2 = a - 1`` is sharp at the ends.  ``a < 1``: zeros at
    ``1 +- sqrt(a)`` inside, so no remainder smaller than ``g'' r^2/2`` may be used (with half
    of it, ``a = 3/4`` and ``a`` just above ``1/2`` would pass); ``a = 5/4``: proved in one piece."""
    value = Fraction(eval(a, {}, {}))
    with workprec(PREC):
        motion = Closed([value - 1, 2, -1])
        if proved:
            assert exclude(motion, 0, 2) == 1
        else:
            with pytest.raises(Unproved):
                exclude(motion, 0, 2)


@pytest.mark.parametrize("z", ["1", "1/3", "2**-30"])
def test_a_double_zero_is_never_excluded(z):
    """``g = (u - z)^2 (1 + u^2)``: a tangency at ``z``, positive elsewhere."""
    z = Fraction(eval(z, {}, {}))
    coeffs = poly_from_roots([z, z])
    coeffs = [a + b for a, b in zip(coeffs + [0, 0], [0, 0] + coeffs)]   # times (1 + u^2)
    with workprec(PREC):
        with pytest.raises(Unproved, match="tangency|near-tangency"):
            exclude(Closed(coeffs), Fraction(-1, 2), 2)
        # the same function lifted by 2^-40 has no zero: excluded
        lifted = [coeffs[0] + Fraction(1, 2 ** 40)] + coeffs[1:]
        assert exclude(Closed(lifted), Fraction(-1, 2), 2) > 0


@pytest.mark.parametrize("order, roots", [
    (1, [0, Fraction(1, 2 ** 30)]),                   # g = u (u - d): g'(0) = -d < 0
    (2, [0, 0, Fraction(1, 2 ** 30)]),                # g = u^2 (u - d): g''(0) = -2 d < 0
    (1, [0, Fraction(1, 4), Fraction(1, 2)]),         # g'(0) = 1/8 > 0, a dip on (1/4, 1/2)
])
def test_a_structural_zero_that_leaves_downward_is_not_excluded(order, roots):
    """``g^(k)(0) = 0`` for ``k < order`` (a structural zero), but ``g`` turns negative right
    after it or dips below 0 later: ``g > 0`` on ``(0, 1]`` is false.  The true twin, the
    zeros mirrored to ``u <= 0``, is proved."""
    with workprec(PREC):
        with pytest.raises(Unproved):
            exclude(Closed(poly_from_roots(roots)), 0, 1, order=order)
        twin = Closed(poly_from_roots([-z for z in roots]))
        assert exclude(twin, 0, 1, order=order) > 0


def test_a_box_of_starts_of_which_some_have_a_zero_is_refused():
    """``g = (u - 1)^2 - p`` for every ``p`` of the ball ``[-2^-60, 2^-60]`` (a box of starts):
    two zeros for ``p > 0``, none for ``p < 0``; ``g > 0`` for every start is false."""
    with workprec(PREC):
        p = arb(0, arb(2) ** -60)
        motion = Closed([1 - p, -2, 1])
        with pytest.raises(Unproved):
            exclude(motion, 0, 2)
        with pytest.raises(Unproved):
            certify.root(motion, g(), ball(1), ball(0), "test")


# --- Krawczyk roots ------------------------------------------------------------------------
def _zeros_in(interval, zeros):
    return [z for z in zeros if interval.contains(ball(z))]


#: gaps between two zeros; ``3/4 64^-k``: the first ball that contracts (radii ``64^-j / 4``,
#: ``certify.RHO_STEP``) has its image's radius ``2 rho^2 / gap`` just below ``gap / 2``, so a
#: uniqueness ball reported wider than the Krawczyk image would reach the other zero
GAPS = [Fraction(1, 1000), Fraction(3, 4 * 64 ** 2), Fraction(3, 4 * 64 ** 5), Fraction(1, 2 ** 100)]


@pytest.mark.parametrize("gap", GAPS, ids=["1e-3", "3/4 64^-2", "3/4 64^-5", "2^-100"])
@pytest.mark.parametrize("where", ["between", "at the first", "at the second"])
def test_two_zeros_never_share_a_uniqueness_ball(gap, where):
    """``g = (u - 1)(u - 1 - gap)``: a guess between or at the zeros.  ``root`` either refuses
    or returns a uniqueness ball ``wide`` with one zero only, and ``tight`` holding it."""
    zeros = [Fraction(1), 1 + gap]
    guess = {"between": 1 + gap / 2, "at the first": Fraction(1), "at the second": 1 + gap}[where]
    with workprec(PREC):
        motion = Closed(poly_from_roots(zeros))
        try:
            wide, tight = certify.root(motion, g(), ball(guess), ball(0), "test")
        except Unproved:
            return
        assert len(_zeros_in(wide, zeros)) == 1, (wide, gap)
        assert _zeros_in(tight, zeros) == _zeros_in(wide, zeros) and wide.contains(tight)


@pytest.mark.parametrize("gap", [Fraction(1, 1000), Fraction(1, 2 ** 40)], ids=["1e-3", "2^-40"])
def test_the_krawczyk_operator_rejects_a_ball_with_two_zeros(gap):
    """On a ball ``H`` holding both zeros, ``K(H)`` never lies inside ``H`` (it would prove a
    unique zero), whatever the preconditioner ``Y`` (Krawczyk's theorem holds for any ``Y``)."""
    with workprec(PREC):
        motion = Closed(poly_from_roots([1, 1 + gap]))
        for rho in (gap, 2 * gap, 100 * gap):
            H = arb(ball(1 + gap / 2), ball(rho))
            for Y in (arb(1) / ball(gap), -arb(1) / ball(gap), arb(1), arb(-1), arb(1) / ball(rho)):
                assert not H.contains_interior(certify._krawczyk(motion, g(), H, Y.mid()))


@pytest.mark.parametrize("coeffs, exp_sign, guess", [
    ([1, 0, 1], 0, "1/2"),             # 1 + u^2: no real zero, a minimum at 0
    ([1, 1], 0, "1/2"),                # 1 + u: its only zero is below lo = 0
    ([1], 1, "3"),                     # 1 + exp(u): no zero at all, slope > 0
])
def test_a_function_without_a_zero_near_the_guess_is_refused(coeffs, exp_sign, guess):
    with workprec(PREC):
        motion = Closed(coeffs, exp_sign)
        with pytest.raises(Unproved, match="Krawczyk|slope"):
            certify.root(motion, g(), from_fraction(Fraction(guess)), ball(0), "test")


@pytest.mark.parametrize("z", ["1", "1/3"])
def test_a_slope_enclosing_zero_at_the_zero_is_refused(z):
    """``g = (u - z)^2``: a double zero (a grazing or tangency): no Krawczyk ball exists."""
    z = Fraction(eval(z, {}, {}))
    with workprec(PREC):
        motion = Closed(poly_from_roots([z, z]))
        with pytest.raises(Unproved, match="slope|Krawczyk"):
            certify.root(motion, g(), ball(z).mid(), ball(0), "test")
        # -(u - z)^2 + tiny: two zeros 2^-80 apart around z; refuse, or prove one of them
        twin = Closed(poly_from_roots([z - Fraction(1, 2 ** 80), z + Fraction(1, 2 ** 80)], lead=-1))
        try:
            wide, _ = certify.root(twin, g(), ball(z).mid(), ball(0), "test")
        except Unproved:
            return
        assert len(_zeros_in(wide, [z - Fraction(1, 2 ** 80), z + Fraction(1, 2 ** 80)])) == 1


def _omega():
    """``W(1)``, the zero of ``exp(-u) - u`` (mpmath's Lambert W)."""
    with mpmath.workdps(200):
        return mpmath.lambertw(1).real


@pytest.mark.parametrize("name, coeffs, exp_sign, guess, exact", [
    ("u^3 - 2", [-2, 0, 0, 1], 0, "5/4", lambda: mpmath.cbrt(2)),
    ("exp(-u) - u", [0, -1], -1, "1/2", _omega),
    ("2 - u^2 near its zero sqrt 2", [2, 0, -1], 0, "7/5", lambda: mpmath.sqrt(2)),
])
def test_the_root_enclosure_contains_the_closed_form_zero(name, coeffs, exp_sign, guess, exact):
    with workprec(PREC):
        wide, tight = certify.root(Closed(coeffs, exp_sign), g(), from_fraction(Fraction(guess)),
                                   ball(0), "test")
        with mpmath.workdps(200):
            z = exact()
        # the closed form at 200 digits is within 10^-198 of the zero: far inside the
        # precision of the enclosure (2^-320 ~ 5e-97), so an enclosure shrunk below its
        # midpoint's own error misses it
        assert tight.overlaps(from_mpf(z) + arb(0, arb(10) ** -198)), (name, tight, z)
        assert wide.contains(tight) and float(tight.rad()) < 1e-80


def test_a_box_of_zeros_is_enclosed_whole():
    """``g = u - p`` for every ``p`` in ``[1 - 2^-70, 1 + 2^-70]``: the zero moves with the
    start; the enclosure must hold it for *every* ``p``, i.e. both ends of the ball."""
    with workprec(PREC):
        p = arb(1, arb(2) ** -70)
        wide, tight = certify.root(Closed([-p, 1]), g(), ball(1), ball(0), "test")
        assert tight.contains(p.lower()) and tight.contains(p.upper())
        assert float(tight.rad()) < 2 ** -69


def test_precision_is_untouched():
    before = ctx.prec
    with workprec(PREC):
        with pytest.raises(Unproved):
            exclude(Closed(poly_from_roots([1, 1])), 0, 2)
    assert ctx.prec == before


# --- the motions' derivative stacks (the contract the certificates rely on) ----------------
from reference.enclosure import motion as motion_module  # noqa: E402
from reference.enclosure.balls import BallModel, span  # noqa: E402
from reference.scene import Scene  # noqa: E402

STACK_SCENES = [
    Scene(F=1, f="0.3", omega=1, l=0, r=20),
    Scene(F=1, f="0.2", omega=1, l=0, r=1, damping="0.5"),
    Scene(F=1, f=0, omega="2*pi", l=-1, r=1, damping="2"),
]


@pytest.mark.parametrize("scene", STACK_SCENES, ids=["undamped", "damped", "damped, frictionless"])
def test_each_stack_entry_is_the_derivative_of_the_one_before(scene):
    """Exclusion bounds ``g`` by ``g(c) + g'(c) [-r, r] + g''(I) [0, r^2/2]`` and Krawczyk uses
    ``g'(H)``: both are sound only if ``stack[k + 1]`` is the derivative of ``stack[k]``.  The
    mean value theorem says ``(s_k(b) - s_k(a)) / (b - a)`` lies in ``s_{k+1}([a, b])``; a stack
    with a wrong derivative (a dropped damping term, a sign) fails it on short intervals."""
    import random
    rng = random.Random(24)
    with workprec(PREC):
        m = BallModel(scene)
        for _ in range(6):
            t0, x0, v0 = (from_fraction(Fraction(rng.randint(-4000, 4000), 1000)) for _ in range(3))
            s = (1 if v0 > 0 else -1) if scene.has("friction") else 0
            motions = [(motion_module.Flight(m, t0, x0, v0, s), 5),
                       (motion_module.Rest(m, x0), 4)]
            for mo, depth in motions:
                a = from_fraction(Fraction(rng.randint(0, 3000), 1000))
                b = a + arb(2) ** -30
                lo, hi, piece = mo.stack(a), mo.stack(b), mo.stack(span(a, b))
                for k in range(depth - 1):
                    slope = (hi[k] - lo[k]) / (b - a)
                    assert slope.overlaps(piece[k + 1]), (type(mo).__name__, k, slope, piece[k + 1])
