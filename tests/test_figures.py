"""The figure registry (``cross_check.paper.figures``, issue 7): every figure renders, and the
numbers behind them hold.

All figures are rendered once at ``--quick`` resolution into a temporary directory (a
module-scoped fixture shares the computed numbers: the fold, ``R*``); the checks:

* the pseudo-arclength continuation's fold lies at the closed-form ``f/F = 2/pi``
  (paper eq. ``fold:bif``), and Newton finds the non-sticking pair just below it and
  none just above it;
* the 3:1 resonance ``tr Phi' = -1`` crosses at the paper's ``R* ~ 0.8932``;
* the Birkhoff classifier calls an island orbit regular and a sea orbit chaotic, both
  on test maps with known answers and on the paper's frictionless narrow scene.
"""
import os

import numpy as np
import pytest

from cross_check import scenes
from cross_check.dynamics import portraits as por
from cross_check.paper import figures
from cross_check.paper.figures.fold import closed_form_fold
from cross_check.paper.figures.narrow import central_centre
from cross_check.paper.figures.resonance import resonance_centre
from cross_check.tolerances import tol


@pytest.fixture(scope="module")
def rendered(tmp_path_factory):
    out = tmp_path_factory.mktemp("figs")
    ctx = {}
    done = figures.render(list(figures.FIGURES), str(out), figures.QUICK, ctx)
    return out, done, ctx


@pytest.mark.parametrize("name", list(figures.FIGURES))
def test_every_figure_renders_a_png(rendered, name):
    """One registered draw function per figure, drawn into its PNG."""
    out, done, _ = rendered
    path = os.path.join(out, figures.file_name(name))
    assert done[name][0] == path
    with open(path, "rb") as fh:
        head = fh.read(8)
    assert head == b"\x89PNG\r\n\x1a\n"
    assert os.path.getsize(path) > 10_000  # a drawn figure, not an empty canvas


def test_file_names_follow_the_labels():
    assert figures.file_name("fig:nofriction") == "fig_nofriction.png"
    assert figures.file_name("fig:narrow-with-friction") == "fig_narrow_with_friction.png"
    assert figures.resolve("fig_many_wide") == "fig:many:wide"
    assert figures.resolve("three:per") == "fig:three:per"
    assert figures.resolve("fig:none") is None


