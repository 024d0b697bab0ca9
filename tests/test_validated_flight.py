"""reference.enclosure.lohner: validated flights under position forcing (issue 25).

Every ball is checked against code that shares nothing with the ball recurrences: the point
Taylor flight of ``reference.taylor`` (mpmath, its own fixed-point recurrence and analytic
truncation bound) and the closed-form flight ``motion.Flight`` of the plain model (``k -> 0``).
The certificates are seen to fail: a Picard box that does not contract is refused, a
remainder that would be dropped leaves the reference outside (the low-order test), the step
budget and a start time before the flight say so.
"""
import mpmath
import pytest
from flint import arb

from cross_check.tolerances import tol
from reference.enclosure import motion
from reference.enclosure.balls import BallModel, from_mpf, from_number, workprec
from reference.enclosure.certify import Unproved
from reference.enclosure.lohner import ValidatedFlight
from reference.enclosure.picard import contracts, picard_box
from reference.enclosure.series import Field
from reference.scene import Scene
from reference.taylor import TaylorFlight
from tests.enclosure_checks import inside

XPOT = Scene(F=1, f="0.1", omega="2*pi", l=-1, r=1, wavenumber="pi/2")
#: a scene of the family that is not the paper's: other k, F, f, w, walls, with damping
OTHER = Scene(F=2, f="0.3", omega=3, l=-2, r="1.5", wavenumber="0.9", damping="0.15")


def _point(scene, t0, x0, v0, s, u, dps, periods=False):
    """The point Taylor flight's state and flight matrix at ``t0 + u`` (``u`` in periods if
    ``periods``), mpmath at ``dps`` digits."""
    with mpmath.workdps(dps):
        t0 = mpmath.mpf(t0)
        u = mpmath.mpf(u) * (2 * mpmath.pi / scene.mpf("omega") if periods else 1)
        fl = TaylorFlight(scene, t0, mpmath.mpf(x0), mpmath.mpf(v0), s)
        return fl.state(t0 + u), fl.jacobian(t0 + u)


@pytest.mark.parametrize("scene, x0, v0, s, prec", [
    (XPOT, "0.3", "1.5", 1, 200), (OTHER, "0.1", "0.8", 1, 200),
    pytest.param(XPOT, "-0.7", "-2.5", -1, 200, marks=pytest.mark.slow),
    pytest.param(XPOT, "0.3", "1.5", 1, 320, marks=pytest.mark.slow),
    pytest.param(OTHER, "-1.5", "-3", -1, 320, marks=pytest.mark.slow)],
    ids=["xpot+", "other", "xpot-", "xpot+320", "other-320"])
def test_a_period_of_flight_contains_the_point_taylor_reference(scene, x0, v0, s, prec):
    """One period ``T`` of flight (no walls: the ODE alone): the point reference at 60 digits
    lies in the balls of ``(x, v)`` and of the flight matrix, whose radius is below
    ``validated_flight_radius`` relative (200 bits: 60 digits)."""
    with workprec(prec):
        m = BallModel(scene)
        fl = ValidatedFlight(m, arb(0), from_number(x0), from_number(v0), s)
        for frac in ("0.37", "1"):
            u = m.T * from_number(frac)
            (xr, vr), Jr = _point(scene, 0, x0, v0, s, frac, 60, periods=True)
            X, V = fl.state(u)
            D = fl.derivative(u)
            assert inside(X, xr) and inside(V, vr), (prec, frac, X, xr, V, vr)
            assert all(inside(D[i][j], Jr[i, j]) for i in range(2) for j in range(2)), (D, Jr)
            for b in (X, V):
                assert float(b.rad()) <= tol("validated_flight_radius").rtol * max(1, abs(float(b.mid())))
        assert len(fl.steps) >= 8                                  # a chain of steps


