"""Hypothesis strategies for the whole suite (one module; each area has its own section).

Scenes are drawn with exact decimal-string parameters so that both integrators see the
same exact problem; states are drawn inside the closed gap ``[l, r]``.
"""
from __future__ import annotations

import math
from fractions import Fraction

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
    """A state ``(x, v)`` with ``x`` in the closed gap and ``|v| <= vmax`` (floats).

    The walls are exact (e.g. ``r = 4/5``) while ``x`` is a float: a float rounded to the
    nearest may lie just outside, so ``x`` is moved inward by ulps until it is inside
    exactly (both integrators rightly reject a state outside the walls).
    """
    l, r = scene.float("l"), scene.float("r")
    u = draw(st.floats(0.0, 1.0))
    x = min(max(l + u * (r - l), l), r)
    while Fraction(x) > scene.exact("r"):
        x = math.nextafter(x, -math.inf)
    while Fraction(x) < scene.exact("l"):
        x = math.nextafter(x, math.inf)
    v = draw(st.floats(-vmax, vmax, allow_nan=False, allow_infinity=False))
    return x, v


# --- claims (the paper's closed forms: tests/test_paper_formulas.py, tests/test_claims.py) ---
@st.composite
def symmetric_scenes(draw, max_f_over_bound=1.0):
    """A base scene where the symmetric solutions of eq. nonstick exist: F = 1, ``f <= 2/pi``.

    ``l`` in [-1, 1], ``R`` in [0.5, 30]; ``omega`` in {1, 2 pi, 1/2}; ``f`` a decimal
    ``<= max_f_over_bound * 2/pi``.
    """
    f = draw(decimals(0.0, 0.6366 * max_f_over_bound))
    omega = draw(st.sampled_from(("1", "2*pi", "0.5")))
    l = draw(decimals(-1.0, 1.0, 2))
    R = draw(decimals(0.5, 30.0, 2))
    r = f"{float(l) + float(R):.2f}"
    return Scene(F="1", f=f, omega=omega, l=l, r=r)


# --- effects: position-dependent forcing (tests/test_taylor.py, tests/test_ode.py) ---------
@st.composite
def xpot_scenes(draw, damping=True):
    """Eq. ``xpot``'s family: F = 1, w = 2 pi, walls -1, 1, k = pi/2; ``f`` in [0, 0.3]
    and (optionally) viscous damping ``c`` in [0, 0.5]."""
    f = draw(decimals(0.0, 0.3, 3))
    c = draw(decimals(0.0, 0.5, 2)) if damping else "0"
    return Scene(F="1", f=f, omega="2*pi", l="-1", r="1", wavenumber="pi/2", damping=c)


@st.composite
def position_forced_scenes(draw, restitutions=("1", "0.9", "0.6", "0")):
    """Issue 33: position forcing with every effect drawn -- ``F`` in [0.3, 3], ``f = rho F``
    with ``rho`` in [0, 0.6], ``omega`` in [0.5, 7], ``l`` in [-2, 1], a gap of 0.2 .. 4, the
    wavenumber with ``k max(|l|, |r|, 1/2)`` in [0.1, 4], damping 0 or 0.01 .. 0.4, the
    restitution one of ``restitutions`` (exact decimal strings; the constructed events, run
    backward through impacts, need ``e > 0``)."""
    F = draw(decimals(0.3, 3.0, 3))
    f = f"{draw(decimals(0.0, 0.6, 3))}*{F}"
    omega = draw(decimals(0.5, 7.0, 3))
    l, gap = draw(decimals(-2.0, 1.0, 2)), draw(decimals(0.2, 4.0, 2))
    r = f"{(round(float(l) * 100) + round(float(gap) * 100)) / 100:.2f}"
    xmax = max(abs(float(l)), abs(float(r)), 0.5)
    k = f"{draw(decimals(0.1, 4.0, 3))}/{xmax:.2f}"
    c = draw(st.sampled_from(("0", "drawn")))
    c = draw(decimals(0.01, 0.4, 3)) if c == "drawn" else c
    e = draw(st.sampled_from(restitutions))
    return Scene(F=F, f=f, omega=omega, l=l, r=r, wavenumber=k, damping=c, restitution=e)


