"""Parameters as intervals: a :class:`ParamBox` is a scene whose parameters may be boxes.

``ParamBox(F=1, f=("0.1", "0.125"), omega=1, l=0, r=(20, 21))`` is every scene with ``F = 1``,
``0.1 <= f <= 0.125``, ``omega = 1``, ``l = 0`` and ``20 <= r <= 21``.  Each parameter is a
value as :class:`reference.scene.Scene` accepts it (int, float, decimal string, a ``pi``
expression, Fraction, mpf), or a pair ``(lo, hi)`` of such values with ``lo <= hi``: the
endpoints are *exact*, and ``reference.enclosure`` turns each parameter into the ball
``[lo, hi]`` (``balls.parameter``), so every certain comparison of the walk holds for every
parameter of the box at once.  A box whose pairs all have ``lo == hi`` is a point: the
enclosure API then runs exactly the point code on :meth:`ParamBox.scene`.

Which effects are on is decided for the whole box (``has``): friction if ``f > 0`` somewhere,
restitution if ``e != 1`` somewhere, damping if ``c > 0`` somewhere.  Two mixtures need care:

* ``f`` in ``[0, hi]`` mixes frictionless and friction scenes.  The walk uses the friction
  model for the whole box, which *is* the frictionless motion at ``f = 0`` as long as the
  velocity keeps its sign on each flight (``x'' = F cos wt - s f`` with ``f = 0``), a turn
  being a smooth reversal (its Table 1 factor ``(|A| - f)/(|A| + f)`` is 1 at ``f = 0``).
  Sticking is refused in such a box (at ``f = 0`` there is none): ``friction_mixed``;
* damping in ``[0, hi]`` with ``hi > 0`` is refused (``ValueError``): the damped flight has
  ``1/c``, which has no ball over ``c = 0``.

Position-dependent forcing has no closed-form flight and is not accepted in a box.
"""
from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from reference.scene import EFFECTS, Scene, _compare_key, _exact

PARAMS = ("F", "f", "omega", "l", "r", "restitution", "damping")


def _text(exact) -> str:
    """An exact value as text ``Scene`` reads back exactly (a fraction or a ``pi`` expression)."""
    if isinstance(exact, Fraction):
        return str(exact.numerator) if exact.denominator == 1 else f"({exact.numerator}/{exact.denominator})"
    return f"({exact.text})"


def _midpoint(lo, hi):
    if lo == hi:
        return _plain(lo)
    if isinstance(lo, Fraction) and isinstance(hi, Fraction):
        return (lo + hi) / 2
    return f"({_text(lo)} + {_text(hi)})/2"


