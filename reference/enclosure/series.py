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

Where the time goes: these sums are most of a validated step (issue 33), and a ball product
costs ~100 ns of Python against ~25 ns of C.  So ``C`` and ``S`` are one complex recurrence,
``E = C + i S = exp(i u)``, ``n E_n = i sum_{j=1..n} j u_j E_{n-j}`` (one ``acb`` sum for two
``arb`` sums; a real factor costs ``acb`` two real products), and the products with a factor
known in advance (``P`` here, ``B`` below) take a block of terms at a time in C
(:class:`Online`).  Scene W of issue 33 (``F=3 f=0.3 omega=0.5 l=-2 r=2 wavenumber=2``), three
golden inputs' proofs, one run each: 9.6 -> 6.7 CPU s; a point series of order 68 at 192 bits
1160 -> 850 us, a box series with its variational columns 2075 -> 1500 us, the remainder's at 64
bits 1510 -> 943 us; the radii the same to 1e-7 relative.

The variational equations ``V' = [[0, 1], [A_x, -c]] V``, ``V(0) = I``
(``A_x = -F k sin(k x) cos(w t)``, so ``A_x = sum B_n tau^n``, ``B_n = -F k (S*P)_n``) give the
Taylor coefficients of the flow derivative ``V(tau) = d(x, v)(t + tau) / d(x, v)(t)``, column
by column: ``dx_{n+1} = dv_n / (n+1)``, ``dv_{n+1} = ((B*dx)_n - c dv_n) / (n+1)``.  Over a box
of starts, ``V_n`` encloses the derivative of the coefficient map ``(x, v) -> (x_n, v_n)``
(``d/dz sum x_n(z) tau^n = V(tau)``), which is what the Lohner step needs.

The columns over a box without the box's recurrence (:meth:`Field.variational_near`): they
depend on the start only through ``S``, and ``S_n`` has the gradient
``k (C * dx1, C * dx2)_n`` (``d sin(k x) = k cos(k x) dx``; :meth:`Field.sin_gradient`).  So
with ``S(m)`` at the box's centre and that gradient over any box ``B`` of starts holding the
box ``Y`` (the Lohner step's a priori box, whose series the remainder computes anyway), the
mean value theorem on the segment from ``m`` gives ``S_n(Y) in S_n(m) + grad S_n(B) . (Y - m)``.
The box's own recurrence costs as much as the centre's: a golden proof's step (192 bits,
order 68, ``Phi'`` to the working precision) took a point series, a box series and a remainder
series, and now takes two series and the box's columns (issue 33, the golden task of
``F=2.74 f=0.54 omega=1.06 l=-0.54 r=0.91 wavenumber=1.22``, two runs each, alternating: 24.9,
24.5 -> 21.5, 22.3 CPU s; the proofs of six of its inputs, three runs each: 5.6, 4.8, 6.1 ->
4.2, 4.7, 4.8 CPU s; every written value the same, the radii the same to the three digits
written, three 50-digit midpoints of Jacobians ~1e15 one unit apart in the last digit; the
orbit proofs at 64 bits, whose box series were of half the order, within noise).

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

from flint import acb, acb_poly, arb, arb_poly


def _dot(a, b_reversed, zero):
    """``sum a_i b_i`` (``b`` given reversed, as the Cauchy products slice it), ``zero`` the
    ``arb(0)`` or ``acb(0)`` it starts from."""
    return sum(map(mul, a, b_reversed), zero)


#: Terms of the online factor multiplied into the known one at once (:class:`Online`): 8 is the
#: fastest of 4 .. 16 at order 68 (136 against 283 us for the whole product, one run).
BLOCK = 8


