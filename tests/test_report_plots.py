"""The report's work-precision diagram (``cross_check.report.plots``): digits against seconds,
no clamp, every method's points labelled without overlap, the one-ulp floor drawn.

The data are synthetic but shaped like a real run (``cross_check.report.precision``): the
reference at dps 16 ... 100 within a factor of two in time (the case that used to pile its
labels on one point), two scipy families over five tolerances, fast alone.
"""
import math

import pytest

from cross_check.report import plots

TRUTH_DPS = 120


def _data():
    pts = {f"reference dps {d}": (10.0 ** -d, 10.0 ** -d, 2e-3 * (1 + d / 100)) for d in (16, 20, 30, 50, 100)}
    for fam, scale in (("RK45", 1.0), ("DOP853", 0.7)):
        for k, rtol in enumerate((1e-3, 1e-6, 1e-9, 1e-10, 1e-12)):
            pts[f"{fam} rtol {rtol:.0e}"] = (rtol * 10 * scale, rtol * 100, 2e-3 * scale * 1.3 ** k)
    pts["fast"] = (3e-16, 1e-15, 1.4e-6)
    return {1: {"points": pts, "ulp_floor": 1e-16}, 10: {"points": pts, "ulp_floor": 1e-9}}


def test_digits_have_no_clamp():
    assert plots.digits_of(1e-100, TRUTH_DPS) == pytest.approx(100)
    assert plots.digits_of(0.0, TRUTH_DPS) == TRUTH_DPS


def test_labels_do_not_overlap_and_each_reference_point_is_named(tmp_path):
    import matplotlib
    matplotlib.use("Agg")

    path = tmp_path / "wp.png"
    placed = plots.work_precision_plot(_data(), path, TRUTH_DPS)
    assert path.stat().st_size > 10_000 and set(placed) == {1, 10}
    for periods, texts in placed.items():
        # the five reference points sit within a factor 2 in time: all five still get a label
        assert {f"dps {d}" for d in (16, 20, 30, 50, 100)} <= set(texts), (periods, texts)
        assert any(t.startswith("fast:") for t in texts)


def test_place_labels_skips_a_label_with_no_free_place():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(3, 2))
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    renderer = fig.canvas.get_renderer()
    items = [(0.5, 0.5, f"label number {i}", "k") for i in range(40)]   # forty labels at one point
    placed = plots.place_labels(ax, items, renderer)
    boxes = [a.get_window_extent(renderer) for a in placed]
    assert 1 <= len(placed) < 40
    assert not any(b.overlaps(c) for i, b in enumerate(boxes) for c in boxes[i + 1:])
    assert all(math.isfinite(b.x0) for b in boxes)
    plt.close(fig)
