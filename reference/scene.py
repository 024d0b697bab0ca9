"""Scene: the parameters of the oscillator and the effects they switch on.

The model (paper, eq. ``main``/``impact``, and the effects of its last section)::

    x'' + c x' + f sgn(x') = F cos(k x) cos(omega t),     l <= x <= r,
    x'(t+) = -e x'(t-)                                     at x = l or x = r,

in Filippov's sense (sticking at ``x' = 0`` while the force is within ``f``).
``c`` (``damping``), ``e`` (``restitution``) and ``k`` (``wavenumber``) are the
optional effects; by default ``c = 0``, ``e = 1`` and the forcing does not depend on
position (``k`` is ``None``, i.e. ``cos(k x) = 1``).

This module is the problem definition shared by ``reference`` and ``fast``: it holds
parameters and validation, nothing that integrates. Every parameter is kept *exactly*:

* ``int`` and ``float`` are taken as the exact binary value they hold (as mpmath does);
* a decimal string such as ``"0.8"`` is the exact decimal 4/5, at any precision;
* a string expression in ``pi`` (``"2*pi"``, ``"(2*pi)**2"``, ``"pi/2"``) is exact too:
  it is evaluated at whatever precision the caller works in; an expression without ``pi``
  and with integer powers (``"1/3"``, ``"2*0.1"``) is read as its exact rational;
* an ``mpmath.mpf`` is the exact binary value it holds.

Values may come from files written by others: reading one is bounded work.  Texts, trees,
magnitudes (``2^-4096 .. 2^4096``), powers and exact rationals have named limits in
``reference.expression`` (re-exported here); a value beyond one is a ``ValueError`` that
starts ``"Scene: <name>"`` and names the limit and the text.

``scene.mpf(name)`` gives a parameter at the current mpmath precision (correctly
rounded for rationals), ``scene.float(name)`` as a correctly rounded float64.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Union

import mpmath

from reference.expression import (MAX_DEPTH, MAX_EXPONENT_BITS, MAX_NODES,  # noqa: F401
                                  MAX_POWER_EXPONENT, MAX_RATIONAL_BITS, MAX_TEXT_LENGTH,
                                  KEY_BITS, Expr, LimitError, check_mpf_parts, check_rational,
                                  decimal_value, read)

Number = Union[int, float, str, "mpmath.mpf", Fraction]

#: Effects a scene can switch on.  ``walls`` is always on; the others follow the values.
EFFECTS = ("walls", "forcing", "friction", "restitution", "damping", "position_forcing")


def _show(value, width: int = 120) -> str:
    """``repr(value)`` cut to ``width`` characters (an int too long to print: its size)."""
    try:
        text = repr(value)
    except ValueError:                      # int beyond sys.get_int_max_str_digits()
        bits = max(abs(Fraction(value).numerator).bit_length(), Fraction(value).denominator.bit_length())
        text = f"<{type(value).__name__} of {bits}-bit integers>"
    return text if len(text) <= width else text[:width - 3] + "..."


def _exact(name: str, value) -> Union[Fraction, Expr]:
    """Convert a user value to an exact ``Fraction`` (or a ``pi`` expression) within the
    limits of ``reference.expression`` (``ValueError`` naming ``name`` otherwise)."""
    try:
        return _exact_value(value)
    except LimitError as exc:
        raise ValueError(f"Scene: {name} = {_show(value)} is refused: {exc}") from None
    except ValueError as exc:
        raise ValueError(f"Scene: {name} {exc}, got {_show(value)}") from None


def _exact_value(value) -> Union[Fraction, Expr]:
    if isinstance(value, bool):
        raise ValueError("must be a real number")
    if isinstance(value, (Fraction, int)):
        return check_rational(Fraction(value))
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError("must be finite")
        return Fraction(value)
    if isinstance(value, mpmath.mpf):
        if not mpmath.isfinite(value):
            raise ValueError("must be finite")
        sign, man, exp, _ = value._mpf_
        check_mpf_parts(int(man), int(exp))
        fr = Fraction(int(man)) * (Fraction(2) ** int(exp))
        return -fr if sign else fr
    if isinstance(value, str):
        return _from_text(value.strip())
    raise ValueError(f"must be int, float, str or mpmath.mpf (or a Fraction), not {type(value).__name__}")


def _from_text(text: str) -> Union[Fraction, Expr]:
    """A decimal string exactly, or a checked expression in ``pi`` (``expression.read``)."""
    if len(text) > MAX_TEXT_LENGTH:
        raise LimitError(f"it has {len(text)} characters, more than MAX_TEXT_LENGTH = {MAX_TEXT_LENGTH}")
    try:
        dec = decimal_value(text)
    except LimitError:
        raise
    except ValueError:
        raise ValueError("must be finite") from None
    if dec is not None:
        return dec
    try:
        return read(text)
    except LimitError:
        raise
    except ValueError as exc:
        raise ValueError(f"must be a number, a decimal string or an expression in pi "
                         f"(+ - * / ** and parentheses): {exc}") from None


def _as_mpf(value: Union[Fraction, Expr]) -> mpmath.mpf:
    if isinstance(value, Expr):
        return value.mpf()
    return mpmath.mpf(value.numerator) / value.denominator


def _compare_key(value: Union[Fraction, Expr]):
    """A value good enough for order checks between parameters (exact for rationals)."""
    if isinstance(value, Fraction):
        return value
    with mpmath.workprec(KEY_BITS):
        return Fraction(*_mpf_ratio(value.mpf()))


def _mpf_ratio(value: mpmath.mpf):
    sign, man, exp, _ = value._mpf_
    num = int(man) * (2 ** exp if exp >= 0 else 1)
    den = 1 if exp >= 0 else 2 ** (-exp)
    return (-num if sign else num), den


@dataclass(frozen=True)
class Scene:
    """A parameter set of the oscillator plus the physical effects it switches on.

    Parameters (the paper's symbols)
    --------------------------------
    F : forcing amplitude, ``F >= 0``.
    f : Coulomb (kinetic) friction level, ``f >= 0``.  ``F <= f`` is legal: motion stops.
    omega : forcing frequency, ``omega > 0``; the period is ``T = 2 pi / omega``.
    l, r : wall positions, ``l < r``.
    restitution : ``e`` in ``[0, 1]``, ``x'(t+) = -e x'(t-)`` at a wall (default 1).
    damping : viscous damping ``c >= 0`` (default 0).
    wavenumber : ``k > 0`` for position-dependent forcing ``F cos(k x) cos(omega t)``
        (the paper's eq. ``xpot`` has ``k = pi/2``), or ``None`` (default) for ``F cos(omega t)``.
    name : a label for reports (not part of the physics).

    Every invalid value raises ``ValueError`` naming the parameter and its allowed range.
    """

    F: Number
    f: Number
    omega: Number
    l: Number
    r: Number
    restitution: Number = 1
    damping: Number = 0
    wavenumber: Number | None = None
    name: str = field(default="", compare=False)

    _PHYSICAL = ("F", "f", "omega", "l", "r", "restitution", "damping", "wavenumber")

    def __post_init__(self):
        exact = {}
        for pname in self._PHYSICAL:
            value = getattr(self, pname)
            if pname == "wavenumber" and value is None:
                exact[pname] = None
                continue
            exact[pname] = _exact(pname, value)
        key = {k: (None if v is None else _compare_key(v)) for k, v in exact.items()}
        if key["F"] < 0:
            raise ValueError(f"Scene: F must be >= 0 (a phase shift of pi flips its sign), got {_show(self.F)}")
        if key["f"] < 0:
            raise ValueError(f"Scene: f must be >= 0 (friction dissipates), got {_show(self.f)}")
        if key["omega"] <= 0:
            raise ValueError(f"Scene: omega must be > 0, got {_show(self.omega)}")
        if key["r"] <= key["l"]:
            raise ValueError(f"Scene: r must be > l (the gap R = r - l is positive), got l={_show(self.l)}, r={_show(self.r)}")
        if not 0 <= key["restitution"] <= 1:
            raise ValueError(f"Scene: restitution must be in [0, 1], got {_show(self.restitution)}")
        if key["damping"] < 0:
            raise ValueError(f"Scene: damping must be >= 0, got {_show(self.damping)}")
        if key["wavenumber"] is not None and key["wavenumber"] <= 0:
            raise ValueError(f"Scene: wavenumber must be > 0 or None, got {_show(self.wavenumber)}")
        object.__setattr__(self, "_exact", exact)
        object.__setattr__(self, "_key", key)

    # -- values -----------------------------------------------------------------------
    def exact(self, name: str) -> Union[Fraction, "Expr", None]:
        """The exact value of a parameter: a ``Fraction``, or a ``pi`` expression."""
        return self._exact[name]

    def mpf(self, name: str) -> mpmath.mpf:
        """A parameter as an ``mpf`` at the current mpmath precision (``None`` if unset)."""
        value = self._exact[name]
        return None if value is None else _as_mpf(value)

    def float(self, name: str) -> float:
        """A parameter as a correctly rounded float64 (``None`` if unset); ``ValueError``
        naming it when float64 cannot hold it (beyond ``1.8e308``, or nonzero below the
        smallest subnormal ``5e-324``): never a silent ``inf`` or ``0``."""
        value = self._exact[name]
        if value is None:
            return None
        try:
            out = float(value)
        except OverflowError:
            out = math.inf
        if not math.isfinite(out) or (out == 0 and self._key[name] != 0):
            raise ValueError(f"Scene: {name} = {_show(getattr(self, name))} has no float64 value "
                             f"(float64 holds magnitudes 5e-324 .. 1.8e308); the reference "
                             f"(mpmath) works at any magnitude")
        return out

    def gap(self) -> mpmath.mpf:
        """``R = r - l`` as an ``mpf`` at the current precision, from the exact difference
        (a gap far below ``|l|`` is never lost to the rounding of ``l`` and ``r``)."""
        l, r = self._exact["l"], self._exact["r"]
        if isinstance(l, Fraction) and isinstance(r, Fraction):
            return _as_mpf(r - l)
        return _as_mpf(self._key["r"] - self._key["l"])

    def floats(self) -> dict:
        """All physical parameters as float64, keyed by name."""
        return {k: self.float(k) for k in self._PHYSICAL}

    # -- effects ----------------------------------------------------------------------
    @property
    def effects(self) -> frozenset:
        """The effects this scene switches on (a subset of ``EFFECTS``)."""
        key = self._key
        on = {"walls"}
        if key["F"] > 0:
            on.add("forcing")
        if key["f"] > 0:
            on.add("friction")
        if key["restitution"] < 1:
            on.add("restitution")
        if key["damping"] > 0:
            on.add("damping")
        if key["wavenumber"] is not None:
            on.add("position_forcing")
        return frozenset(on)

    def has(self, effect: str) -> bool:
        """Whether ``effect`` (one of ``EFFECTS``) is on."""
        if effect not in EFFECTS:
            raise ValueError(f"unknown effect {effect!r}; known: {', '.join(EFFECTS)}")
        return effect in self.effects

    @property
    def period(self) -> float:
        """``T = 2 pi / omega`` in float64 (integrators compute their own at their precision);
        ``ValueError`` when float64 cannot hold it."""
        omega = self.float("omega")
        period = 2 * math.pi / omega
        if not math.isfinite(period) or period == 0:
            raise ValueError(f"Scene: omega = {_show(self.omega)} gives a period T = 2 pi/omega "
                             f"beyond float64's range")
        return period

    def replace(self, **changes) -> "Scene":
        """A copy with some parameters changed (validated again)."""
        values = {k: getattr(self, k) for k in self._PHYSICAL}
        values["name"] = self.name
        values.update(changes)
        return Scene(**values)

    def __repr__(self):
        parts = [f"{k}={getattr(self, k)!r}" for k in ("F", "f", "omega", "l", "r")]
        defaults = {"restitution": 1, "damping": 0, "wavenumber": None}
        for k, default in defaults.items():
            if self._key[k] != (None if default is None else Fraction(default)):
                parts.append(f"{k}={getattr(self, k)!r}")
        if self.name:
            parts.append(f"name={self.name!r}")
        return f"Scene({', '.join(parts)})"