def test_bad_arguments_exit_2_with_one_line(capsys):
    assert figures.main(["--bogus"]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
    assert figures.main(["--only", "fig:none"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--only must be one of" in err[0]


def test_fold_of_the_continuation_is_the_closed_form(rendered):
    _, _, ctx = rendered
    u, tr, fold = ctx["fold"]
    assert fold is not None
    # the fold is the turning point of the branch in f: f is largest there
    assert fold[2] >= u[:, 2].max() - 1e-9
    # centres (|tr| < 2) on one side of the fold, saddles (tr > 2) on the other
    i = int(np.argmax(u[:, 2]))
    assert np.all(np.abs(tr[: max(i - 1, 1)]) < 2) and np.all(tr[i + 2:] > 2)
    # paper eq. fold:bif: f/F = 2/pi, F = 1
    t = tol("fig_fold_f")
    np.testing.assert_allclose(fold[2], closed_form_fold(1.0), rtol=t.rtol, atol=t.atol)


def test_fixed_points_exist_just_below_the_fold_and_not_above():
    f_star = 2 / np.pi
    counts = {}
    for f in (f_star - 1e-3, f_star + 1e-3):
        sc = scenes.wide(f)
        fps = por.periodic_points(sc, (0.0, 20.0, 0.5, 12.0), figures.QUICK.newton_seeds)
        pair = [o for o in fps if not o.dissip and o.kind in ("centre", "saddle")]
        counts[f > f_star] = sorted(o.kind for o in pair)
    assert counts[False] == ["centre", "saddle"], counts
    assert counts[True] == [], counts


def test_resonance_trace_minus_one_at_the_papers_R(rendered):
    _, _, ctx = rendered
    t = tol("fig_resonance_R")
    # paper, caption of fig:resonance: R* ~ 0.8932, four decimals truncated (see the tolerance)
    assert 0.0 <= ctx["R_star"] - 0.8932 < t.atol, ctx["R_star"]
    z, J = resonance_centre(ctx["R_star"], ctx["R_star_z"] if "R_star_z" in ctx else None)
    np.testing.assert_allclose(np.trace(J), -1.0, atol=1e-8)
    np.testing.assert_allclose(np.linalg.det(J), 1.0, atol=1e-9)


def test_fig_fig_scene_has_the_captions_saddle(rendered):
    _, _, ctx = rendered
    # caption of fig:fig: the saddle's eigenvalues are 0.3159 and 3.1659 (4 decimals, rounded)
    t = tol("fig_caption_4_decimals")
    np.testing.assert_allclose(ctx["figfig_multipliers"], [0.3159, 3.1659], rtol=t.rtol, atol=t.atol)


def test_birkhoff_classifier_on_maps_with_known_answers():
    n = 400
    # an irrational rotation of the circle, seen through (cos, sin): regular
    theta = 2 * np.pi * (np.sqrt(5) - 1) / 2 * np.arange(n + 1)
    xs, vs = np.cos(theta)[:, None], np.sin(theta)[:, None]
    assert por.birkhoff_digits(xs, vs)[0] > por.regular_threshold() + 3
    # the Chirikov standard map at K = 6 (fully chaotic): chaotic
    p, q = 0.3, 0.1
    pts = []
    for _ in range(n + 1):
        pts.append((q, p))
        p = (p + 6.0 * np.sin(q)) % (2 * np.pi)
        q = (q + p) % (2 * np.pi)
    pts = np.array(pts)
    assert por.birkhoff_digits(pts[:, :1], pts[:, 1:])[0] < por.regular_threshold() - 1


def test_birkhoff_classifier_on_the_narrow_scene():
    sc = scenes.narrow()
    fps = por.periodic_points(sc, (-0.05, 0.85, -2.6, 2.6), figures.QUICK.newton_seeds)
    central = central_centre([o for o in fps if o.kind == "centre"])
    zc = central.points[0]
    # a start 1e-3 off the central centre lies on an invariant curve of its island (Fig. 1b);
    # a start in the middle band away from the island lies in the chaotic sea (Fig. 1a)
    x0 = np.array([zc[0] + 1e-3, CHAOTIC_START[0]])
    v0 = np.array([zc[1], CHAOTIC_START[1]])
    xs, vs, first = por.run_orbits(sc, x0, v0, 400)
    cls, digits = por.orbit_classes(sc, xs, vs, first)
    assert list(cls) == ["regular", "chaotic"], digits


#: a start in the chaotic sea of the frictionless r = 0.8 scene (inside the grey sea of
#: fig_nofriction.png panel (a) as computed by this suite: its Birkhoff averages agree to 1.2 digits
#: over 800 periods, against 11 for the island start)
CHAOTIC_START = (0.3, 0.5)


def test_orbits_without_omega_dissip_take_the_map_alone_and_the_same_iterates(monkeypatch):
    """``run_orbits`` on a frictionless scene (no ``Omega_dissip`` to track) takes fast's map
    alone, not the map with its Jacobian (1.33 times its cost), and gets the same iterates bit
    for bit as the one-pass map with its zero-velocity flags (``_step``)."""
    import fast
    from reference.scene import Scene

    sc = Scene(F="2.115", f=0, omega="0.949", l=0, r="0.2", restitution="0.6", wavenumber="4.23")
    x0, v0 = np.array([0.05, 0.1, 0.15]), np.array([0.5, -1.0, 2.0])
    xs, vs, zv = [x0], [v0], []
    for _ in range(5):
        x1, v1, z = por._step(sc, xs[-1], vs[-1], zero_velocity=True)      # map and flags
        xs.append(x1), vs.append(v1), zv.append(z)
    monkeypatch.setattr(fast, "map_and_jacobian", lambda *a, **k: pytest.fail("the Jacobian was computed"))
    got_x, got_v, first = por.run_orbits(sc, x0, v0, 5)
    assert np.array_equal(got_x, np.array(xs)) and np.array_equal(got_v, np.array(vs))
    assert (first == 6).all()
