"""Arb balls: the precision context, exact conversions, and the scene in ball arithmetic.

python-flint's ``arb`` is a midpoint-radius interval ("ball") whose every operation returns
a ball that provably contains the exact result for every point of the inputs (Arb, F.
Johansson, IEEE Trans. Comput. 2017).  Precision is a global of python-flint
(``flint.ctx.prec``); :func:`workprec` raises it locally and restores it in ``finally``, as
``mpmath.workprec`` does, so no precision change leaks to the caller.

Comparisons of balls are *certain*: ``a > 0`` is True only if every point of ``a`` is
positive; ``not (a > 0)`` does not mean ``a <= 0``.  Every proof in this package is a chain
of such certain comparisons.
"""
from __future__ import annotations

import contextlib
import math
from fractions import Fraction

import mpmath
from flint import arb, ctx, fmpq

#: Working precision (bits) of an enclosure when the caller gives none: ~96 digits, so that
#: a chain of a few dozen events keeps well over 40 correct digits.
DEFAULT_PREC = 320


@contextlib.contextmanager
def workprec(bits: int):
    """Run the block at ``bits`` of arb precision; the caller's precision is restored."""
    saved = ctx.prec
    ctx.prec = bits
    try:
        yield
    finally:
        ctx.prec = saved


def from_fraction(value: Fraction) -> arb:
    """The ball of a rational (exact when the denominator is a power of two)."""
    return arb(fmpq(value.numerator, value.denominator))


def from_mpf(value) -> arb:
    """The exact ball of an ``mpmath.mpf`` (a binary number: radius 0), at the mpf's own
    precision (not re-rounded to mpmath's current one)."""
    sign, man, exp, _ = value._mpf_ if isinstance(value, mpmath.mpf) else mpmath.mpf(value)._mpf_
    if not man:
        return arb(0)
    return arb((-int(man) if sign else int(man), int(exp)))


def from_number(value) -> arb:
    """A user number as a ball: int/float/mpf exactly, a decimal string or Fraction as the
    ball of its exact rational value."""
    if isinstance(value, arb):
        return value
    if isinstance(value, bool):
        raise TypeError(f"expected a real number, got {value!r}")
    if isinstance(value, Fraction):
        return from_fraction(value)
    if isinstance(value, (int, float)):
        return from_fraction(Fraction(value))
    if isinstance(value, str):
        return from_fraction(Fraction(value.strip()))
    if isinstance(value, mpmath.mpf):
        return from_mpf(value)
    raise TypeError(f"expected int, float, str, Fraction, mpf or arb, got {type(value).__name__}")


def parameter(scene, name: str) -> arb | None:
    """A scene parameter as a ball of its exact value (``pi`` expressions included); for a
    parameter box (``reference.enclosure.params``) the ball ``[lo, hi]`` of its exact ends."""
    exact = scene.exact(name)
    if exact is None:
        return None
    if isinstance(exact, tuple):
        return span(*(_exact_ball(end) for end in exact))
    return _exact_ball(exact)


def _exact_ball(exact) -> arb:
    if isinstance(exact, Fraction):
        return from_fraction(exact)
    return exact.evaluate(from_fraction, arb.pi())


def to_mpf(value: arb) -> mpmath.mpf:
    """The midpoint of a ball as an ``mpf``, rounded to mpmath's working precision (exact when
    that holds the midpoint's mantissa)."""
    man, exp = value.mid().man_exp()
    return mpmath.mpf((int(man) < 0, abs(int(man)), int(exp), abs(int(man)).bit_length()))


def span(lo: arb, hi: arb) -> arb:
    """The ball from the lower end of ``lo`` to the upper end of ``hi``."""
    return lo.lower().union(hi.upper())


def decimal_ball(ball: arb, digits: int) -> tuple[str, float]:
    """``(mid, radius)``: ``mid`` a ``digits``-digit decimal string, ``radius`` a float such
    that ``[mid - radius, mid + radius]`` contains ``ball`` (the rounding of the written
    midpoint included, rounded up).  Call at the ball's working precision."""
    mid = ball.mid().str(digits, radius=False)
    radius = (abs(from_fraction(Fraction(mid)) - ball.mid()) + ball.rad()).upper()
    value = float(radius)
    return mid, (math.nextafter(value, math.inf) if value else 0.0)


def radius_text(value: float) -> str:
    """A radius rounded *up* to 3 significant digits (``"0"`` for an exact ball)."""
    if value == 0:
        return "0"
    exponent = math.floor(math.log10(value)) - 2
    mantissa = math.ceil(value * (1 + 1e-12) / 10.0 ** exponent)
    return f"{mantissa / 100:.2f}e{exponent + 2}"


def rel_radius(value: arb) -> float:
    """``rad / |mid|`` (0 for an exact zero; inf for a ball around 0 with a radius)."""
    rad = float(value.rad())
    mid = abs(float(value.mid()))
    if rad == 0:
        return 0.0
    return rad / mid if mid else float("inf")


class BallModel:
    """The scene's parameters as balls at the current arb precision, plus derived constants.

    ``F, f, w, l, r, e, c, k`` (the paper's symbols; ``k`` None without position forcing),
    ``T = 2 pi / w``; ``friction``,
    ``restitution``, ``damping`` as in ``reference.model.Model``.
    """

    def __init__(self, scene):
        self.scene = scene
        self.F, self.f, self.w = (parameter(scene, k) for k in ("F", "f", "omega"))
        self.l, self.r = parameter(scene, "l"), parameter(scene, "r")
        self.e, self.c = parameter(scene, "restitution"), parameter(scene, "damping")
        self.k = parameter(scene, "wavenumber")
        self.T = 2 * arb.pi() / self.w
        self.friction = scene.has("friction")
        #: a parameter box with f in [0, hi]: frictionless and friction scenes together (the
        #: walk refuses sticking there: ``ParamBox.friction_mixed``; a scene never is)
        self.friction_mixed = bool(getattr(scene, "friction_mixed", False))
        self.restitution = scene.has("restitution")
        self.damping = scene.has("damping")
        self.position_forcing = scene.has("position_forcing")
        # the arithmetic of Table 1 (reference.jacobian reads these, as from an mpf Model)
        self.zero, self.one = arb(0), arb(1)

    @staticmethod
    def exp(z: arb) -> arb:
        return z.exp()

    @staticmethod
    def expm1(z: arb) -> arb:
        return z.expm1()

    def wall(self, side: int) -> arb:
        """``r`` for side +1, ``l`` for side -1."""
        return self.r if side > 0 else self.l

    def amplitude(self, x) -> arb:
        """``F cos(k x)``: the force's amplitude at the position ``x`` (``F`` without position
        forcing, where ``x`` is not used)."""
        return self.F * (self.k * x).cos() if self.position_forcing else self.F

    def force(self, x, t: arb) -> arb:
        """``A(x, t) = F cos(k x) cos(w t)`` (``F cos(w t)`` without position forcing)."""
        return self.amplitude(x) * (self.w * t).cos()
