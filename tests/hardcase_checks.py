"""What the hard-case tests share: the reference, from a case's start, meets its event."""
import mpmath

import reference

#: digits of the reference's runs from a case's 30-digit start
DPS = 30


def assert_impact_at_T(sc, case):
    """The reference from ``case``'s start meets an impact at a wall within 1e-20 of ``T``
    (within 1e-25 of the wall)."""
    with mpmath.workdps(DPS + 10):
        T = 2 * mpmath.pi / sc.mpf("omega")
        log = reference.trajectory(sc, case.x, case.v, T * (1 + mpmath.mpf("1e-6")), dps=DPS)
        near = min((e for e in log if e.kind == "impact"), key=lambda e: abs(e.t - T))
        walls = (sc.mpf("l"), sc.mpf("r"))
        assert abs(near.t - T) < mpmath.mpf(10) ** -20, (case, list(log))
        assert min(abs(near.x - w) for w in walls) < mpmath.mpf(10) ** -25, (case, list(log))
