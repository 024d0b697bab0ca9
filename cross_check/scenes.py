"""The paper's scenes, named after its figure labels, and the states of interest on each.

Scenes (paper, figure captions; every parameter an exact string or integer):

* ``fig:narrow``                -- F = 1, f = 0, w = 1, l = 0, r = 0.8 (Fig. 1a);
* ``fig:narrow-with-friction``  -- the same with f = 0.005 (Fig. 2);
* ``fig:wide:a`` / ``fig:wide:b`` -- R = 4 and R = 20, frictionless (Fig. 1c, 1d);
* ``fig:many:wide/f=0.1`` ... ``/f=0.6`` -- Fig. 1d's scene with f = 0.1, ..., 0.6 (Fig. 3);
* ``fig:many:2pi/f=...``        -- F = 1, w = 2 pi, l = -1, r = 1, f in {0.005, ..., 0.3} (Fig. 5);
* ``fig:resonance/R=...``       -- w = 2 pi, F = w^2, f = 24.65, l = 0, r in {0.89, 0.8932, 0.895}
  (Fig. 8, the 3:1 resonance);
* effect scenes (the paper's last section, issue 6): ``fig:xpotno`` (eq. ``xpot``: F = 1,
  f = 0.1, w = 2 pi, walls -1, 1, forcing ``F cos(pi x/2) cos(w t)``), ``effect:restitution``
  (Fig. 5's f = 0.05 scene with e = 0.9), ``effect:damping`` (the same with c = 0.05) and
  ``effect:zeno`` (Fig. 1a's frictionless scene with e = 0.8: chatter without friction);
* hard scenes (not figures): ``fold/near`` (Fig. 1d's scene with f/F = 2/pi - 1e-6, just below
  the fold eq. ``fold:bif``), ``fold/at`` (f/F = 2/pi exactly), ``stuck/F=f`` and ``stuck/F<f``
  (F <= f: a particle that stops stays stopped).

The registry (``scene(name)``, ``names()``): the built-in scenes above (``SCENES``) are its first
entries; scenes from a user's scene file or an inline ``--scene`` (``cross_check.scenefile``, the one
reader) are ``register``-ed after them under names that must not collide with a built-in one.
Every command looks scenes up here, so a registered scene gets everything a built-in one has.

States of interest per scene: a deterministic sample in the gap (``numpy`` PCG64, seed
``SEED`` + CRC32 of the scene name; float64 values, exact as binary numbers) plus the hard cases
of ``cross_check.agreement.hardcases`` (decimal strings, constructed by closed-form backward flights).
"""
from __future__ import annotations

import functools
import zlib

import numpy as np

from reference.scene import Scene
from cross_check.agreement.case import Case
from cross_check.agreement.hardcases import construct as construct_hard_cases

SEED = 20261122

_BASE_NARROW = dict(F=1, f=0, omega=1, l=0, r="0.8")
_BASE_2PI = dict(F=1, omega="2*pi", l=-1, r=1)
_RESONANCE = dict(F="(2*pi)**2", f="24.65", omega="2*pi", l=0)


def _build() -> dict[str, Scene]:
    out = {}

    def add(name, **params):
        out[name] = Scene(name=name, **params)

    add("fig:narrow", **_BASE_NARROW)
    add("fig:narrow-with-friction", **{**_BASE_NARROW, "f": "0.005"})
    add("fig:wide:a", F=1, f=0, omega=1, l=0, r=4)
    add("fig:wide:b", F=1, f=0, omega=1, l=0, r=20)
    for f in ("0.1", "0.2", "0.3", "0.4", "0.5", "0.6"):
        add(f"fig:many:wide/f={f}", F=1, f=f, omega=1, l=0, r=20)
    for f in ("0.005", "0.01", "0.05", "0.1", "0.2", "0.3"):
        add(f"fig:many:2pi/f={f}", f=f, **_BASE_2PI)
    for r in ("0.89", "0.8932", "0.895"):
        add(f"fig:resonance/R={r}", r=r, **_RESONANCE)
    add("fig:xpotno", F=1, f="0.1", omega="2*pi", l=-1, r=1, wavenumber="pi/2")
    add("effect:restitution", f="0.05", restitution="0.9", **_BASE_2PI)
    add("effect:damping", f="0.05", damping="0.05", **_BASE_2PI)
    add("effect:zeno", **{**_BASE_NARROW, "restitution": "0.8"})
    add("fold/near", F=1, f="2/pi - 0.000001", omega=1, l=0, r=20)
    add("fold/at", F=1, f="2/pi", omega=1, l=0, r=20)
    add("stuck/F=f", F=1, f=1, omega=1, l=0, r="0.8")
    add("stuck/F<f", F=1, f="1.5", omega=1, l=0, r="0.8")
    return out


#: All scenes by name (figure scenes first, in the paper's order).
SCENES: dict[str, Scene] = _build()

#: The scenes of the paper's figures (the rest are hard parameter sets).
FIGURE_SCENES = tuple(n for n in SCENES if n.startswith("fig:"))

