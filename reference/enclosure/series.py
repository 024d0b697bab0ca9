"""The flight under position forcing on balls: its right-hand side, its derivative stack and
its Taylor coefficients (automatic differentiation), for ``reference.enclosure.lohner``.

In flight with a fixed friction sign ``s`` (``0`` without friction) the motion solves

    x' = v,   v' = a(t, x, v) = F cos(k x) cos(w t) - s f - c v,

with no closed form.  Everything here is ball arithmetic: called with balls that are whole
boxes (a start box, an a priori enclosure), every result encloses the exact value for every
point of them.

Taylor coefficients
-------------------
Write ``x(t + tau) = sum_n x_n tau^n``, ``u = k x``, ``C = cos u = sum C_n tau^n``,
``S = sin u = sum S_n tau^n`` and ``cos(w (t + tau)) = sum P_n tau^n`` with
``P_n = w^n / n! cos(w t + n pi/2)``.  From ``C' = -S u'``, ``S' = C u'``:

    n C_n = - sum_{j=1..n} j u_j S_{n-j},     n S_n = sum_{j=1..n} j u_j C_{n-j},

and the equation of motion gives, with ``*`` the Cauchy product,

    (n+1)(n+2) x_{n+2} = F (C*P)_n - c (n+1) x_{n+1} - s f [n = 0],

so ``x_0 .. x_N`` cost ``O(N^2)`` ball operations (the same recurrence as the point
reference's ``reference.taylor``, written again here on balls: the enclosure shares no
integration code with the point reference).  ``v_n = (n+1) x_{n+1}``.

The variational equations ``V' = [[0, 1], [A_x, -c]] V``, ``V(0) = I``
(``A_x = -F k sin(k x) cos(w t)``, so ``A_x = sum B_n tau^n``, ``B_n = -F k (S*P)_n``) give the
Taylor coefficients of the flow derivative ``V(tau) = d(x, v)(t + tau) / d(x, v)(t)``, column
by column: ``dx_{n+1} = dv_n / (n+1)``, ``dv_{n+1} = ((B*dx)_n - c dv_n) / (n+1)``.  Over a box
of starts, ``V_n`` encloses the derivative of the coefficient map ``(x, v) -> (x_n, v_n)``
(``d/dz sum x_n(z) tau^n = V(tau)``), which is what the Lohner step needs.

The stack
---------
``[x, v, a, a', a'']`` at a state, with ``A = F cos(k x) cos(w t)``:

    a'  = A_t + A_x v - c a,
    a'' = A_tt + 2 A_xt v + A_xx v^2 + A_x a - c a',

``A_t = -F w cos(kx) sin(wt)``, ``A_x = -F k sin(kx) cos(wt)``, ``A_tt = -w^2 A``,
``A_xt = F k w sin(kx) sin(wt)``, ``A_xx = -k^2 A``.
"""
from __future__ import annotations

from operator import mul

from flint import arb, arb_poly


def _dot(a, b_reversed) -> arb:
    """``sum a_i b_i`` (``b`` given reversed, as the Cauchy products slice it)."""
    return sum(map(mul, a, b_reversed), arb(0))


class Field:
    """The right-hand side of a flight with sign ``s`` for a ``BallModel`` with position
    forcing (damping optional)."""

    def __init__(self, model, s: int):
        self.F, self.f, self.w, self.k = model.F, model.f, model.w, model.k
        self.c = model.c if model.damping else arb(0)
        self.sf = model.f * s if s else arb(0)
        self.s = s

    # -- values ----------------------------------------------------------------------------
    def accel(self, t, x, v) -> arb:
        """``a = F cos(k x) cos(w t) - s f - c v``."""
        return self.F * (self.k * x).cos() * (self.w * t).cos() - self.sf - self.c * v

    def stack(self, t, x, v) -> list:
        """``[x, v, a, a', a'']`` at ``(t, x, v)`` (module docstring)."""
        F, k, w, c = self.F, self.k, self.w, self.c
        sx, cx = (k * x).sin_cos()
        st, ct = (w * t).sin_cos()
        A = F * cx * ct
        A_t, A_x = -F * w * cx * st, -F * k * sx * ct
        a = A - self.sf - c * v
        a1 = A_t + A_x * v - c * a
        a2 = -w * w * A + 2 * F * k * w * sx * st * v - k * k * A * v * v + A_x * a - c * a1
        return [x, v, a, a1, a2]

    def lipschitz(self, t, x) -> arb:
        """An upper bound of ``|Df|_inf = max(1, |A_x| + |c|)`` over the balls (an exact ball;
        ``|c|``: a flight run backward in time has the damping ``-c``)."""
        A_x = self.F * self.k * (self.k * x).sin() * (self.w * t).cos()
        bound = (abs(A_x) + abs(self.c)).upper()     # exact: the comparison is decided
        return bound if bound > 1 else arb(1)

    # -- Taylor coefficients -------------------------------------------------------------
    def series(self, t, x, v, order: int, variational: int = -1):
        """``(xs, cols)``: ``xs = [x_0 .. x_order]`` of the flight through ``(t, x, v)`` and,
        if ``variational >= 0``, the columns ``(dx1, dv1, dx2, dv2)`` of the flow derivative,
        each ``[V_0 .. V_variational]`` (``variational <= order - 1``)."""
        if order < 2 or variational > order - 1:
            raise ValueError(f"series: need order >= 2 and variational <= order - 1, got "
                             f"{order}, {variational}")
        F, k, w, c, sf = self.F, self.k, self.w, self.c, self.sf
        xs = [x, v] + [arb(0)] * (order - 1)
        ju = [arb(0), k * v]                         # j u_j, u = k x
        sx, cx = (k * x).sin_cos()
        C, S = [cx], [sx]
        st, ct = (w * t).sin_cos()
        cyc, P, wn = (ct, -st, -ct, st), [], arb(1)
        for n in range(order - 1):
            P.append(cyc[n % 4] * wn)
            wn = wn * w / (n + 1)
            if n >= 1:
                C.append(-_dot(ju[1:n + 1], S[n - 1::-1]) / n)
                S.append(_dot(ju[1:n + 1], C[n - 1::-1]) / n)
            a_n = F * _dot(C, P[::-1]) - c * (n + 1) * xs[n + 1]
            if n == 0:
                a_n -= sf
            xs[n + 2] = a_n / ((n + 1) * (n + 2))
            ju.append(k * (n + 2) * xs[n + 2])
        if variational < 0:
            return xs, None
        return xs, self._variational(S, P, variational)

    def _variational(self, S, P, order):
        SP = (arb_poly(S[:order]) * arb_poly(P[:order])).coeffs()      # both known: one product
        Fk = -self.F * self.k
        B = [Fk * SP[n] if n < len(SP) else arb(0) for n in range(order)]
        cols = []
        for dx0, dv0 in ((1, 0), (0, 1)):
            dx, dv = [arb(dx0)], [arb(dv0)]
            for n in range(order):
                dx.append(dv[n] / (n + 1))
                dv.append((_dot(B[:n + 1], dx[n::-1]) - self.c * dv[n]) / (n + 1))
            cols += [dx, dv]
        return tuple(cols)