@pytest.mark.slow
def test_a_flight_of_another_scene_contains_mpmaths_odefun():
    """A third integrator, mpmath's ``odefun`` (its own Taylor method, ~1e-40 at 40 digits), on a
    scene that is not the paper's (other k, F, f, w, damping): inside the ball up to its error
    (``taylor_odefun_dps30``'s headroom, far above the ball's ~1e-94)."""
    with mpmath.workdps(40):
        k, c, f = mpmath.mpf("0.9"), mpmath.mpf("0.15"), mpmath.mpf("0.3")
        sol = mpmath.odefun(lambda t, y: [y[1], 2 * mpmath.cos(k * y[0]) * mpmath.cos(3 * t) - f - c * y[1]],
                            mpmath.mpf("0.2"), [mpmath.mpf("0.1"), mpmath.mpf("1.3")])
        want = sol(mpmath.mpf("1.7"))
    with workprec(320):
        fl = ValidatedFlight(BallModel(OTHER), from_number("0.2"), from_number("0.1"), from_number("1.3"), 1)
        for got, value in zip(fl.state(from_number("1.5")), want):
            assert inside(got, value, tol("taylor_odefun_dps30"))


def test_a_flight_from_a_ball_of_start_times_contains_both_ends():
    """An event time is a ball: the flight from ``t0 +- 1e-20`` contains the flights from both
    ends (the start moved to the ball's lower end and the Picard enclosure of that move)."""
    with workprec(320):
        m = BallModel(XPOT)
        fl = ValidatedFlight(m, from_number("0.3") + arb(0, from_number("1e-20")), from_number("0.2"),
                             from_number("1.1"), 1)
        X, V = fl.state(arb("0.5"))
        D = fl.derivative(arb("0.5"))
        for t0 in ("0.29999999999999999999", "0.30000000000000000001"):
            (xr, vr), Jr = _point(XPOT, t0, "0.2", "1.1", 1, "0.5", 60)
            assert inside(X, xr) and inside(V, vr)
            assert all(inside(D[i][j], Jr[i, j]) for i in range(2) for j in range(2))
        assert 1e-21 < float(X.rad()) < 1e-18          # the start's spread, not more


def test_the_lohner_frame_keeps_the_wrapping_down():
    """A box ``1e-20`` wide, three time units of flight (38 steps): the enclosure's radius
    stays within 3x the radius of the hull of the exact image, ``(|D_i0| + |D_i1|) r`` to first
    order (measured 1.3x and 2.0x).  An axis box (no frame) wraps at every step: 2.5x and 9.2x
    here, 15x and 140x after six."""
    wide = Scene(F=1, f="0.1", omega="2*pi", l=-30, r=30, wavenumber="pi/2")
    with workprec(320):
        r = from_number("1e-20")
        fl = ValidatedFlight(BallModel(wide), arb(0), from_number("0.3") + arb(0, r),
                             from_number("1.5") + arb(0, r), 1)
        Z, D = fl.state(arb(3)), fl.derivative(arb(3))
        for i in range(2):
            hull = (abs(D[i][0].mid()) + abs(D[i][1].mid())) * r
            assert hull <= Z[i].rad() <= 3 * hull, (i, Z[i].rad() / hull)


def test_k_to_zero_contains_the_closed_form_flight():
    """``k = 1e-60``: ``cos(k x) = 1 - O(1e-120)``, far below the balls' ~1e-94, so the
    validated flight of the position-forced scene and the closed-form enclosure of the plain
    model (``motion.Flight``) must overlap, stack entry by entry, and the flight matrix must
    hold the closed form's ``[[1, h], [0, 1]]``."""
    tiny = Scene(F=1, f="0.1", omega="2*pi", l=-5, r=5, wavenumber="1e-60")
    plain = Scene(F=1, f="0.1", omega="2*pi", l=-5, r=5)
    with workprec(320):
        fl = ValidatedFlight(BallModel(tiny), arb("0.25"), from_number("0.3"), from_number("1.7"), 1)
        closed = motion.Flight(BallModel(plain), arb("0.25"), from_number("0.3"), from_number("1.7"), 1)
        for h in ("0.01", "0.4", "1.3"):
            u = arb(h)
            got, want = fl.stack(u), closed.stack(u)
            for g, w in zip(got[:4], want[:4]):
                assert abs(g.mid() - w.mid()) <= g.rad() + w.rad(), (h, g, w)
                assert float(g.rad()) < 1e-85 * max(1, abs(float(g.mid())))
            D = fl.derivative(u)
            flat = [[1, u], [0, 1]]             # A_x = O(k^2) = 1e-120 moves it, no more
            assert all(abs(D[i][j].mid() - flat[i][j]) <= D[i][j].rad() + arb("1e-110")
                       for i in range(2) for j in range(2)), D