#: A small representative subset for quick runs (one per figure family, plus friction).
QUICK_SCENES = ("fig:narrow", "fig:narrow-with-friction", "fig:many:wide/f=0.3",
                "fig:many:2pi/f=0.1", "fig:resonance/R=0.8932")


# ------------------------------------------------------------------ scene families (one parameter free)
def narrow(f=0, r="0.8") -> Scene:
    """Fig. narrow / narrow-with-friction: F = 1, w = 1, l = 0, r = 0.8."""
    return Scene(F=1, f=f, omega=1, l=0, r=r)


def wide(f=0, r=20) -> Scene:
    """Fig. wide:b / many:wide / fold: F = 1, w = 1, l = 0, r = 20."""
    return Scene(F=1, f=f, omega=1, l=0, r=r)


def two_pi(f) -> Scene:
    """Fig. many:2pi / f005 / three:per: F = 1, w = 2 pi, l = -1, r = 1."""
    return Scene(F=1, f=f, omega="2*pi", l=-1, r=1)


def resonance(r) -> Scene:
    """Fig. resonance: w = 2 pi, F = w^2, f = 24.65, l = 0."""
    return Scene(F="(2*pi)**2", f="24.65", omega="2*pi", l=0, r=r)


def xpot() -> Scene:
    """Fig. xpotno (eq. xpot): F = 1, f = 0.1, w = 2 pi, walls -1, 1, forcing F cos(pi x/2) cos(w t)."""
    return Scene(F=1, f="0.1", omega="2*pi", l=-1, r=1, wavenumber="pi/2")


#: Scenes registered after the built-ins (a user's scene file, an inline scene), by name.
_USER: dict[str, Scene] = {}


def register(sc: Scene) -> str:
    """Add a user's scene to the registry under ``sc.name`` (after the built-ins); returns the name.

    A name of a built-in scene is refused (``ValueError``); registering a name again replaces
    the earlier scene (a long-lived process -- a test session, a dask worker -- may verify two
    files that both use a name; one file's duplicates are refused by ``cross_check.scenefile``)."""
    if not isinstance(sc, Scene) or not sc.name:
        raise ValueError(f"register: a Scene with a name is required, got {sc!r}")
    if sc.name in SCENES:
        raise ValueError(f"scene name {sc.name!r} is taken by a built-in scene; choose another name")
    _USER[sc.name] = sc
    return sc.name


def names() -> list[str]:
    """Every scene of the registry: the built-ins first, then the registered ones."""
    return list(SCENES) + list(_USER)


def scene(name: str) -> Scene:
    """A scene by name, built-in or registered (ValueError lists the known names)."""
    found = SCENES.get(name) or _USER.get(name)
    if found is None:
        raise ValueError(f"scene must be one of {', '.join(names())}; got {name!r}")
    return found


def slug(name: str) -> str:
    """A file-name-safe form of a scene name (``fig:many:wide/f=0.1`` -> ``fig-many-wide_f=0.1``)."""
    return name.replace(":", "-").replace("/", "_")


def velocity_scale(sc: Scene) -> float:
    """``F / w``: the amplitude of the forced velocity (the paper's natural unit)."""
    return max(sc.float("F") / sc.float("omega"), 1e-300)


def sample_states(name: str, n: int, seed: int = SEED) -> list[Case]:
    """``n`` deterministic states in the open gap, ``|v| <= 2 F / w``.

    ``x = l + u R`` with ``u ~ U(0.01, 0.99)``, ``v ~ U(-2F/w, 2F/w)``, rounded to float64.
    """
    if n < 0:
        raise ValueError(f"n must be >= 0, got {n}")
    sc = scene(name)
    rng = np.random.default_rng(seed + zlib.crc32(name.encode()))
    l, r = sc.float("l"), sc.float("r")
    u = rng.uniform(0.01, 0.99, n)
    vmax = 2 * velocity_scale(sc)
    vs = rng.uniform(-vmax, vmax, n)
    out = []
    for i in range(n):
        x = float(min(max(l + u[i] * (r - l), l), r))
        out.append(Case(f"sample-{i}", repr(x), repr(float(vs[i])), "float64",
                        f"PCG64 seed {seed}+crc32(name), x = l + U(0.01,0.99) R, v = U(-2F/w, 2F/w)"))
    return out


@functools.lru_cache(maxsize=None)
def _hard_states(sc: Scene) -> tuple:
    """Keyed by the scene's parameters (a registered name may be re-registered)."""
    cases, notes = construct_hard_cases(sc)
    return tuple(Case(c.name, c.x, c.v, "decimal", c.how, c.kind, c.t_event) for c in cases), tuple(notes.items())


def hard_states(name: str) -> list[Case]:
    """The constructible hard cases of the scene (see ``cross_check.agreement.hardcases``)."""
    return list(_hard_states(scene(name))[0])


def hard_case_notes(name: str) -> dict[str, str]:
    """The hard cases the scene does not admit, each with the reason (``hardcases.construct``)."""
    return dict(_hard_states(scene(name))[1])


def states_of_interest(name: str, n_sample: int = 8, hard: bool = True) -> list[Case]:
    """Sample states followed by the hard cases."""
    return sample_states(name, n_sample) + (hard_states(name) if hard else [])
