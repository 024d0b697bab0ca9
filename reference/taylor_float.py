"""``TaylorFlight.evaluate_float``: a position-forced flight in float64 with rigorous error bounds.

``reference.events`` takes its far-from-root safe steps in float64 when the flight offers
``evaluate_float(h)`` (``events._float_advance``; the closed-form flights of ``reference.flows``
always did).  Without it a position-forced flight ran every safe step on the mpf step
polynomials: issue 33, a ten-period map at 40 digits of an unseen scene spent ~90% of its time
in those probes (``x`` and ``v`` by Horner at ~80 terms, ~400 probes a flight, most of them
far from any event), which the scorecards' ten-period truths and ``impact_at_t``'s refinement
pay in full.  The mpf steps still locate every event (from ~1e-14 of a possible root), so the
events and the states are the reference's, to its working precision.

At ``t = t_start + h`` (``h`` taken exactly) in the Taylor step ``i`` of length ``h_i`` that
holds it, with ``sigma = (t - t_i) / h_i`` in ``[0, 1]`` and the step's scaled polynomials
``x = sum X_n sigma^n``, ``v h_i = sum V_n sigma^n`` (``X_n = x_n h_i^n``, bounded by the step's
certificate, so that no coefficient overflows however short the step; ``N + 2`` terms at most),
the float64 Horner value of ``p`` (coefficients and ``sigma`` rounded to float64, relative error
``u = 2^-53`` each) is within

    ``(1 + 2 (N + 2)) u S + (N + 2) u S + (rounding of S) <= (4 N + 16) u S``,
    ``S = sum |p_n| |sigma|^n``

of the mpf polynomial: Horner's rounding (``gamma_{2n}``), the coefficients' conversion, and
``|p'(sigma)| u |sigma| <= N u S`` for the rounding of ``sigma`` (Higham, *Accuracy and
Stability*, sec. 5.1); ``v`` takes two roundings more (``1 / h_i`` and the product: ``+2 u``).
The mpf polynomial is within the flight's noise floor of the flight (added).  The
acceleration ``a = F cos(k x) cos(w t) - s f - c v`` and its derivative
``a' = -F w cos(k x) sin(w t) - F k sin(k x) cos(w t) v - c a`` take ``x``'s error through
``|d cos(k x)/dx| <= k`` and ``v``'s directly, and ``64 u`` times the magnitudes of their
terms for the rest (the rounding of ``w t``, ``k x`` and the products, ``cos``/``sin`` to 1 ulp:
``reference.flows``' allowance).
"""
from __future__ import annotations

import math

U = 2.0 ** -53
#: ``reference.flows``' allowance for a short formula's roundings and libm's ``cos``/``sin``
E = 64 * 2.0 ** -52


def _horner(coeffs, tau):
    """``(p(tau), sum |p_n| |tau|^n)`` in float64."""
    acc, mag, at = 0.0, 0.0, abs(tau)
    for c in reversed(coeffs):
        acc = acc * tau + c
        mag = mag * at + abs(c)
    return acc, mag


def step_floats(X, V, P, h):
    """A step's scaled polynomials as float64 coefficient lists (kept per step by the flight):
    ``X_n 2^-P`` and ``V_n 2^-P`` (correctly rounded: ``int / int``), and ``1 / h``."""
    one = 1 << P
    return [z / one for z in X], [z / one for z in V], float(1 / h)


def evaluate(prm, s, noise, coeffs, sigma, t):
    """``(x, v, a, a', ex, ev, ea, ea')`` (module docstring): ``prm = (F, f, c, k, w)`` as
    floats, ``noise = (noise_x, noise_v)`` as floats, ``coeffs`` the step's ``step_floats``,
    ``sigma`` and ``t`` (mpf) the fraction of the step and the time."""
    F, f, c, k, w = prm
    xf, vf, hinv = coeffs
    tf, sigma = float(t), float(sigma)
    x, sx = _horner(xf, sigma)
    v, sv = _horner(vf, sigma)
    v, sv = v * hinv, sv * hinv
    ex = (4 * len(xf) + 16) * U * sx * (1 + 1e-10) + noise[0] + 1e-300
    ev = (4 * len(vf) + 18) * U * sv * (1 + 1e-10) + noise[1] + 1e-300
    kx, wt = k * x, w * tf
    ck, sk, cw, sw = math.cos(kx), math.sin(kx), math.cos(wt), math.sin(wt)
    a = F * ck * cw - s * f - c * v
    da = -F * w * ck * sw - F * k * sk * cw * v - c * a
    trig = k * ex + E * (2 + abs(kx) + abs(wt))        # of cos(k x), sin(k x), cos(w t), sin(w t)
    ea = F * trig + c * ev + E * (F + f + c * abs(v)) + 1e-300
    eda = (F * w * trig + F * k * (abs(v) * trig + ev) + c * ea
           + E * (F * w + F * k * abs(v) + c * abs(a))) + 1e-300
    return x, v, a, da, ex, ev, ea, eda
