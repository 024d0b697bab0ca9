"""The hand-off of a validated flight's set through an event (``reference.enclosure.handoff``).

The hand-off is a construction, not a check: no later certificate of the walk would notice a
wrong set.  So it is held to the truth from outside.  A box of starts ``1e-30`` wide is proved
over one period, and true motions from its corners and centre (the point reference at
60 digits: ``reference.trajectory``, its own Taylor flights and event finder) must have the
proof's itinerary, every event time in its ball and ``Phi`` in the proved ball.  The corners
are where a wrong shape of the set shows: a set is a parallelogram, and the corners of the box
map to its extreme points.

The default run holds the box with turns and impacts (``FRICTION``); the frictionless and the
lossy boxes, and the mutants on the frictionless one, are slow.

The check is seen to fail: a hand-off that drops one term of ``dz_b/dr`` (the rate before or
after the event times ``dtau*/dr``) or does not run the centre back to ``base`` gives a proof
that some true motion leaves.  And the hand-off is seen to gain: a point start's ``Phi`` at 192
bits, ~1e-38 wide with the old hand-off of balls (33 events), is now ~1e-54.
"""
import functools

import mpmath
import pytest

import reference
from reference.enclosure import enclose_map, handoff
from reference.enclosure.balls import workprec
from reference.scene import Scene
from tests.enclosure_checks import DPS, inside

FRICTIONLESS = Scene(F=2, f=0, omega="0.5", l=-1, r=1, wavenumber=2)
FRICTION = Scene(F=3, f="0.3", omega="0.5", l=-2, r=2, wavenumber=2)
LOSSY = Scene(F=2, f="0.2", omega=1, l="-0.5", r="0.5", wavenumber="1.5", damping="0.1", restitution="0.8")
RADIUS = mpmath.mpf("1e-30")
PREC = 192

#: (scene, x, v): 11 impacts; 15 turns and 15 impacts (a run in towards a wall), a stick and a
#: slip; 7 impacts and 2 turns with damping and restitution 0.8 (from the point reference)
BOXES = [(FRICTIONLESS, "-0.7", "1.2"), (FRICTION, "1.5", "-1"), (LOSSY, "0.1", "3")]


def _samples(x, v):
    """The box's corners and centre."""
    with mpmath.workdps(DPS):
        X, V = mpmath.mpf(x), mpmath.mpf(v)
        return [(X + i * RADIUS, V + j * RADIUS) for i, j in ((-1, -1), (-1, 1), (1, -1), (1, 1), (0, 0))]


@functools.lru_cache(maxsize=None)
def _truth(scene, x, v):
    """``[(sample, events, Phi)]``: the point reference from each sample over one period."""
    T = 2 * mpmath.pi / scene.mpf("omega")
    out = []
    for xs, vs in _samples(x, v):
        with mpmath.workdps(DPS):
            log = list(reference.trajectory(scene, xs, vs, T, dps=DPS))
            out.append(((xs, vs), log, reference.stroboscopic_map(scene, xs, vs, dps=DPS)))
    return out


def _outside(enc, scene, x, v):
    """The true motions from the box's samples that leave the proof ``enc``: ``[(sample,
    what)]`` (an itinerary, an event time or ``Phi`` that is not in its ball)."""
    out = []
    for sample, log, end in _truth(scene, x, v):
        with workprec(enc.prec):
            if [e.kind for e in log] != [e.kind for e in enc.events]:
                out.append((sample, "itinerary"))
            elif not all(inside(b.t, p.t) for b, p in zip(enc.events, log)):
                out.append((sample, "an event time"))
            elif not (inside(enc.phi[0], end[0]) and inside(enc.phi[1], end[1])):
                out.append((sample, "Phi"))
    return out


def _prove(scene, x, v):
    return enclose_map(scene, x, v, x_radius=RADIUS, v_radius=RADIUS, prec=PREC, max_prec=PREC)


#: the default run holds the box with turns and impacts; the frictionless and the lossy one are slow
SLOW_BOXES = [pytest.param(*b, marks=pytest.mark.slow) if b[0] is not FRICTION else b for b in BOXES]


@pytest.mark.parametrize("scene, x, v", SLOW_BOXES)
def test_every_true_motion_from_the_box_stays_in_the_handed_sets(scene, x, v, monkeypatch):
    used = []
    real = handoff.Handoff.start

    def counted(self, *args):
        out = real(self, *args)
        used.append(out is not None)
        return out

    monkeypatch.setattr(handoff.Handoff, "start", counted)
    enc = _prove(scene, x, v)
    assert enc.proved, enc.reason
    assert sum(used) >= 5                           # the sets were handed, not the old boxes
    assert _outside(enc, scene, x, v) == []