def test_a_low_order_flight_carries_its_remainder():
    """Order 8 with steps cut to ``2^-40``: the Lagrange remainders, not the rounding, make
    the radius (~1e-12 here; the derivative's, of order 4 to ``2^-20``, ~1e-6), and the
    reference lies inside.  Dropping the remainder (or the
    derivative's) would leave a ~1e-90 ball that misses the reference: this test turns red."""
    with workprec(320):
        m = BallModel(XPOT)
        fl = ValidatedFlight(m, arb(0), from_number("0.3"), from_number("1.5"), 1, order=8, tol_bits=40)
        u = arb("0.7")
        X, V = fl.state(u)
        D = fl.derivative(u)
    (xr, vr), Jr = _point(XPOT, 0, "0.3", "1.5", 1, "0.7", 40)
    with workprec(320):
        assert inside(X, xr) and inside(V, vr)
        assert all(inside(D[i][j], Jr[i, j]) for i in range(2) for j in range(2))
    assert 1e-20 < float(X.rad()) < 1e-8 and 1e-20 < float(D[0][0].rad()) < 1e-4   # D: order 4


def test_a_step_too_long_for_its_remainder_is_shortened_on_the_same_box():
    """A first step twice the guess is too long for the state's remainder bound; ``_remainder``
    shortens it on the coefficients over the longer step's Picard box (no second series) to a
    step that meets every bound, ``shortened``; the flight over the shortened steps still holds
    the point reference.  Kept at the long step, the bound fails: the check has something to
    check."""
    with workprec(200):
        m = BallModel(OTHER)
        fl = ValidatedFlight(m, arb(0), from_number("0.1"), from_number("0.8"), 1)
        mid = [fl.x0.mid(), fl.v0.mid()]
        xs, _, _, _ = fl.field.trig_series(arb(0), mid[0], mid[1], fl.p + 1)
        tol = fl._tol(mid)
        long = fl._dyadic(2 * fl._guess(xs, tol))
        got = fl._remainder(arb(0), [fl.x0, fl.v0], long, tol)
        h, ((rx, rv), E, _), shortened = got
        assert shortened and h < long
        assert all(abs(c).upper() * h ** (fl.p + 1) <= tol for c in (rx, rv))
        assert not all(abs(c).upper() * long ** (fl.p + 1) <= tol for c in (rx, rv))
        assert max(abs(b).upper() for row in E for b in row) * h ** (fl.q + 1) <= tol.sqrt()
        fl._shrink = 2.0                     # the first step starts at twice its guess
        u = m.T * from_number("0.37")
        X, V = fl.state(u)
    (xr, vr), _ = _point(OTHER, 0, "0.1", "0.8", 1, "0.37", 60, periods=True)
    with workprec(200):
        assert inside(X, xr) and inside(V, vr), (X, xr, V, vr)


def test_a_picard_box_that_does_not_contract_is_refused():
    """``Y + [0, h] f(B)`` inside ``B`` is checked, not assumed: a box too small for the step
    is refused by ``contracts``; with strong damping (``v' ~ -c v``, ``c h = 5``) no widening
    contracts and ``picard_box`` gives up; a short step has a box, and it holds the
    reference's states over the step."""
    with workprec(320):
        m = BallModel(XPOT)
        field = Field(m, 1)
        Y = [from_number("0.3"), from_number("1.5")]
        h = arb("0.05")
        hball, span = h / 2 + arb(0, h / 2), h / 2 + arb(0, h / 2)
        N = picard_box(field, span, Y, hball)
        assert N is not None and contracts(field, span, Y, hball, [n + arb(0, "1e-3") for n in N])
        small = [Y[0] + arb(0, "1e-3"), Y[1] + arb(0, "1e-3")]       # x moves 0.075 in the step
        assert contracts(field, span, Y, hball, small) is None
        damped = Field(BallModel(Scene(F=1, f="0.1", omega="2*pi", l=-1, r=1, wavenumber="pi/2",
                                       damping=5)), 1)
        assert picard_box(damped, arb(0.5, 0.5), Y, arb(0.5, 0.5)) is None
        assert picard_box(damped, span, Y, hball) is not None
        for frac in ("0", "0.3", "1"):
            (xr, vr), _ = _point(XPOT, 0, "0.3", "1.5", 1, 0.05 * float(frac), 30)
            assert N[0].contains(from_mpf(xr)) and N[1].contains(from_mpf(vr))


