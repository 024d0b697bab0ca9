"""Hypothesis strategies for the whole suite (one module; each area has its own section).

Scenes are drawn with exact decimal-string parameters so that both integrators see the
same exact problem; states are drawn inside the closed gap ``[l, r]``.
"""
from __future__ import annotations

from hypothesis import strategies as st

from reference.scene import Scene


# --- scenes and states (shared) -------------------------------------------------------
def decimals(lo: float, hi: float, places: int = 4):
    """Decimal strings in ``[lo, hi]`` with ``places`` digits: exact at any precision."""
    scale = 10 ** places
    return st.integers(int(round(lo * scale)), int(round(hi * scale))).map(
        lambda n: f"{n / scale:.{places}f}")


@st.composite
def scenes(draw, friction=True, max_f_over_F=0.6, omegas=("1", "2*pi")):
    """A base-model scene (paper's eq. main): F = 1, one of the paper's omegas, a gap."""
    F = "1"
    f = draw(decimals(0.0, max_f_over_F)) if friction else "0"
    omega = draw(st.sampled_from(omegas))
    l = draw(decimals(-1.0, 0.0, 2))
    R = draw(decimals(0.5, 4.0, 2))
    r = f"{float(l) + float(R):.2f}"
    return Scene(F=F, f=f, omega=omega, l=l, r=r)


@st.composite
def states(draw, scene: Scene, vmax: float = 2.0):
    """A state ``(x, v)`` with ``x`` in the closed gap and ``|v| <= vmax`` (floats)."""
    l, r = scene.float("l"), scene.float("r")
    u = draw(st.floats(0.0, 1.0))
    x = min(max(l + u * (r - l), l), r)
    v = draw(st.floats(-vmax, vmax, allow_nan=False, allow_infinity=False))
    return x, v
