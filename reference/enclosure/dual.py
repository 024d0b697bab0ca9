"""Dual numbers on balls: a value and its gradient, both arb balls (forward-mode AD).

A :class:`Dual` ``val + grad . eps`` stands for a function ``g`` of ``n`` variables over a
box: ``val`` encloses ``g`` and ``grad[i]`` encloses ``dg/du_i`` for every point of the box the
inputs were given over (each operation applies the chain rule to balls, so the enclosures hold
by induction: ``(g h)' = g' h + g h'``, ``sin(g)' = cos(g) g'``, ...).  Evaluated at a point it
gives ``g`` and its exact gradient; over a box, an enclosure of the gradient over the box --
what a mean-value form and a Krawczyk operator need.  ``centred`` runs Table 1 on them (the
gradients with respect to the event data), ``impacts`` its closed-form flight equations.
"""
from __future__ import annotations

from flint import arb


class Dual:
    """``val + grad . eps``: a ball and its gradient (balls) with respect to the event data."""

    __slots__ = ("val", "grad")

    def __init__(self, val, grad):
        self.val, self.grad = val, grad

    @classmethod
    def variable(cls, value, index: int, n: int) -> "Dual":
        """The ``index``-th of ``n`` variables, over the ball ``value``."""
        return cls(value, tuple(arb(1) if i == index else arb(0) for i in range(n)))

    @staticmethod
    def lift(x, n):
        return x if isinstance(x, Dual) else Dual(x, (0,) * n)

    def _n(self):
        return len(self.grad)

    def __add__(self, o):
        o = Dual.lift(o, self._n())
        return Dual(self.val + o.val, tuple(a + b for a, b in zip(self.grad, o.grad)))

    __radd__ = __add__

    def __neg__(self):
        return Dual(-self.val, tuple(-a for a in self.grad))

    def __sub__(self, o):
        return self + (-Dual.lift(o, self._n()))

    def __rsub__(self, o):
        return Dual.lift(o, self._n()) - self

    def __mul__(self, o):
        o = Dual.lift(o, self._n())
        return Dual(self.val * o.val, tuple(a * o.val + self.val * b for a, b in zip(self.grad, o.grad)))

    __rmul__ = __mul__

    def __truediv__(self, o):
        o = Dual.lift(o, self._n())
        q = self.val / o.val
        return Dual(q, tuple((a - q * b) / o.val for a, b in zip(self.grad, o.grad)))

    def __rtruediv__(self, o):
        return Dual.lift(o, self._n()) / self

    def _chain(self, value, slope):
        return Dual(value, tuple(slope * a for a in self.grad))

    def cos(self):
        s, c = self.val.sin_cos()
        return self._chain(c, -s)

    def sin(self):
        s, c = self.val.sin_cos()
        return self._chain(s, c)

    def sin_cos(self):
        s, c = self.val.sin_cos()
        return self._chain(s, c), self._chain(c, -s)

    def exp(self):
        e = self.val.exp()
        return self._chain(e, e)

    def expm1(self):
        return self._chain(self.val.expm1(), self.val.exp())

    def __abs__(self):
        if self.val > 0:
            return self
        if self.val < 0:
            return -self
        raise ZeroDivisionError("abs of a Dual whose value encloses 0 (no derivative)")

    # comparisons decide on the value (the walk proved their signs on the whole box)
    def __gt__(self, o):
        return self.val > (o.val if isinstance(o, Dual) else o)

    def __lt__(self, o):
        return self.val < (o.val if isinstance(o, Dual) else o)

    def __eq__(self, o):
        return self.val == (o.val if isinstance(o, Dual) else o)

    __hash__ = None