def _no_rate_before(M, j, DJ, pre, post):
    """``DJ M - z'+ dtau``: the jump's own move along the flow before the event left out."""
    dtau = [-M[j][k] / pre[j] for k in range(2)]
    return [[sum(DJ[i][n] * M[n][k] for n in range(2)) - post[i] * dtau[k] for k in range(2)]
            for i in range(2)]


def _no_rate_after(M, j, DJ, pre, post):
    return REAL_GRADIENT(M, j, DJ, pre, [0 * p for p in post])


REAL_GRADIENT = handoff.gradient
MUTANTS = {"gradient": [_no_rate_before, _no_rate_after],
           "_back": [lambda post, t, z, base: list(z)]}


@pytest.mark.parametrize("scene, x, v", SLOW_BOXES[:2])
@pytest.mark.parametrize("name, mutant", [(n, m) for n, ms in MUTANTS.items() for m in ms])
def test_a_wrong_hand_off_is_caught_by_the_true_motions(scene, x, v, name, mutant, monkeypatch):
    """Each mutant gives an unproved walk or a proof that some true motion leaves: never a
    proof that holds every sample."""
    monkeypatch.setattr(handoff, name, mutant)
    enc = _prove(scene, x, v)
    assert not enc.proved or _outside(enc, scene, x, v)


def test_the_hand_off_keeps_a_point_start_tight():
    """33 events of ``FRICTION`` from a point: ``Phi`` was ~1e-38 wide at 192 bits with balls
    handed through each event (issue 33's measurement), and is ~1e-54 now."""
    enc = enclose_map(FRICTION, "1.5", "-1", prec=PREC, max_prec=PREC)
    assert enc.proved and len(enc.events) == 33
    assert max(float(b.rad()) for b in enc.phi) < 1e-50


@pytest.mark.parametrize("kind", ["impact", "turn", "stick"])
def test_an_event_logged_again_at_the_instant_of_the_last_is_refused(kind):
    """A handed set starts at ``base``, before the last event's time ball, where the last event's
    own zero lies: a log that puts a second event at that instant (after the first turn and the
    first impact of ``FRICTION``) is refused, never proved as that zero."""
    from reference.enclosure.certify import Unproved
    from tests.test_walk_negative import Case, event

    case = Case(FRICTION, "1.5", "-1")
    L = list(case.points)
    for i in (0, 1):
        with pytest.raises(Unproved):
            case.walk(L[:i + 1] + [event(L[i], kind=kind)] + L[i + 1:])


# --- property (hypothesis, slow): random position-forced scenes, every effect -------------------
from hypothesis import HealthCheck, assume, given, settings, strategies as st  # noqa: E402

from tests.strategies import position_forced_scenes, states  # noqa: E402


@st.composite
def _random_boxes(draw):
    sc = draw(position_forced_scenes(restitutions=("1", "0.9", "0.6")))
    x, v = draw(states(sc, vmax=2 * sc.float("F") / sc.float("omega")))
    margin = 1e-6 * (sc.float("r") - sc.float("l"))
    # a box of 1e-30 at a wall or across v = 0 is refused by design (tested elsewhere): in flight
    assume(sc.float("l") + margin < x < sc.float("r") - margin)
    assume(abs(v) > 0.05 * sc.float("F") / sc.float("omega"))
    return sc, x, v


@pytest.mark.slow
@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(_random_boxes())
def test_property_true_motions_from_a_box_of_a_random_scene_stay_in_its_proof(case):
    """Any scene of the family, any float state, a box of ``1e-30``: the proof holds -- and every
    true motion from the box's corners and centre stays in it -- or says why not.  A chatter run
    is closed by its tail bound with fewer bounces than the reference logs: there only ``Phi``
    is compared."""
    sc, x, v = case
    enc = _prove(sc, x, v)
    if not enc.proved:
        assert len(enc.reason) > 20
        return
    if "chatter" in [e.kind for e in enc.events]:
        with workprec(enc.prec):
            assert all(inside(enc.phi[0], end[0]) and inside(enc.phi[1], end[1])
                       for _, _, end in _truth(sc, x, v))
        return
    assert _outside(enc, sc, x, v) == []
