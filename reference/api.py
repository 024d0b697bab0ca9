"""Public entry points: input checks, the precision context, and rounding of the results.

Every call works inside ``mpmath.workdps(dps + GUARD_DIGITS + extra)`` and restores the
caller's precision on exit (also on error): no global precision change leaks.  ``extra`` is 0
for the paper's scenes; a scene whose gap is tiny against ``|l|`` or ``F/w^2``, or a call
whose time span is many periods, gets the digits that keep the caller's ``dps`` right
(``reference.model.extra_digits``), up to ``MAX_EXTRA_DIGITS`` more and ``MAX_DPS`` in all
(a ``ValueError`` naming the quantity beyond).  Inputs ``x``, ``v``,
``t_end``, ``t0`` may be ``int``, ``float`` (its exact binary value), ``str`` (a decimal,
read at the working precision), ``fractions.Fraction`` or ``mpmath.mpf``.  The state must
lie in the closed gap: note that a float such as ``0.8`` is ``0.8000000000000000444``, so
it lies *outside* a wall given exactly as ``"0.8"``.
"""
from __future__ import annotations

from fractions import Fraction
from functools import lru_cache

import mpmath

from reference.integrator import MAX_EVENTS, EventLog, integrate
from reference.jacobian import product_of_table1
from reference.model import GUARD_DIGITS, MAX_EXTRA_DIGITS, Model, extra_digits
from reference.scene import Scene


#: the largest precision a call accepts: an event's cost grows like dps^1.7 (measured, six
#: events of the narrow scene: 0.44 s at 10000 digits, 3.5 s at 30000, 25 s at 100000), so
#: above this a chatter run or a busy period takes minutes
MAX_DPS = 10000


def check_dps(dps):
    """``dps`` must be an int in ``[15, MAX_DPS]``."""
    if isinstance(dps, bool) or not isinstance(dps, int) or not 15 <= dps <= MAX_DPS:
        raise ValueError(f"dps must be an integer >= 15 (decimal digits) and <= {MAX_DPS} (an "
                         f"event costs seconds above it), got {dps!r}")


def _work_dps(scene, dps, span_ratio=1):
    """The working digits of a call: ``dps + GUARD_DIGITS`` plus the scene's and the time
    span's ``extra_digits``; ``ValueError`` naming the quantity when ``dps + extra`` would
    pass ``MAX_DPS``."""
    extra, what = extra_digits(scene, span_ratio)
    if extra > MAX_EXTRA_DIGITS or dps + extra > MAX_DPS:
        raise ValueError(f"reference: {what} needs {extra} more working digits than dps + "
                         f"{GUARD_DIGITS}, above reference.model.MAX_EXTRA_DIGITS = "
                         f"{MAX_EXTRA_DIGITS} or dps + {extra} above MAX_DPS = {MAX_DPS}: the "
                         f"events of a call would cost seconds each")
    return dps + GUARD_DIGITS + extra


