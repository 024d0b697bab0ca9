"""Scene: exact parameters, validation with clear messages, effects derived from values."""
from fractions import Fraction

import mpmath
import pytest
from hypothesis import given, strategies as st

from reference.scene import EFFECTS, Scene

BASE = dict(F=1, f="0.005", omega=1, l=0, r="0.8")


@pytest.mark.parametrize(
    "change, fragment",
    [
        (dict(F=-1), "F must be >= 0"),
        (dict(F=float("nan")), "F must be finite"),
        (dict(f=-0.1), "f must be >= 0"),
        (dict(f=float("inf")), "f must be finite"),
        (dict(omega=0), "omega must be > 0"),
        (dict(omega="-2*pi"), "omega must be > 0"),
        (dict(l=1), "r must be > l"),
        (dict(r=0), "r must be > l"),
        (dict(r="0.8x"), "r must be a number"),
        (dict(restitution=1.5), "restitution must be in [0, 1]"),
        (dict(damping=-1), "damping must be >= 0"),
        (dict(wavenumber=0), "wavenumber must be > 0"),
        (dict(l=True), "l must be a real number"),
        (dict(F=[1]), "F must be int, float, str or mpmath.mpf"),
    ],
)
def test_bad_parameters_raise_valueerror_naming_the_parameter(change, fragment):
    with pytest.raises(ValueError, match=fragment.replace("[", r"\[").replace("]", r"\]")):
        Scene(**{**BASE, **change})


def test_F_not_above_f_is_legal_physics():
    scene = Scene(F=1, f=2, omega=1, l=0, r=1)
    assert "friction" in scene.effects and "forcing" in scene.effects


def test_values_are_exact():
    scene = Scene(**BASE)
    assert scene.exact("r") == Fraction(4, 5)          # decimal string: exactly 4/5
    assert scene.exact("F") == 1
    assert Scene(**{**BASE, "r": 0.8}).exact("r") == Fraction(0.8)  # float: its binary value
    with mpmath.workdps(60):
        assert mpmath.almosteq(scene.mpf("r"), mpmath.mpf(4) / 5, rel_eps=mpmath.mpf(10) ** -59)
        two_pi = Scene(**{**BASE, "omega": "2*pi"}).mpf("omega")
        assert abs(two_pi - 2 * mpmath.pi) < mpmath.mpf(10) ** -58


def test_pi_expressions_are_evaluated_at_the_callers_precision():
    scene = Scene(F="(2*pi)**2", f="24.65", omega="2*pi", l=0, r="0.8932")
    for dps in (20, 80):
        with mpmath.workdps(dps):
            assert abs(scene.mpf("F") - 4 * mpmath.pi ** 2) <= mpmath.mpf(10) ** (2 - dps)
    assert scene.float("omega") == 6.283185307179586


def test_mpf_parameters_keep_their_binary_value_and_precision_does_not_leak():
    with mpmath.workdps(40):
        value = mpmath.mpf(1) / 3
    prec = mpmath.mp.prec
    scene = Scene(**{**BASE, "f": value})
    with mpmath.workdps(40):
        assert scene.mpf("f") == value
    assert mpmath.mp.prec == prec


@pytest.mark.parametrize(
    "change, expected",
    [
        ({}, {"walls", "forcing", "friction"}),
        (dict(f=0), {"walls", "forcing"}),
        (dict(F=0, f=0), {"walls"}),
        (dict(restitution="0.9"), {"walls", "forcing", "friction", "restitution"}),
        (dict(damping="0.1"), {"walls", "forcing", "friction", "damping"}),
        (dict(wavenumber="pi/2"), {"walls", "forcing", "friction", "position_forcing"}),
    ],
)
def test_effects_follow_the_values(change, expected):
    scene = Scene(**{**BASE, **change})
    assert scene.effects == frozenset(expected)
    assert set(scene.effects) <= set(EFFECTS)


def test_unknown_effect_name_is_an_error():
    with pytest.raises(ValueError, match="unknown effect"):
        Scene(**BASE).has("gravity")


def test_scene_is_frozen_hashable_and_replace_revalidates():
    scene = Scene(**BASE)
    with pytest.raises(AttributeError):
        scene.F = 2
    assert hash(scene) == hash(Scene(**BASE))
    assert scene.replace(f="0.1").exact("f") == Fraction(1, 10)
    with pytest.raises(ValueError, match="r must be > l"):
        scene.replace(r=-1)


@given(st.integers(-10**6, 10**6), st.integers(1, 10**6))
def test_any_valid_decimal_gap_is_accepted_exactly(n, m):
    l, r = f"{n}e-3", f"{n + m}e-3"
    scene = Scene(F=1, f=0, omega=1, l=l, r=r)
    assert scene.exact("r") - scene.exact("l") == Fraction(m, 1000)