@dataclass(frozen=True, init=False)
class ParamBox:
    """A box of scenes (module docstring).  ``bounds[name] = (lo, hi)``, exact values."""

    bounds: tuple

    def __init__(self, F, f, omega, l, r, restitution=1, damping=0, wavenumber=None):
        if wavenumber is not None:
            raise ValueError("ParamBox: position-dependent forcing (wavenumber) has no closed-form "
                             "flight; only wavenumber=None is accepted in a parameter box")
        given = dict(F=F, f=f, omega=omega, l=l, r=r, restitution=restitution, damping=damping)
        pairs = []
        for name in PARAMS:
            value = given[name]
            lo, hi = value if isinstance(value, (tuple, list)) and len(value) == 2 else (value, value)
            if isinstance(value, (tuple, list)) and len(value) != 2:
                raise ValueError(f"ParamBox: {name} must be a number or a pair (lo, hi), got {value!r}")
            a, b = _exact(name, lo), _exact(name, hi)
            if _compare_key(a) > _compare_key(b):
                raise ValueError(f"ParamBox: {name} must have lo <= hi, got ({lo!r}, {hi!r})")
            pairs.append((name, a, b))
        object.__setattr__(self, "bounds", tuple(pairs))
        ex = self._exact_map()
        # the whole box is valid iff its extreme corners are (each constraint is monotone;
        # r > l needs r_lo > l_hi): Scene's validation names the parameter and its range
        low = {k: _plain(v[0]) for k, v in ex.items()}
        high = {k: _plain(v[1]) for k, v in ex.items()}
        Scene(**{**low, "l": high["l"]})
        Scene(**{**high, "l": low["l"]})
        c_lo, c_hi = ex["damping"]
        if c_lo == 0 and _compare_key(c_hi) > 0:
            raise ValueError("ParamBox: damping must be exactly 0 or a box with lo > 0 (the damped "
                             f"flight has 1/c), got ({c_lo}, {c_hi})")

    def _exact_map(self) -> dict:
        return {name: (a, b) for name, a, b in self.bounds}

    # -- the Scene-like interface reference.enclosure reads --------------------------------
    def exact(self, name: str):
        """The exact value of a parameter if it is a point, else the pair ``(lo, hi)``."""
        if name == "wavenumber":
            return None
        lo, hi = self._exact_map()[name]
        return lo if lo == hi else (lo, hi)

    def lo(self, name: str):
        return self._exact_map()[name][0]

    def hi(self, name: str):
        return self._exact_map()[name][1]

    def has(self, effect: str) -> bool:
        """Whether ``effect`` is on for *some* parameter of the box (see the module docstring)."""
        if effect not in EFFECTS:
            raise ValueError(f"unknown effect {effect!r}; known: {', '.join(EFFECTS)}")
        ex = {k: tuple(_compare_key(v) for v in pair) for k, pair in self._exact_map().items()}
        return {"walls": True, "forcing": ex["F"][1] > 0, "friction": ex["f"][1] > 0,
                "restitution": ex["restitution"][0] < 1, "damping": ex["damping"][1] > 0,
                "position_forcing": False}[effect]

    @property
    def friction_mixed(self) -> bool:
        """``f`` spans ``[0, hi]`` with ``hi > 0``: frictionless and friction scenes together."""
        lo, hi = self._exact_map()["f"]
        return lo == 0 and _compare_key(hi) > 0

    @property
    def is_point(self) -> bool:
        return all(a == b for _, a, b in self.bounds)

    def point(self, **values) -> Scene:
        """The scene at the given values (others at the box's midpoint); no check that they lie
        in the box (:meth:`contains` does)."""
        ex = self._exact_map()
        args = {k: (values[k] if k in values else _midpoint(*ex[k])) for k in PARAMS}
        return Scene(**args)

    def midpoint(self) -> Scene:
        """The scene at the box's centre (the point integrator's itinerary is taken there)."""
        return self.point()

    def scene(self) -> Scene:
        """The one scene of a point box (``ValueError`` for a proper box)."""
        if not self.is_point:
            raise ValueError(f"ParamBox.scene: not a point: {self!r}")
        return self.midpoint()

    def contains(self, scene: Scene) -> bool:
        """Whether every parameter of ``scene`` lies in the box (exact comparisons for rationals,
        400 bits for ``pi`` expressions)."""
        ex = self._exact_map()
        return all(_compare_key(ex[k][0]) <= _compare_key(scene.exact(k)) <= _compare_key(ex[k][1])
                   for k in PARAMS) and scene.wavenumber is None

    def mid(self, name: str):
        """The exact midpoint of a parameter (as ``ParamBox`` accepts it)."""
        return _plain(_midpoint(*self._exact_map()[name]))

    def width(self, name: str) -> Fraction:
        lo, hi = self._exact_map()[name]
        return _compare_key(hi) - _compare_key(lo)

    def replace(self, **changes) -> "ParamBox":
        """A copy with some parameters (numbers or pairs) changed."""
        ex = {k: (a if a == b else (a, b)) for k, a, b in self.bounds}
        ex.update(changes)
        return ParamBox(**{k: _plain(v) for k, v in ex.items()})

    def split(self, name: str) -> tuple:
        """The two halves of the box along ``name`` (at the exact midpoint)."""
        lo, hi = self._exact_map()[name]
        mid = _midpoint(lo, hi)
        return self.replace(**{name: (lo, mid)}), self.replace(**{name: (mid, hi)})

    def __hash__(self):
        return hash(self.bounds)

    def __repr__(self):
        parts = []
        for name, a, b in self.bounds:
            if name in ("restitution", "damping") and a == b and a == (1 if name == "restitution" else 0):
                continue
            parts.append(f"{name}={_repr(a)}" if a == b else f"{name}=({_repr(a)}, {_repr(b)})")
        return f"ParamBox({', '.join(parts)})"


def _plain(value):
    """An exact value (or pair) as input ``ParamBox`` accepts."""
    if isinstance(value, tuple):
        return tuple(_plain(v) for v in value)
    return value if isinstance(value, (Fraction, str, int)) else value.text


def _repr(exact) -> str:
    return repr(str(exact)) if isinstance(exact, Fraction) else repr(exact.text)
