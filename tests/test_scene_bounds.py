"""Scene values are untrusted input (issue 29): reading one is bounded work.

Each value ends in a value or a ``ValueError`` that starts ``"Scene: <name>"`` and names the
limit and the text, at once.  The timed checks here guard against a hang (1 s per value, for
work that takes microseconds), not a speed target.
"""
import time
from fractions import Fraction

import mpmath
import pytest
from hypothesis import given, settings

from reference import expression as ex
from reference.scene import Scene
from tests.strategies import hostile_expressions

BASE = dict(F=1, f=0, omega=1, l=0, r=1)
#: a hang guard: reading, probing and evaluating one value takes milliseconds
HANG_GUARD_S = 1.0


def _scene(**change):
    return Scene(**{**BASE, **change})


def _timed(fn):
    start = time.perf_counter()
    try:
        return fn(), None
    except ValueError as exc:
        return None, exc
    finally:
        assert time.perf_counter() - start < HANG_GUARD_S


@pytest.mark.parametrize("text, limit", [
    ("10**10**10", "MAX_POWER_EXPONENT"),
    ("9**9**9**9", "MAX_POWER_EXPONENT"),
    ("pi**pi**pi**pi", "MAX_POWER_EXPONENT"),
    ("(2**1000000)**1000000", "MAX_POWER_EXPONENT"),
    ("1e999999999", "MAX_EXPONENT_BITS"),
    ("1e-999999999", "MAX_EXPONENT_BITS"),
    ("2*1e999999", "MAX_EXPONENT_BITS"),
    ("10**1300", "MAX_EXPONENT_BITS"),
])
def test_the_values_that_hung_are_refused_at_once_naming_parameter_limit_and_text(text, limit):
    _, err = _timed(lambda: _scene(F=text))
    assert err is not None and str(err).startswith("Scene: F = ")
    assert limit in str(err) and repr(text) in str(err)


def test_1e308_times_10_is_a_scene_value_but_has_no_float64():
    scene = _scene(F="1e308*10")                       # the reference's range is wider
    assert scene.exact("F") == Fraction(10) ** 309     # a rational expression is read exactly
    with pytest.raises(ValueError, match=r"^Scene: F = '1e308\*10' has no float64 value"):
        scene.float("F")
    with pytest.raises(ValueError, match="^Scene: omega = '1e-400' gives|^Scene: omega = '1e-400' has"):
        _scene(omega="1e-400").period


@settings(max_examples=150)
@given(hostile_expressions())
def test_hostile_expressions_end_in_a_value_or_a_named_valueerror_within_a_second(text):
    scene, err = _timed(lambda: _scene(F=text))
    if err is not None:
        assert str(err).startswith("Scene: F ")
        return
    with mpmath.workdps(60):                             # every later evaluation is bounded too
        _timed(lambda: scene.mpf("F"))
    _timed(lambda: scene.float("F"))


def _chains(n_chains, terms):
    """``n_chains`` parenthesised sums of ``terms`` ones, added: depth ``terms + 1``."""
    return "+".join("(" + "+".join("1" * terms) + ")" for _ in range(n_chains))


