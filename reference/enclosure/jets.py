"""First-order jets on balls: a value and its gradient, both arb balls (forward-mode AD).

A :class:`Jet` ``(v, d)`` stands for a function ``g`` of ``n`` variables over a box: ``v``
encloses ``g`` and ``d[i]`` encloses ``dg/dz_i`` for every point of the box the inputs were
given over (each operation applies the chain rule to balls, so the enclosures hold by
induction: ``(g h)' = g' h + g h'``, ``sin(g)' = cos(g) g'``, ...).  Evaluated at a point, the
jet gives ``g`` and its exact gradient; evaluated over a box, an enclosure of the gradient over
the box -- what a mean-value form and a Krawczyk operator need.  Only the operations the
closed-form flights use are defined (``+ - * /``, ``sin``, ``cos``); a constant is an ``arb``
or an int (zero gradient).
"""
from __future__ import annotations

from flint import arb


class Jet:
    """A value ``v`` and gradient ``d`` (a tuple of balls); see the module docstring."""

    __slots__ = ("v", "d")

    def __init__(self, v, d):
        self.v, self.d = v, tuple(d)

    @classmethod
    def variable(cls, value, index: int, n: int) -> "Jet":
        """The ``index``-th of ``n`` variables, over the ball ``value``."""
        return cls(value, (arb(1) if i == index else arb(0) for i in range(n)))

    @classmethod
    def constant(cls, value, n: int) -> "Jet":
        return cls(value, (arb(0),) * n)

    def _lift(self, other):
        if isinstance(other, Jet):
            return other
        if isinstance(other, (arb, int)):
            return Jet(arb(other), (arb(0),) * len(self.d))
        raise TypeError(f"Jet: cannot combine with {type(other).__name__}")

    def __add__(self, other):
        o = self._lift(other)
        return Jet(self.v + o.v, (a + b for a, b in zip(self.d, o.d)))

    __radd__ = __add__

    def __neg__(self):
        return Jet(-self.v, (-a for a in self.d))

    def __sub__(self, other):
        return self + (-self._lift(other))

    def __rsub__(self, other):
        return self._lift(other) - self

    def __mul__(self, other):
        o = self._lift(other)
        return Jet(self.v * o.v, (a * o.v + self.v * b for a, b in zip(self.d, o.d)))

    __rmul__ = __mul__

    def __truediv__(self, other):
        o = self._lift(other)
        q = self.v / o.v
        return Jet(q, ((a - q * b) / o.v for a, b in zip(self.d, o.d)))

    def __rtruediv__(self, other):
        return self._lift(other) / self

    def sin(self) -> "Jet":
        s, c = self.v.sin_cos()
        return Jet(s, (c * a for a in self.d))

    def cos(self) -> "Jet":
        s, c = self.v.sin_cos()
        return Jet(c, (-s * a for a in self.d))
