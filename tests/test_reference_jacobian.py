"""Phi' as the Table 1 product against central finite differences of Phi at high precision.

The orbits cover impacts only (f = 0), impacts with turning points, and sticking.  The
reflection matrix takes the velocity BEFORE the impact; ``test_reflection_uses_v_before``
shows that the paper's ambiguous ``x'(t*)`` read as the velocity after would fail.
"""
import importlib

import mpmath
import pytest
from mpmath import mpf

import reference
from cross_check.tolerances import tol
from reference import Scene
from tests.strategies import REFERENCE_SCENES

jac_module = importlib.import_module("reference.jacobian")

FD_DPS, FD_STEP, J_DPS = 80, mpf("1e-30"), 60

# (scene, x, v, event kinds expected in [0, T]) -- kinds from the reference's own log,
# checked below so that each case really exercises what its name says.
CASES = {
    "impacts_f0": ("narrow_f0", "0.3", "0.5", {"impact"}),
    "impacts_f0_wide": ("wide_f0", "19.5", "1.2", {"impact"}),
    "impacts_turns": ("narrow_f0005", "0.79", "0.02", {"impact", "turn"}),
    "turns_2pi": ("2pi_f01", "0.5", "0.01", {"turn"}),
    "impact_turns_wide": ("wide_f03", "0.1", "-0.7", {"impact", "turn"}),
    "sticking": ("resonance", "0.1", "-0.7", {"turn", "stick", "slip", "impact"}),
    "restitution_f0": ("e09_f0", "0.3", "0.5", {"impact"}),
    "restitution_friction": ("e09_f005", "0.3", "0.5", {"impact", "turn"}),
}
#: restitution scenes (issue 6 effect; Jacobian with ((1+e) A + (1-e) s f)/v-)
EXTRA_SCENES = {
    "e09_f0": Scene(F=1, f=0, omega=1, l=0, r="0.8", restitution="0.9"),
    "e09_f005": Scene(F=1, f="0.05", omega=1, l=0, r="0.8", restitution="0.9"),
}


def finite_differences(scene, x, v):
    """Central differences of Phi at FD_DPS digits."""
    with mpmath.workdps(FD_DPS + 10):
        x, v = mpf(x), mpf(v)
        cols = []
        for dx, dv in ((FD_STEP, 0), (0, FD_STEP)):
            p = reference.stroboscopic_map(scene, x + dx, v + dv, dps=FD_DPS)
            m = reference.stroboscopic_map(scene, x - dx, v - dv, dps=FD_DPS)
            cols.append(((p[0] - m[0]) / (2 * FD_STEP), (p[1] - m[1]) / (2 * FD_STEP)))
        return [[cols[0][0], cols[1][0]], [cols[0][1], cols[1][1]]]


def assert_close(J, D, name):
    t = tol(name)
    with mpmath.workdps(FD_DPS):
        for i in range(2):
            for j in range(2):
                err = abs(J[i][j] - D[i][j])
                assert err <= t.atol + t.rtol * abs(D[i][j]), (i, j, J[i][j], D[i][j])


@pytest.mark.parametrize("case", sorted(CASES))
def test_table1_product_matches_finite_differences(case):
    name, x, v, kinds = CASES[case]
    scene = {**REFERENCE_SCENES, **EXTRA_SCENES}[name]
    log = reference.trajectory(scene, x, v, 2 * mpmath.pi / scene.mpf("omega"), dps=30)
    assert {e.kind for e in log} == kinds, [e.kind for e in log]
    J = reference.jacobian(scene, x, v, dps=J_DPS)
    assert_close(J, finite_differences(scene, x, v), "ref_fd_jacobian")


def test_reflection_uses_v_before(monkeypatch):
    """With v+ = -v- in the reflection matrix, the product misses the derivative by O(1)."""
    scene, x, v = REFERENCE_SCENES["narrow_f0005"], "0.79", "0.02"
    D = finite_differences(scene, x, v)
    right = reference.jacobian(scene, x, v, dps=J_DPS)
    assert_close(right, D, "ref_fd_jacobian")
    original = jac_module.impact_matrix
    monkeypatch.setattr(jac_module, "impact_matrix",
                        lambda model, A, v_before, t=None: original(model, A, -v_before, t))
    wrong = reference.jacobian(scene, x, v, dps=J_DPS)
    with mpmath.workdps(FD_DPS):
        assert max(abs(wrong[i][j] - D[i][j]) for i in range(2) for j in range(2)) > 0.1


def det(J):
    return J[0][0] * J[1][1] - J[0][1] * J[1][0]


def test_determinants_follow_table1():
    """det = 1 without turns (area preservation), product of turn factors with them,
    0 with sticking (paper, Section 4)."""
    with mpmath.workdps(40):
        J = reference.jacobian(REFERENCE_SCENES["narrow_f0"], "0.3", "0.5", dps=40)
        assert abs(det(J) - 1) < mpf(10) ** -35
        scene = REFERENCE_SCENES["narrow_f0005"]
        log = reference.trajectory(scene, "0.79", "0.02", 2 * mpmath.pi, dps=40)
        F, f = 1, mpf("0.005")
        factor = mpf(1)
        for e in log:
            if e.kind == "turn":
                A = abs(F * mpmath.cos(e.t))
                factor *= (A - f) / (A + f)
        J = reference.jacobian(scene, "0.79", "0.02", dps=40)
        assert factor < 1 and abs(det(J) - factor) < mpf(10) ** -35
        J = reference.jacobian(REFERENCE_SCENES["resonance"], "0.1", "-0.7", dps=40)
        assert det(J) == 0 and J[1][0] == 0 and J[1][1] == 0


def test_chatter_gives_the_zero_matrix():
    scene = REFERENCE_SCENES["resonance"]
    log = reference.trajectory(scene, "0.89", "0.1", 1, dps=30)
    assert "chatter" in [e.kind for e in log]
    J = reference.jacobian(scene, "0.89", "0.1", dps=30)
    assert all(J[i][j] == 0 for i in range(2) for j in range(2))


def test_grazing_impact_has_no_jacobian_and_says_so():
    """A grazing impact (zero velocity before impact) makes 2A/v- infinite: ValueError.

    Found by the claims' reference Newton on fig:narrow (f = 0), which reached a state whose
    period has an impact with v- = 0; the matrix itself is what must refuse.
    """
    model = type("Model", (), {"e": mpf(1), "f": mpf(0)})()
    with pytest.raises(ValueError, match="grazing impact at t = 0.25"):
        jac_module.impact_matrix(model, mpf(1), mpf(0), mpf("0.25"))