@st.composite
def flight_starts(draw, scene: Scene, vmax: float = 4.0):
    """``(t0, x0, v0, s)`` starting a flight: ``x0`` in the gap, ``s = sgn(v0)`` (either sign
    at ``v0 = 0``), ``t0`` in ``[0, T)``; floats (exact binary values at any precision)."""
    x, v = draw(states(scene, vmax=vmax))
    s = (1 if v > 0 else -1) if v != 0 else draw(st.sampled_from((1, -1)))
    t0 = draw(st.floats(0.0, 0.999)) * scene.period
    return t0, x, v, s


# --- reference (tests/test_reference_*.py) --------------------------------------------------
#: The paper's scenes (cross_check.scenes, module docstring), a representative of each family.
REFERENCE_SCENES = {
    "narrow_f0": Scene(F="1", f="0", omega="1", l="0", r="0.8"),
    "narrow_f0005": Scene(F="1", f="0.005", omega="1", l="0", r="0.8"),
    "wide_f03": Scene(F="1", f="0.3", omega="1", l="0", r="20"),
    "wide_f0": Scene(F="1", f="0", omega="1", l="0", r="20"),
    "2pi_f01": Scene(F="1", f="0.1", omega="2*pi", l="-1", r="1"),
    "2pi_f0005": Scene(F="1", f="0.005", omega="2*pi", l="-1", r="1"),
    "resonance": Scene(F="(2*pi)**2", f="24.65", omega="2*pi", l="0", r="0.8932"),
}