@pytest.mark.parametrize("within, beyond, limit", [
    ("1" * ex.MAX_TEXT_LENGTH, "1" * (ex.MAX_TEXT_LENGTH + 1), "MAX_TEXT_LENGTH"),
    (_chains(3, 21), _chains(3, 22), "MAX_NODES"),                      # 125 and 131 nodes
    ("-" * (ex.MAX_DEPTH - 2) + "+1", "-" * ex.MAX_DEPTH + "1", "MAX_DEPTH"),   # depth 32, 33
    ("2**4000*2**96", "2**4000*2**97", "MAX_EXPONENT_BITS"),
    ("2**-4000*2**-96", "2**-4000*2**-97", "MAX_EXPONENT_BITS"),
    ("1e1233", "1e1234", "MAX_EXPONENT_BITS"),
    ("1e-1233", "1e-1234", "MAX_EXPONENT_BITS"),
    ("1**4096", "1**4097", "MAX_POWER_EXPONENT"),
    (Fraction(2 ** 65535 + 1, 2 ** 65535), Fraction(2 ** 65536 + 1, 2 ** 65536), "MAX_RATIONAL_BITS"),
    (2 ** 4096, 2 ** 4097, "MAX_EXPONENT_BITS"),
    (mpmath.mpf((0, 1, 4096, 1)), mpmath.mpf((0, 1, 4097, 1)), "MAX_EXPONENT_BITS"),
    (mpmath.mpf((0, 1, -4096, 1)), mpmath.mpf((0, 1, -2 ** 100, 1)), "MAX_EXPONENT_BITS"),
])
def test_each_limit_takes_the_value_at_it_and_refuses_the_one_beyond(within, beyond, limit):
    assert _scene(F=within).exact("F") is not None
    _, err = _timed(lambda: _scene(F=beyond))
    assert err is not None and str(err).startswith("Scene: F = ") and limit in str(err)


@pytest.mark.parametrize("name", ["F", "f", "omega", "l", "r", "restitution", "damping", "wavenumber"])
def test_every_parameter_and_replace_are_bounded_and_named(name):
    with pytest.raises(ValueError, match=rf"^Scene: {name} = '9\*\*9\*\*9\*\*9' is refused"):
        _scene(**{name: "9**9**9**9"})
    with pytest.raises(ValueError, match=rf"^Scene: {name} = '1e999999999' is refused"):
        _scene().replace(**{name: "1e999999999"})


@pytest.mark.parametrize("text, fragment", [
    ("355/113 - pi", "cancels"),
    ("1/(pi - 3.14159265358979323846264338327950288419716939937510582097494459230781640628620899"
     "862803482534211706798214808651328230664709384460955)", "divides by zero"),
    ("0**-1", "divides by zero"),
    ("(-8)**(1/3)", "not real"),
    ("__import__('os')", "not a number, pi or"),
    ("1j", "not a number, pi or"),
])
def test_values_that_depend_on_the_precision_or_are_not_real_numbers_are_refused(text, fragment):
    with pytest.raises(ValueError, match=r"^Scene: F must be a number") as info:
        _scene(F=text)
    assert fragment in str(info.value)


def test_rational_expressions_are_exact_and_pi_expressions_stay_exact_at_any_precision():
    assert _scene(F="2*0.1").exact("F") == Fraction(1, 5)
    assert _scene(F="1e20 + 1 - 1e20").exact("F") == 1              # exact, no cancellation
    assert _scene(F="1e1000 + 1e-1000 - 1e1000").exact("F") == Fraction(1, 10 ** 1000)
    scene = _scene(F="pi - 3")
    for dps in (15, 300):
        with mpmath.workdps(dps):
            assert abs(scene.mpf("F") - (mpmath.pi - 3)) <= mpmath.mpf(10) ** (-dps)


@pytest.mark.parametrize("make", ["mpf", "fraction", "arb"])
def test_every_arithmetic_goes_through_the_same_checks(make):
    """The exact, mpf and Arb evaluations are one evaluator: each refuses a value beyond
    ``MAX_EXPONENT_BITS`` before taking the power (the parse alone has no values)."""
    from flint import arb

    from reference.enclosure.balls import from_fraction

    tree = ex.parse("10**2000")
    args = {"mpf": (), "fraction": (Fraction, Fraction(0)), "arb": (from_fraction, arb.pi())}[make]
    with pytest.raises(ex.LimitError, match="MAX_EXPONENT_BITS"):
        ex.eval_tree(tree, *args)
    assert ex.eval_tree(ex.parse("10**1000"), *args) is not None


def test_the_gap_is_exact_where_the_walls_round_together():
    scene = _scene(l="1e30", r="1e30 + 1")
    with mpmath.workdps(15):
        assert scene.mpf("r") - scene.mpf("l") == 0             # what rounding would give
        assert scene.gap() == 1
