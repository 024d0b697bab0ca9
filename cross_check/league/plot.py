"""The league's work-precision diagram: median digits on Phi against seconds per start-period
(log axis), one curve per peer through its settings in their order (a tolerance sweep, as
DiffEqDevTools draws it), each point labelled with its setting (points that coincide share one
label), the float64 floor (15.95 digits) and the peers' 10-digit line drawn for reference."""
from __future__ import annotations

import math

from cross_check.league.table import PEER_DIGITS

FLOAT64_DIGITS = -math.log10(2.0 ** -53)
_MARKERS = "o^sDvP<>Xhp*"
#: points closer than this (decades of time, digits) share a label
_NEAR = (0.15, 0.3)


def _labels(rows):
    """``[(seconds, digits, text)]``: one label per run of coinciding points of a curve."""
    out = []
    for r in rows:
        s, d = r["seconds_per_start"], r["median_digits"]
        if out and abs(math.log10(s / out[-1][0])) < _NEAR[0] and abs(d - out[-1][1]) < _NEAR[1]:
            out[-1] = (out[-1][0], out[-1][1], f"{out[-1][2]} / {r['setting']}")
        else:
            out.append((s, d, r["setting"]))
    return out


def work_precision_png(doc, path) -> list[str]:
    """Draw the league ``doc`` (``table.document``) into ``path``; return the curves drawn."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9.0, 6.0))
    curves = {}
    for r in doc["rows"]:
        if r["seconds_per_start"] and r["median_digits"] is not None:
            curves.setdefault(r["peer"], []).append(r)
    for i, (peer, rows) in enumerate(curves.items()):
        sec = [r["seconds_per_start"] for r in rows]
        dig = [r["median_digits"] for r in rows]
        fast = peer == "fast"
        line, = ax.semilogx(sec, dig, marker="*" if fast else _MARKERS[i % len(_MARKERS)], ms=12 if fast else 6,
                            ls="-" if len(rows) > 1 else "none", label=peer, zorder=3 if fast else 2)
        for j, (s, d, text) in enumerate(_labels(rows)):
            ax.annotate(text, (s, d), xytext=(5, 5 if j % 2 == 0 else -10), textcoords="offset points",
                        fontsize=6.5, color=line.get_color())
    ax.axhline(FLOAT64_DIGITS, color="k", ls=":", lw=1, label=f"float64 ({FLOAT64_DIGITS:.2f} digits)")
    ax.axhline(PEER_DIGITS, color="grey", ls="--", lw=0.8, label=f"{PEER_DIGITS:g} digits")
    ax.set_xlabel("seconds per start-period (the scorer's timed batch calls)")
    ax.set_ylabel("significant correct digits of Phi, median over the graded starts")
    ax.set_title(f"League ({'quick' if doc['quick'] else 'full'}): {len(doc['scenes'])} golden scenes, one period")
    ax.set_ylim(bottom=-0.5, top=17.5)
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=7.5, loc="lower left", ncol=2)   # fast sits top left, the slow and coarse bottom right
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return list(curves)


__all__ = ["work_precision_png"]