@st.composite
def exact_states(draw, scene: Scene, vmax: float = 2.0, places: int = 6):
    """``(x, v)`` as decimal strings, ``x`` inside the *exact* closed gap ``[l, r]``.

    (The shared ``states`` draws floats, whose binary value can fall just outside a wall
    given as a decimal, e.g. ``float('0.8') > 4/5``; the reference rejects those.)
    """
    from fractions import Fraction

    l, r = Fraction(scene.exact("l")), Fraction(scene.exact("r"))
    scale = 10 ** places
    lo, hi = -(-l * scale // 1), r * scale // 1          # ceil(l), floor(r) in 10^-places
    n = draw(st.integers(int(lo), int(hi)))
    sign, (whole, frac) = ("-" if n < 0 else ""), divmod(abs(n), scale)
    x = f"{sign}{whole}.{frac:0{places}d}"
    v = draw(decimals(-vmax, vmax, places))
    return x, v


@st.composite
def reference_cases(draw, friction=True, vmax=2.0):
    """A paper scene (with or without friction) and an exact state in its gap."""
    names = [k for k, s in REFERENCE_SCENES.items() if friction or not s.has("friction")]
    scene = REFERENCE_SCENES[draw(st.sampled_from(sorted(names)))]
    x, v = draw(exact_states(scene, vmax=vmax))
    return scene, x, v


# --- scenes (cross_check front door: the paper's named scenes) ------------------------
@st.composite
def named_scene_states(draw, names=None, vmax_factor: float = 2.0):
    """``(name, x, v)``: a scene of ``cross_check.scenes`` and a float64 state strictly
    inside its gap (``x = l + u R``, ``u`` in ``[0.001, 0.999]``), ``|v| <= vmax_factor F/w``."""
    from cross_check import scenes as named

    name = draw(st.sampled_from(sorted(names or set(named.FIGURE_SCENES))))
    sc = named.scene(name)
    l, r = sc.float("l"), sc.float("r")
    u = draw(st.floats(0.001, 0.999))
    vmax = vmax_factor * named.velocity_scale(sc)
    v = draw(st.floats(-vmax, vmax, allow_nan=False, allow_infinity=False))
    return name, l + u * (r - l), v


# --- fast (float64 engine, issue 3: tests/test_fast_*.py) ----------------------------------
@st.composite
def fast_batches(draw, scene: Scene, n: int = 16, vmax: float = 2.0):
    """A batch of ``n`` float64 states in the closed gap (a hypothesis-drawn seed)."""
    import numpy as np

    seed = draw(st.integers(0, 2 ** 32 - 1))
    rng = np.random.default_rng(seed)
    l, r = scene.float("l"), scene.float("r")
    x = np.clip(rng.uniform(l, r, n), l, r)
    v = rng.uniform(-vmax, vmax, n)
    return x, v


# --- effects: chatter (tests/test_reference_chatter.py) -------------------------------------
@st.composite
def chattering_orbits(draw):
    """``(scene, x, v)``: a particle on the wall ``r = 1`` at ``t = 0`` moving into it with a
    small speed ``u0`` while ``A = cos 0 = 1`` pushes (``F = w = 1``, ``l = 0``).

    Either ``f = 0`` with restitution ``e`` in [0.3, 0.97] or ``e`` in [0.8, 1] with
    ``f`` in [0.02, 0.5]; ``u0`` is at most ``0.3 / c1`` with the frozen-force tail length
    per unit speed ``c1 = e (1/(1+f) + 1/sqrt(1-f^2)) / (1 - rho)``, ``rho = e sqrt((1-f)/(1+f))``:
    the tail (<= 0.3) ends while ``cos t >= cos 0.3 > 0.95 > f`` still pushes.
    """
    if draw(st.booleans()):
        e, f = draw(decimals(0.3, 0.97, 2)), "0"
    else:
        e, f = draw(decimals(0.8, 1.0, 2)), draw(decimals(0.02, 0.5, 2))
    ef, ff = float(e), float(f)
    rho = ef * math.sqrt((1 - ff) / (1 + ff))
    c1 = ef * (1 / (1 + ff) + 1 / math.sqrt(1 - ff * ff)) / (1 - rho)
    u0 = draw(st.floats(0.01, 1.0)) * min(0.1, 0.3 / c1)
    return Scene(F="1", f=f, omega="1", l="0", r="1", restitution=e), "1", f"{u0:.6g}"


# --- untrusted scene values (issue 29: tests/test_scene_bounds.py, tests/test_engine_ranges.py) ---
_ATOMS = ("0", "1", "2", "9", "10", "pi", "0.5", "1e3", "1.0000001", "(2**1000000)", "-1", "0x1F",
          "1e308", "1e-308", "123456789012345678901234567890", "(pi-3)", "3.14159265358979")


@st.composite
def hostile_expressions(draw):
    """Scene values as a hostile file would write them: towers of powers, deep nesting,
    unary chains, huge and tiny literals, long sums and products, and arithmetic trees of
    all of these -- each must evaluate or be refused at once (``reference.expression``)."""
    atom = st.sampled_from(_ATOMS)
    kind = draw(st.sampled_from(("tower", "nest", "unary", "literal", "sum", "tree", "long")))
    if kind == "tower":
        return "**".join(draw(st.lists(atom, min_size=2, max_size=7)))
    if kind == "nest":
        n = draw(st.integers(1, 200))
        return "(" * n + draw(atom) + ")" * n
    if kind == "unary":
        return "".join(draw(st.lists(st.sampled_from("-+"), min_size=1, max_size=300))) + draw(atom)
    if kind == "literal":
        mant = draw(st.sampled_from(("1", "9.99", "0", "123456789", "0.000001")))
        return f"{mant}e{draw(st.integers(-10 ** 12, 10 ** 12))}"
    if kind == "sum":
        op = draw(st.sampled_from("+-*/"))
        return op.join(draw(st.lists(atom, min_size=2, max_size=150)))
    if kind == "long":
        return draw(atom) * draw(st.integers(1, 400))
    tree = st.recursive(atom, lambda inner: st.tuples(inner, st.sampled_from(["+", "-", "*", "/", "**"]), inner)
                        .map(lambda t: f"({t[0]}{t[1]}{t[2]})"), max_leaves=24)
    return draw(tree)


def _log_decimal(lo: int, hi: int):
    """Decimal strings ``m e k`` with ``k`` in ``[lo, hi]`` (log-uniform magnitudes)."""
    return st.tuples(st.integers(1, 9), st.integers(lo, hi)).map(lambda mk: f"{mk[0]}e{mk[1]}")


@st.composite
def extreme_scenes(draw, position_forcing=False):
    """Scenes with extreme but legal values: ``F``, ``omega``, the gap and the wall offset
    anywhere in ``1e-150 .. 1e150`` (beyond what float64 holds with room, ``fast.params``),
    ``f`` from 0 to ``2 F``, damping from 0 to ``100 omega``, any restitution; optionally a
    wavenumber of ``0.1 .. 3`` per gap."""
    F, w, gap = (draw(_log_decimal(-150, 150)) for _ in range(3))
    f = draw(st.sampled_from(("0", f"0.3*{F}", f"2*{F}", draw(_log_decimal(-150, 150)))))
    c = draw(st.sampled_from(("0", f"1e-20*{w}", f"0.5*{w}", f"100*{w}")))
    e = draw(st.sampled_from(("1", "0.5", "0")))
    l = draw(st.sampled_from(("0", f"-({gap})", draw(_log_decimal(-150, 150)))))
    k = f"1.5/({gap})" if position_forcing else None
    return Scene(F=F, f=f, omega=w, l=l, r=f"{l}+{gap}", damping=c, restitution=e, wavenumber=k)


# --- enclosures: wrong point logs (tests/test_walk_negative.py, issue 24) -------------------
@st.composite
def log_perturbations(draw):
    """``(op, where, size)``: a wrong point log from a right one -- ``remove`` an event, ``add``
    a copy of one ``size`` T later, or ``shift`` one by ``size`` T -- at the event ``where``
    (a fraction of the log's length, in ``[0, 1)``); ``size = +-10^k``, ``k`` in ``[-12, -2]``."""
    op = draw(st.sampled_from(("remove", "add", "shift")))
    where = draw(st.floats(0.0, 1.0, exclude_max=True))
    size = draw(st.sampled_from((1, -1))) * 10.0 ** draw(st.integers(-12, -2))
    return op, where, size


# --- enclosures: boxes at x1's sticking boundary (tests/test_impacts_negative.py, issue 34) ---
def x1_sticking_r(f: Fraction):
    """``w^2 R / F`` on x1's sticking boundary at ``f/F`` (``F = w = 1``, ``l = 0``): where
    eq. ``nonstick:cond``'s left side (``reference.paper``, linear in ``R`` with slope 1)
    vanishes, as an mpf; it falls as ``f`` grows (1.138 at 0.06, 1.058 at 0.3, 0.886 at 0.5)."""
    import mpmath

    from reference import paper

    sc = Scene(F=1, f=f, omega=1, l=0, r=20)
    with mpmath.workdps(30):
        return 20 - paper.nonstick_condition_printed(sc, dps=30)


@st.composite
def sticking_boundary_boxes(draw):
    """A small ``ParamBox`` (``F = w = 1``, ``l = 0``, ``e = 1``) at x1's sticking boundary:
    ``f`` from ``f_lo`` in [0.05, 0.6], ``r`` from ``R*(f_lo) (1 + d)`` with ``d`` in
    [-0.002, 0.04] (the corner ``(f_lo, r_lo)`` is the box's nearest to the boundary, ``R*``
    falling in ``f``: ``d < 0`` puts it on the sticking side), each width ``10^-4``,
    ``4 10^-4`` or ``1.6 10^-3`` (about the widest the prover takes this close)."""
    from reference.enclosure import ParamBox

    f_lo = Fraction(draw(decimals(0.05, 0.6, 3)))
    d = Fraction(draw(st.integers(-20, 400)), 10000)
    r_lo = Fraction(round(x1_sticking_r(f_lo) * (1 + float(d)) * 10 ** 5), 10 ** 5)
    wf, wr = (Fraction(draw(st.sampled_from((1, 4, 16))), 10000) for _ in range(2))
    return ParamBox(F=1, f=(f_lo, f_lo + wf), omega=1, l=0, r=(r_lo, r_lo + wr))


# --- dissip-invariance: scenes for the return-to-rest cover (tests/test_dissip_invariance.py) ----
@st.composite
def rest_scenes(draw):
    """A scene with every effect the cover supports: ``F`` of a few sizes, ``f/F`` in
    ``(0, 1.2]`` (below and above the fold and ``F``), one of three ``omega``, a gap of
    ``0.5 .. 6``, restitution ``e`` in ``(0, 1]``, damping 0 or up to ``0.2 omega``."""
    F = draw(st.sampled_from(("1", "0.5", "3")))
    f = f"{draw(decimals(0.05, 1.2, 3))}*{F}"
    omega = draw(st.sampled_from(("1", "2*pi", "0.7")))
    l = draw(decimals(-1.0, 1.0, 2))
    gap = draw(decimals(0.5, 6.0, 2))
    e = draw(st.sampled_from(("1", "0.9", "0.5")))
    c = draw(st.sampled_from(("0", "0", f"0.2*{omega}")))
    return Scene(F=F, f=f, omega=omega, l=l, r=f"{l}+{gap}", restitution=e, damping=c)