def test_budgets_and_bad_input_say_so():
    with workprec(320):
        m = BallModel(XPOT)
        fl = ValidatedFlight(m, arb(0), from_number("0.3"), from_number("1.5"), 1, max_steps=3)
        with pytest.raises(Unproved, match="step budget"):
            fl.state(arb(1))
        with pytest.raises(Unproved, match="before the flight's start"):
            fl.state(arb(-1, "0.5"))
        for kwargs in ({"order": 1}, {"tol_bits": 2.5}, {"max_steps": 0}):
            with pytest.raises(ValueError, match=next(iter(kwargs))):
                ValidatedFlight(m, arb(0), arb(0), arb(1), 1, **kwargs)
        with pytest.raises(ValueError, match="s must be"):
            ValidatedFlight(m, arb(0), arb(0), arb(1), 0)
        with pytest.raises(ValueError, match="position forcing"):
            ValidatedFlight(BallModel(Scene(F=1, f="0.1", omega=1, l=0, r=1)), arb(0), arb(0), arb(1), 1)


def test_the_full_derivative_carries_phi_prime_to_the_working_precision():
    """``full_derivative`` (issue 33): the flow derivative's series of the state's order and its
    remainder below ``2^-prec``: at 192 bits the flight matrix over a period holds the point
    reference at 60 digits in balls within ``golden_proved_agreement`` / 1e3 (what lets a golden
    input's proof certify 40 digits of ``Phi'`` with room for kappa), where half the order --
    the default, whose balls the check must refuse -- is some 20 digits wider."""
    bound = tol("golden_proved_agreement").rtol / 1e3
    with workprec(192):
        m = BallModel(OTHER)
        u = m.T
        (_, _), Jr = _point(OTHER, 0, "0.1", "0.8", 1, 1, 60, periods=True)
        widest = {}
        for full in (True, False):
            fl = ValidatedFlight(m, arb(0), from_number("0.1"), from_number("0.8"), 1, full_derivative=full)
            D = fl.derivative(u)
            assert all(inside(D[i][j], Jr[i, j]) for i in range(2) for j in range(2)), (full, D, Jr)
            widest[full] = max(float(D[i][j].rad()) / max(1, abs(float(D[i][j].mid())))
                               for i in range(2) for j in range(2))
    assert widest[True] <= bound, widest
    assert widest[False] > bound * 1e10, widest


@pytest.mark.parametrize("order", [[n for n in range(30)], [0, 29, 3, 17, 17, 8, 28, 1]])
def test_the_online_product_is_the_cauchy_product(order):
    """``series.Online`` on integers (exact balls): every coefficient is the Cauchy product,
    exactly, asked in turn or out of order, across several blocks."""
    import random

    from reference.enclosure.series import BLOCK, Online

    assert 30 > 3 * BLOCK            # the products cross several blocks
    rng = random.Random(7)
    a = [rng.randint(-10**6, 10**6) for _ in range(30)]
    b = [rng.randint(-10**6, 10**6) for _ in range(30)]
    online = Online([arb(x) for x in b])
    balls = [arb(x) for x in a]
    for n in order:
        got = online.coeff(balls, n)
        assert got.is_exact() and got == arb(sum(a[i] * b[n - i] for i in range(n + 1))), n
    with pytest.raises(ValueError, match="n < 30"):
        online.coeff(balls, 30)
