"""The reference's precision promise on very short flights (issue 18): a run at ``dps`` digits
agrees with one at ``dps + 20`` to about ``10^(2 - dps)``, at dps 20, 50 and 100, on states whose
flights are very short -- the exact (decimal) hard cases of the hard-case scenes (chatter
bounces, grazing, release at the stick-slip boundary, sticking), and
gaps of 1e-6 (about a thousand impacts a period).  At dps 50 alone the guard digits would hide a
loss confined to such flights; three precisions do not.
"""
import mpmath
import pytest

import reference
from cross_check import scenes
from cross_check.tolerances import tol
from reference.model import Model
from reference.scene import Scene

DPS = (20, 50, 100)
_TINY = Scene(F=1, f="0.1", omega=1, l=0, r="1e-6")
#: the short-flight hard cases; not ``crossing_pair`` and ``turn_at_wall``: built exactly on an
#: itinerary switch, where ``Phi`` has a square-root singularity (no Lipschitz bound, the band),
#: so a ``dps``-digit run can differ from a ``dps + 20`` one far above 10^-dps (measured: 6e-14
#: at dps 20) without any loss of precision in the flights -- the threshold pairs test them
#: from both sides instead
_SHORT = ("grazing", "stick_slip_boundary", "sticking", "chatter")


def _states():
    out = []
    for name in ("fig:narrow-with-friction", "fig:many:2pi/f=0.1", "fig:many:wide/f=0.3"):
        out += [(f"{name}/{c.name}", scenes.scene(name), c.x, c.v) for c in scenes.hard_states(name)
                if c.name in _SHORT]
    out += [("gap 1e-6/flying", _TINY, "5e-7", "1e-5"), ("gap 1e-6/at rest on l", _TINY, "0", "0")]
    return out


STATES = _states()


@pytest.mark.parametrize("dps", DPS)
@pytest.mark.parametrize("name, scene, x, v", STATES, ids=[s[0] for s in STATES])
def test_self_agreement_on_short_flights(name, scene, x, v, dps):
    with mpmath.workdps(dps + 30):
        x0, v0 = mpmath.mpf(x), mpmath.mpf(v)
    a = reference.stroboscopic_map(scene, x0, v0, dps=dps)
    b = reference.stroboscopic_map(scene, x0, v0, dps=dps + 20)
    bound = tol("reference_short_flight_lost_digits").rtol * mpmath.mpf(10) ** -dps
    with mpmath.workdps(dps + 30):
        err = max(abs(a[0] - b[0]) / max(1, abs(b[0])), abs(a[1] - b[1]) / max(1, abs(b[1])))
    assert err <= bound, f"{name} at dps {dps}: {mpmath.nstr(err, 3)} > {mpmath.nstr(bound, 3)}"


def test_the_states_are_short_flights():
    assert len(STATES) >= 12
    assert {s[0].rsplit("/", 1)[1] for s in STATES} >= {"chatter", "grazing", "stick_slip_boundary", "at rest on l"}


# --- damped flights shorter than 1e-7 T (issue 24) --------------------------------------------
#: flights from rest at the wall ``x0 = l = 0`` (a release; ``x`` is then the displacement
#: itself, ``~ (A - s f) h^2 / 2``, built from terms that cancel to ``O(h^2)``: ``1 - cos``,
#: ``theta - sin theta``, ``exp(-c h) - 1 + c h``); undamped too (the raised-precision
#: ``theta - sin theta`` of ``BaseFlight``)
FLIGHT_SCENES = {
    "damped c=0.05": Scene(F=1, f="0.05", omega="2*pi", l=0, r=1, damping="0.05"),
    "damped c=2": Scene(F=1, f="0.2", omega=1, l=0, r=1, damping="2"),
    "damped, frictionless": Scene(F=1, f=0, omega=1, l=0, r=1, damping="0.5"),
    "undamped": Scene(F=1, f="0.1", omega=1, l=0, r=1),
}
#: flight lengths in units of T (all < 1e-7 T); at dps d only those the start time 3/8
#: resolves with 8 digits to spare
LENGTHS = ("1e-8", "1e-10", "1e-12", "1e-17", "1e-25", "1e-40", "1e-60", "1e-90")


