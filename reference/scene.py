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
  it is evaluated at whatever precision the caller works in;
* an ``mpmath.mpf`` is the exact binary value it holds.

``scene.mpf(name)`` gives a parameter at the current mpmath precision (correctly
rounded for rationals), ``scene.float(name)`` as a correctly rounded float64.
"""
from __future__ import annotations

import ast
import math
from dataclasses import dataclass, field
from decimal import Decimal, InvalidOperation
from fractions import Fraction
from typing import Union

import mpmath

Number = Union[int, float, str, "mpmath.mpf", Fraction]

#: Effects a scene can switch on.  ``walls`` is always on; the others follow the values.
EFFECTS = ("walls", "forcing", "friction", "restitution", "damping", "position_forcing")

_ALLOWED_BINOPS = (ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow)


class _Expr:
    """An exact real given by an arithmetic expression in ``pi`` (evaluated on demand)."""

    __slots__ = ("text", "_tree")

    def __init__(self, text: str, tree: ast.AST):
        self.text = text
        self._tree = tree

    def mpf(self) -> mpmath.mpf:
        """The value at the current mpmath precision (a few guard bits inside)."""
        with mpmath.workprec(mpmath.mp.prec + 20):
            value = _eval_tree(self._tree)
        return +value

    def evaluate(self, number, pi):
        """The value in another arithmetic: ``number(Fraction)`` makes a constant, ``pi`` is
        that arithmetic's pi (``reference.enclosure`` evaluates in arb balls this way)."""
        return _eval_tree(self._tree, number, pi)

    def __float__(self) -> float:
        with mpmath.workprec(113):
            return float(_eval_tree(self._tree))

    def __eq__(self, other):
        return isinstance(other, _Expr) and other.text == self.text

    def __hash__(self):
        return hash(self.text)

    def __repr__(self):
        return repr(self.text)


def _mp_number(value: Fraction) -> mpmath.mpf:
    return mpmath.mpf(value.numerator) / value.denominator


def _eval_tree(node: ast.AST, number=_mp_number, pi=None):
    """Evaluate an expression tree; ``number`` turns a ``Fraction`` into the arithmetic's
    constant and ``pi`` is its pi (default: mpmath at the current precision)."""
    if isinstance(node, ast.Expression):
        return _eval_tree(node.body, number, pi)
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
        return number(Fraction(str(node.value)))
    if isinstance(node, ast.Name) and node.id == "pi":
        return +mpmath.pi if pi is None else pi
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        value = _eval_tree(node.operand, number, pi)
        return -value if isinstance(node.op, ast.USub) else value
    if isinstance(node, ast.BinOp) and isinstance(node.op, _ALLOWED_BINOPS):
        a, b = _eval_tree(node.left, number, pi), _eval_tree(node.right, number, pi)
        op = node.op
        if isinstance(op, ast.Add):
            return a + b
        if isinstance(op, ast.Sub):
            return a - b
        if isinstance(op, ast.Mult):
            return a * b
        if isinstance(op, ast.Div):
            return a / b
        return a ** b
    raise ValueError(f"unsupported element {ast.dump(node)}")


def _exact(name: str, value) -> Union[Fraction, _Expr]:
    """Convert a user value to an exact ``Fraction`` (or a ``pi`` expression)."""
    if isinstance(value, bool):
        raise ValueError(f"Scene: {name} must be a real number, got {value!r}")
    if isinstance(value, (Fraction, int)):
        return Fraction(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"Scene: {name} must be finite, got {value!r}")
        return Fraction(value)
    if isinstance(value, mpmath.mpf):
        if not mpmath.isfinite(value):
            raise ValueError(f"Scene: {name} must be finite, got {value!r}")
        sign, man, exp, _ = value._mpf_
        fr = Fraction(int(man)) * (Fraction(2) ** exp)
        return -fr if sign else fr
    if isinstance(value, str):
        text = value.strip()
        try:
            dec = Decimal(text)
        except InvalidOperation:
            dec = None
        if dec is not None:
            if not dec.is_finite():
                raise ValueError(f"Scene: {name} must be finite, got {value!r}")
            return Fraction(dec)
        try:
            tree = ast.parse(text, mode="eval")
            expr = _Expr(text, tree)
            with mpmath.workprec(113):
                probe = _eval_tree(tree)
        except (SyntaxError, ValueError, ZeroDivisionError) as exc:
            raise ValueError(
                f"Scene: {name} must be a number, a decimal string or an expression in pi "
                f"(+ - * / ** and parentheses), got {value!r}"
            ) from exc
        if not (mpmath.isfinite(probe) and mpmath.im(probe) == 0):
            raise ValueError(f"Scene: {name} must be finite and real, got {value!r}")
        return expr
    raise ValueError(f"Scene: {name} must be int, float, str or mpmath.mpf, got {type(value).__name__}")


def _as_mpf(value: Union[Fraction, _Expr]) -> mpmath.mpf:
    if isinstance(value, _Expr):
        return value.mpf()
    return mpmath.mpf(value.numerator) / value.denominator


def _compare_key(value: Union[Fraction, _Expr]):
    """A value good enough for order checks between parameters (exact for rationals)."""
    if isinstance(value, Fraction):
        return value
    with mpmath.workprec(400):
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
            raise ValueError(f"Scene: F must be >= 0 (a phase shift of pi flips its sign), got {self.F!r}")
        if key["f"] < 0:
            raise ValueError(f"Scene: f must be >= 0 (friction dissipates), got {self.f!r}")
        if key["omega"] <= 0:
            raise ValueError(f"Scene: omega must be > 0, got {self.omega!r}")
        if key["r"] <= key["l"]:
            raise ValueError(f"Scene: r must be > l (the gap R = r - l is positive), got l={self.l!r}, r={self.r!r}")
        if not 0 <= key["restitution"] <= 1:
            raise ValueError(f"Scene: restitution must be in [0, 1], got {self.restitution!r}")
        if key["damping"] < 0:
            raise ValueError(f"Scene: damping must be >= 0, got {self.damping!r}")
        if key["wavenumber"] is not None and key["wavenumber"] <= 0:
            raise ValueError(f"Scene: wavenumber must be > 0 or None, got {self.wavenumber!r}")
        object.__setattr__(self, "_exact", exact)
        object.__setattr__(self, "_key", key)

    # -- values -----------------------------------------------------------------------
    def exact(self, name: str) -> Union[Fraction, "_Expr", None]:
        """The exact value of a parameter: a ``Fraction``, or a ``pi`` expression."""
        return self._exact[name]

    def mpf(self, name: str) -> mpmath.mpf:
        """A parameter as an ``mpf`` at the current mpmath precision (``None`` if unset)."""
        value = self._exact[name]
        return None if value is None else _as_mpf(value)

    def float(self, name: str) -> float:
        """A parameter as a correctly rounded float64 (``None`` if unset)."""
        value = self._exact[name]
        return None if value is None else float(value)

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
        """``T = 2 pi / omega`` in float64 (integrators compute their own at their precision)."""
        return 2 * math.pi / self.float("omega")

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