class Online:
    """The Cauchy product ``(a * b)_n`` of a factor ``b`` known in advance and a factor ``a``
    known term by term (``a_0 .. a_n`` when ``(a * b)_n`` is asked for).

    Each finished block ``a_N .. a_{N+BLOCK-1}`` is multiplied into all of ``b`` at once, one
    ``arb_poly`` product in C, and accumulated; only the terms of the open block are summed in
    Python.  The recurrences here are sequential (``a_n`` needs ``(a * b)_{n-1}``), so a whole
    product cannot be taken at once; ~``n BLOCK / 2`` Python terms replace ``n^2 / 2`` (issue 33:
    the Python overhead of a ball product, ~100 ns, is most of a validated step's cost).  Ball
    arithmetic encloses in any order of summation, so the result encloses the same sum."""

    __slots__ = ("b", "acc", "start", "poly", "zero")

    def __init__(self, b, complex_: bool = False):
        """``b``: the known factor, ``arb`` balls (``acb`` with ``complex_``)."""
        self.poly, self.zero = (acb_poly, acb(0)) if complex_ else (arb_poly, arb(0))
        self.b, self.acc, self.start = b, self.poly([]), 0

    def coeff(self, a, n: int) -> arb:
        """``(a * b)_n`` for ``0 <= n < len(b)``, ``n`` in any order: ``a`` holds ``a_0 .. a_n``
        and its terms do not change once given (a block is multiplied in when a call reaches
        ``BLOCK`` terms past it)."""
        if not 0 <= n < len(self.b):
            raise ValueError(f"Online.coeff: need 0 <= n < {len(self.b)} (the known factor's "
                             f"length), got n = {n}")
        s = self.start
        if n - s >= BLOCK:
            e = s + BLOCK
            self.acc += (self.poly(a[s:e]) * self.poly(self.b[:len(self.b) - s])).left_shift(s)
            self.start = s = e
        return self.acc[n] + _dot(a[s:n + 1], self.b[n - s::-1], self.zero)


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
        xs, _, S, P = self.trig_series(t, x, v, order)
        return xs, (None if variational < 0 else self.variational(S, P, variational))

    def trig_series(self, t, x, v, order: int):
        """``(xs, C, S, P)``: ``xs`` as :meth:`series`, and the coefficients ``C_0 .. C_{order-2}``,
        ``S_0 .. S_{order-2}`` of ``cos(k x)``, ``sin(k x)`` and ``P_0 .. P_{order-2}`` of
        ``cos(w (t + tau))`` along it (so :meth:`variational` of them reaches ``order - 1``)."""
        if order < 2:
            raise ValueError(f"trig_series: need order >= 2, got {order}")
        F, k, c, sf = self.F, self.k, self.c, self.sf
        xs = [x, v] + [arb(0)] * (order - 1)
        ju = [acb(0), acb(k * v)]                    # j u_j, u = k x (real; complex for the dot)
        sx, cx = (k * x).sin_cos()
        C, S, E = [cx], [sx], [acb(cx, sx)]          # E = C + i S = exp(i u)
        P = self._forcing(t, order - 1)
        CP, zero, damped = Online(P), acb(0), not c.is_zero()
        for n in range(order - 1):
            if n >= 1:          # n E_n = i sum j u_j E_{n-j}: both recurrences in one dot
                z = _dot(ju[1:n + 1], E[n - 1::-1], zero)
                C.append(-z.imag / n)
                S.append(z.real / n)
                E.append(acb(C[n], S[n]))
            a_n = F * CP.coeff(C, n)
            if damped:
                a_n -= c * (n + 1) * xs[n + 1]
            if n == 0:
                a_n -= sf
            xs[n + 2] = a_n / ((n + 1) * (n + 2))
            ju.append(acb(k * (n + 2) * xs[n + 2]))
        return xs, C, S, P

    def sin_gradient(self, C, cols, order: int) -> tuple:
        """``(dS/dx0, dS/dv0)``, each ``[.._0 .. .._{order-1}]``: the coefficients of the
        derivatives of ``S = sin(k x)`` along the flight with respect to its start,
        ``k (C * dx1)`` and ``k (C * dx2)`` (``d sin(k x) = k cos(k x) dx``), from the ``C`` of
        :meth:`trig_series` and the columns of :meth:`series` (``order`` at most both lengths).
        Over balls that are boxes, they bound the derivatives for every start of the box."""
        if not 0 < order <= min(len(C), len(cols[0])):
            raise ValueError(f"sin_gradient: need 0 < order <= {min(len(C), len(cols[0]))} (the "
                             f"lengths of C and of the columns), got {order}")
        c, out = arb_poly(C[:order]), []
        for col in (cols[0], cols[2]):
            prod = (c * arb_poly(col[:order])).coeffs()
            out.append([self.k * prod[n] if n < len(prod) else arb(0) for n in range(order)])
        return tuple(out)

    def variational_near(self, S, P, dS, dz, order: int):
        """The columns of :meth:`series` (``variational = order``) over the box ``m + dz`` of
        starts, from ``S``, ``P`` of :meth:`trig_series` at the point ``m`` and ``dS`` of
        :meth:`sin_gradient` over a box of starts that holds ``m + dz`` (at the same time or a
        ball of times holding it): by the mean value theorem on the segment from ``m``,
        ``S_n(m + d) = S_n(m) + grad S_n(xi) . d`` for a ``xi`` of the box, so
        ``S_n(m) + dS_n . dz`` encloses ``S_n`` over the box -- without the recurrence over
        the box, whose cost is the point's again."""
        have = min(len(S), len(P), len(dS[0]), len(dS[1]))
        if not 0 < order <= have:
            raise ValueError(f"variational_near: need 0 < order <= {have} (the lengths of S, P "
                             f"and dS), got {order}")
        box = [S[n] + dS[0][n] * dz[0] + dS[1][n] * dz[1] for n in range(order)]
        return self.variational(box, P, order)

    def variational(self, S, P, order: int):
        """The columns ``(dx1, dv1, dx2, dv2)`` of the flow derivative, each ``[V_0 .. V_order]``,
        from ``S_0 .. S_{order-1}`` and ``P_0 .. P_{order-1}`` of :meth:`trig_series` (module
        docstring: ``B_n = -F k (S*P)_n``)."""
        SP = (arb_poly(S[:order]) * arb_poly(P[:order])).coeffs()      # both known: one product
        Fk = -self.F * self.k
        B = [acb(Fk * SP[n]) if n < len(SP) else acb(0) for n in range(order)]
        # the two columns as one complex column (real + i imaginary): B is real, so each ball
        # product is the two real ones, in one Python call
        dx, dv, Bdx, c = [acb(1, 0)], [acb(0, 1)], Online(B, complex_=True), acb(self.c)
        for n in range(order):
            dx.append(dv[n] / (n + 1))
            dv.append((Bdx.coeff(dx, n) - c * dv[n]) / (n + 1))
        return ([z.real for z in dx], [z.real for z in dv], [z.imag for z in dx],
                [z.imag for z in dv])

    def _forcing(self, t, n: int) -> list:
        """``P_0 .. P_{n-1}``: the Taylor coefficients of ``cos(w (t + tau))``."""
        st, ct = (self.w * t).sin_cos()
        cyc, P, wn = (ct, -st, -ct, st), [], arb(1)
        for j in range(n):
            P.append(cyc[j % 4] * wn)
            wn = wn * self.w / (j + 1)
        return P