def _exact_flight(scene, t0, h, v0, s, dps):
    """``(x, v)`` of the flight from ``(t0, 0, v0)`` at ``t0 + h`` from the plain closed forms
    (the particular solution of the module docstring of ``reference.flows``, not its
    regrouped evaluation), at ``dps`` digits -- enough to absorb their cancellation."""
    with mpmath.workdps(dps):
        F, f, w, c = (scene.mpf(k) for k in ("F", "f", "omega", "damping"))
        t = t0 + h
        if c == 0:
            x = v0 * h + F / w ** 2 * (mpmath.cos(w * t0) - mpmath.cos(w * t) - w * h * mpmath.sin(w * t0)) \
                - s * f * h * h / 2
            return x, v0 + F / w * (mpmath.sin(w * t) - mpmath.sin(w * t0)) - s * f * h
        P, Q = F * c / (c * c + w * w), F * w / (c * c + w * w)
        vp = lambda u: P * mpmath.cos(w * u) + Q * mpmath.sin(w * u) - s * f / c
        Xp = lambda u: (P * mpmath.sin(w * u) - Q * mpmath.cos(w * u)) / w - s * f * u / c
        E = mpmath.exp(-c * h)
        return Xp(t) - Xp(t0) + (v0 - vp(t0)) * (1 - E) / c, vp(t) + (v0 - vp(t0)) * E


@pytest.mark.parametrize("dps", DPS)
@pytest.mark.parametrize("name", list(FLIGHT_SCENES))
def test_flights_shorter_than_1e_7_T_keep_their_digits(name, dps):
    """From rest at ``x0 = 0`` (``s = +1``, then ``v0 = h F``: comparable terms), ``t0 = 3/8``:
    ``x`` and ``v`` to ``10^(2 - dps)`` relative to themselves, against the plain closed
    forms at ``3 dps + 40`` digits."""
    scene = FLIGHT_SCENES[name]
    bound = tol("reference_short_flight_rel").rtol * mpmath.mpf(10) ** -dps
    checked = 0
    for length in LENGTHS:
        if mpmath.mpf(length) < mpmath.mpf(10) ** (8 - dps):
            continue
        for s, v0_over_h in ((1, 0), (1, 1), (-1, -1)):
            with mpmath.workdps(dps):
                model = Model(scene)
                t0 = mpmath.mpf(3) / 8
                t = t0 + mpmath.mpf(length) * model.T
                h = t - t0                                  # exact: what the flight sees
                v0 = v0_over_h * h
                x, v, _ = model.flight(t0, mpmath.mpf(0), v0, s).evaluate(t)
            xe, ve = _exact_flight(scene, t0, h, v0, s, 3 * dps + 40)
            with mpmath.workdps(3 * dps + 40):
                err = max(abs(x - xe) / abs(xe), abs(v - ve) / abs(ve))
                assert err <= bound, (name, dps, length, s, v0_over_h, mpmath.nstr(err, 3))
            checked += 1
    assert checked >= 9          # three lengths at least, even at dps 20


@pytest.mark.parametrize("dps", DPS)
@pytest.mark.parametrize("scene", [Scene(F=1, f="0.2", omega=1, l=0, r=1),
                                   Scene(F=1, f=0, omega=1, l=0, r=1, restitution="0.8")],
                         ids=["friction", "restitution"])
def test_chatter_bounces_shorter_than_1e_7_T_keep_their_digits(scene, dps):
    """A bounce of a chatter run (``reference.chatter.wall_bounce``, wall-relative: ``theta -
    sin theta`` of its own, at raised precision) of speed ``10^-9 .. 10^-(dps - 8)`` -- durations
    far below 1e-7 T: duration, height and next speed to ``10^(2 - dps)`` relative, against the
    same bounce at ``dps + 30``."""
    from reference import chatter
    bound = tol("reference_short_flight_rel").rtol * mpmath.mpf(10) ** -dps
    for exponent in sorted({9, 15, dps - 8}):
        out = []
        for digits in (dps, dps + 30):
            with mpmath.workdps(digits):
                b = chatter.wall_bounce(Model(scene), mpmath.mpf("0.3"), 1,
                                        mpmath.mpf(10) ** -exponent, mpmath.mpf(10))
                out.append((b.duration, b.height, b.speed))
        with mpmath.workdps(dps + 30):
            for got, want in zip(*out):
                assert abs(got / want - 1) <= bound, (exponent, mpmath.nstr(got / want - 1, 3))