def check_count(name, value, low):
    """An integer argument ``>= low`` (``TypeError`` for a non-integer type)."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise TypeError(f"{name} must be an integer >= {low}, got {value!r}")
    if value < low:
        raise ValueError(f"{name} must be an integer >= {low}, got {value!r}")
    return value


def to_mpf(name, value):
    """Convert an input number exactly (at the working precision for decimal strings)."""
    if isinstance(value, bool):
        raise ValueError(f"{name} must be a real number, got {value!r}")
    try:
        if isinstance(value, Fraction):
            out = mpmath.mpf(value.numerator) / value.denominator
        elif isinstance(value, (int, float, str, mpmath.mpf)):
            out = mpmath.mpf(value.strip() if isinstance(value, str) else value)
        else:
            raise TypeError
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be int, float, str, Fraction or mpf, got {value!r}") from None
    if not mpmath.isfinite(out):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return out


def _state(model, x, v):
    x, v = to_mpf("x", x), to_mpf("v", v)
    if not model.l <= x <= model.r:
        raise ValueError(
            f"x must lie in the closed gap [l, r] = [{model.scene.l}, {model.scene.r}], got {x}")
    return x, v


def _check_scene(scene):
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a reference.Scene, got {type(scene).__name__}")


@lru_cache(maxsize=64)
def _model(scene, prec):
    """The scene at a precision (cached: a Model is immutable once built)."""
    return Model(scene)


def _model_here(scene):
    return _model(scene, mpmath.mp.prec)


def _rounded(dps, *values):
    with mpmath.workdps(dps):
        return tuple(+value for value in values)


def stroboscopic_map(scene, x, v, *, periods=1, dps=50, max_events=MAX_EVENTS):
    """``Phi^periods(x, v)``: the state at ``t = periods T`` from ``(x, v)`` at ``t = 0``;
    ``periods = 0`` is the identity (as in ``fast``).

    Returns ``(x, v)`` as mpf rounded to ``dps`` digits.  ``max_events`` bounds the events
    of the call (``RuntimeError`` beyond it).
    """
    _check_scene(scene)
    check_dps(dps)
    check_count("periods", periods, 0)
    check_count("max_events", max_events, 1)
    with mpmath.workdps(_work_dps(scene, dps, max(periods, 1))):
        model = _model_here(scene)
        x, v = _state(model, x, v)
        if periods == 0:
            return _rounded(dps, x, v)
        model.check_span(0, periods * model.T)
        log = integrate(model, mpmath.mpf(0), x, v, periods * model.T, max_events)
        return _rounded(dps, log.x_end, log.v_end)


def trajectory(scene, x, v, t_end, *, t0=0, dps=50, max_events=MAX_EVENTS) -> EventLog:
    """The event log of the motion from ``(x, v)`` at ``t0`` to ``t_end >= t0``.

    A list of ``Event`` (see ``reference.integrator``), values rounded to ``dps`` digits;
    ``log.x_end``, ``log.v_end`` give the state at ``t_end`` (right limit).
    """
    _check_scene(scene)
    check_dps(dps)
    check_count("max_events", max_events, 1)
    with mpmath.workdps(30):
        span = max(abs(to_mpf("t0", t0)), abs(to_mpf("t_end", t_end))) * scene.mpf("omega") / (2 * mpmath.pi)
    with mpmath.workdps(_work_dps(scene, dps, max(span, 1))):
        model = _model_here(scene)
        x, v = _state(model, x, v)
        t0, t_end = to_mpf("t0", t0), to_mpf("t_end", t_end)
        if t_end < t0:
            raise ValueError(f"t_end must be >= t0 (integration runs forward), got t0={t0}, t_end={t_end}")
        model.check_span(t0, t_end)
        log = integrate(model, t0, x, v, t_end, max_events)
        return _round_log(log, dps)


def _round_log(log, dps):
    out = EventLog()
    with mpmath.workdps(dps):
        for ev in log:
            out.append(type(ev)(ev.kind, +ev.t, +ev.x, +ev.v, +ev.v_before, ev.count))
        out.t0, out.x0, out.v0 = +log.t0, +log.x0, +log.v0
        out.t_end, out.x_end, out.v_end = +log.t_end, +log.x_end, +log.v_end
    out.mode_end = log.mode_end
    return out


def jacobian(scene, x, v, *, dps=50, max_events=MAX_EVENTS):
    """``Phi'(x, v)`` over ``[0, T]``: the ordered product of the paper's Table 1 matrices.

    Returned as a list of lists of mpf (``J[i][j]``), rounded to ``dps`` digits.  The
    reflection matrix uses the velocity *before* the impact (see ``reference.jacobian``).
    Raises ``ValueError`` on a grazing orbit (an impact with velocity below the noise
    floor), where the derivative does not exist.
    """
    _check_scene(scene)
    check_dps(dps)
    check_count("max_events", max_events, 1)
    with mpmath.workdps(_work_dps(scene, dps)):
        model = _model_here(scene)
        x, v = _state(model, x, v)
        log = integrate(model, mpmath.mpf(0), x, v, model.T, max_events)
        J = product_of_table1(model, log)
        with mpmath.workdps(dps):
            return [[+J[0][0], +J[0][1]], [+J[1][0], +J[1][1]]]
