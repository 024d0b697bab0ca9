"""What the enclosure tests share: a point value in a proved ball, and a proof's map and
Jacobian against the point reference at ``DPS`` digits."""
import reference
from cross_check.tolerances import tol
from reference.enclosure.balls import from_mpf, workprec

DPS = 60
#: the point reference's own error at DPS digits (the slack of every containment below)
TOL = tol("enclosure_vs_reference_dps60")


def inside(ball, value, tolerance=TOL):
    """``value`` (an mpf) lies in ``ball`` up to ``tolerance`` (``atol + rtol max(1, |value|)``,
    the point reference's own error)."""
    slack = tolerance.atol + tolerance.rtol * max(1, abs(float(value)))
    return bool(abs(from_mpf(value) - ball.mid()) <= ball.rad() + slack)


def assert_map_contains_the_point_reference(enc, scene, x, v, jacobian=True):
    """The proved ``Phi`` (and ``Phi'`` if ``jacobian``) of ``enc`` holds the point reference's
    at ``DPS`` digits from the same start."""
    xr, vr = reference.stroboscopic_map(scene, x, v, dps=DPS)
    J = reference.jacobian(scene, x, v, dps=DPS) if jacobian else None
    with workprec(enc.prec):
        assert inside(enc.phi[0], xr) and inside(enc.phi[1], vr), (enc.phi, xr, vr)
        if jacobian:
            assert all(inside(enc.jacobian[i][j], J[i][j]) for i in range(2) for j in range(2)), \
                (enc.jacobian, J)
