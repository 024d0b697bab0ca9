"""The report's plots: the work-precision diagram, as DiffEqDevTools draws it.

Significant correct digits ``-log10(error)`` (error relative to ``max(1, |truth|)``, median over
the states) against seconds per trajectory-period on a log axis, one line per method family
(the reference over its ``dps``, RK45 and DOP853 over ``rtol``, ``fast`` one point), every
point labelled (``dps 30``, ``rtol 1e-06``) where it does not overlap another label, and the
one-ulp floor of float64 drawn as a line.  No clamp: the reference at 100 digits sits at ~100.
One panel per horizon (1 and 10 periods).
"""
from __future__ import annotations

import math

#: marker and order of the families (the first word of a method's key)
FAMILIES = (("reference", "o"), ("RK45", "s"), ("DOP853", "^"), ("fast", "*"), ("heyoka", "D"))
#: label offsets tried in turn (points from the data point): right, below, left, above, farther out
_OFFSETS = [(5, 4), (5, -11), (-6, 4), (-6, -11), (5, 14), (5, -21), (-6, 14), (-6, -21), (14, -4), (-16, -4),
            (5, 26), (5, -33), (-6, 26), (-6, -33)]


def digits_of(err: float, cap: float) -> float:
    """``-log10(err)``; an exact result (``err == 0``) counts as all ``cap`` digits of the truth."""
    return cap if err <= 0 else -math.log10(err)


def _family(key: str) -> str:
    return key.split()[0]


def _short_label(key: str) -> str:
    parts = key.split()
    return " ".join(parts[1:]) if len(parts) > 1 else key


def place_labels(ax, items, renderer):
    """Annotate ``items = [(x, y, text, colour)]`` (data coordinates) without overlaps.

    Each label takes the first offset of ``_OFFSETS`` whose box overlaps no placed label and
    stays inside the axes; a label with no free place is left out (its point stays drawn).
    Returns the placed annotations."""
    placed = []
    legend = ax.get_legend()
    boxes = [legend.get_window_extent(renderer)] if legend is not None else []
    axes_box = ax.get_window_extent(renderer)
    for x, y, text, colour in items:
        for dx, dy in _OFFSETS:
            ann = ax.annotate(text, (x, y), xytext=(dx, dy), textcoords="offset points", fontsize=7, color=colour,
                              ha="left" if dx > 0 else "right", va="center")
            box = ann.get_window_extent(renderer)
            inside = (box.x0 >= axes_box.x0 and box.x1 <= axes_box.x1
                      and box.y0 >= axes_box.y0 and box.y1 <= axes_box.y1)
            if inside and not any(box.overlaps(b) for b in boxes):
                placed.append(ann)
                boxes.append(box)
                break
            ann.remove()
    return placed


def work_precision_plot(data: dict, path, truth_dps: int):
    """Draw ``data[periods] = {"points": {method: (median err, worst err, s/period)}, "ulp_floor": e}``.

    Returns ``{periods: [annotation texts placed]}`` (the tests check they do not overlap)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(data), figsize=(6.5 * len(data), 5.0), squeeze=False)
    panels = []
    for ax, (periods, d) in zip(axes[0], data.items()):
        items = []
        for family, marker in FAMILIES:
            keys = [k for k in d["points"] if _family(k) == family]
            keys = [k for k in keys if math.isfinite(d["points"][k][2])]
            if not keys:
                continue
            keys.sort(key=lambda k: d["points"][k][2])
            sec = [d["points"][k][2] for k in keys]
            dig = [digits_of(d["points"][k][0], truth_dps) for k in keys]
            line, = ax.semilogx(sec, dig, marker=marker, ms=9 if family == "fast" else 5,
                                ls="none" if len(keys) == 1 else "-", label=family)
            colour = line.get_color()
            items += [(s, g, _short_label(k), colour) for s, g, k in zip(sec, dig, keys) if family != "fast"]
            if family == "fast":
                items.append((sec[0], dig[0], f"fast: {dig[0]:.1f} digits", colour))
        floor = digits_of(d["ulp_floor"], truth_dps)
        ax.axhline(floor, color="k", ls=":", lw=1, label=f"one-ulp floor ({floor:.1f} digits)")
        ax.set_xlabel("seconds per trajectory-period")
        ax.set_ylabel("significant correct digits of Phi^n (median)")
        ax.set_title(f"after {periods} period(s)")
        ax.legend(fontsize=8, loc="upper left")
        ax.grid(True, which="major", alpha=0.3)
        panels.append((ax, periods, items))
    fig.tight_layout()
    renderer = fig.canvas.get_renderer()
    placed = {periods: [a.get_text() for a in place_labels(ax, items, renderer)] for ax, periods, items in panels}
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return placed
