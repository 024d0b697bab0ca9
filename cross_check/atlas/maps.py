"""The atlas's maps and its agreement with the closed forms.

``fields`` turns the gathered values into arrays (``R`` rows, ``f/F`` columns); ``boundaries``
measures, for each closed-form boundary, where the computed region actually switches, in grid
cells (the checks: within one cell); ``draw`` writes one PNG per claim, the computed region
shaded and the closed-form boundaries drawn over it, labelled.
"""
from __future__ import annotations

import math

import numpy as np

from cross_check.atlas.claims import FOLD, STICK_ATTRACTOR, x2_nonstick_boundary

#: field name -> (claim, how to read it from a point's value)
FIELDS = {
    "x1 exists, non-sticking": ("symmetric", lambda d: d["x1"]),
    "x2 exists, non-sticking": ("symmetric", lambda d: d["x2"]),
    "printed condition > 0": ("symmetric", lambda d: d["printed"]),
    "period-1 centre": ("subharmonic-islands", lambda d: d["m1"]),
    "period-3 centre": ("subharmonic-islands", lambda d: d["m3"]),
    "period-5 centre": ("subharmonic-islands", lambda d: d["m5"]),
    "no-impact periodic orbit": ("no-impact", lambda d: d["exists"]),
    "no-impact orbit sticks": ("no-impact", lambda d: d["sticks"]),
    "Omega_dissip leaves itself (fraction)": ("dissip-invariance", lambda d: d["fraction"]),
    "log10 max |det Phi' - 1| (non-sticking)": ("area-preservation",
                                                lambda d: None if d["max_det_minus_1"] is None
                                                else math.log10(max(d["max_det_minus_1"], 1e-17))),
}


def fields(values: dict) -> dict:
    """``{field: float array (R rows, f/F columns)}``, nan where undefined, for the claims present."""
    out = {}
    for name, (claim, read) in FIELDS.items():
        if claim in values:
            out[name] = np.array([[np.nan if read(d) is None else float(read(d)) for d in row]
                                  for row in values[claim]])
    return out


def _switch(xs, column):
    """Midpoint of the first True -> False switch along ``xs`` (``None`` if there is none)."""
    for k in range(len(xs) - 1):
        if column[k] == 1 and column[k + 1] == 0:
            return 0.5 * (xs[k] + xs[k + 1])
    return None


def boundaries(grid, values) -> dict:
    """Each closed-form boundary against the computed switch, in grid cells: ``{name: worst
    |computed - closed form| / cell}`` over the rows or columns where the closed form applies."""
    F = fields(values)
    fF, R = grid.fF, grid.R
    df = 1.0 / grid.n
    dlog = (math.log10(R[-1]) - math.log10(R[0])) / (grid.n - 1)
    out = {}

    def along_f(field, f_star, rows):
        errs = [abs(s - f_star) / df for i in rows if (s := _switch(fF, F[field][i])) is not None]
        return (max(errs) if errs else None), len(errs)

    if "x1 exists, non-sticking" in F:
        out["x1: fold f/F = 2/pi"] = along_f("x1 exists, non-sticking", FOLD, np.flatnonzero(R >= 4))
        errs = []
        for j in np.flatnonzero((fF > 0) & (fF < FOLD - 2 * df)):
            col = F["x2 exists, non-sticking"][:, j][::-1]       # R falling: True -> False
            s = _switch(np.log10(R[::-1]), col)
            if s is not None:
                # the closed form over the column's cell (steep near the fold): distance to that range
                lo, hi = (math.log10(x2_nonstick_boundary(min(fF[j] + d, FOLD))) for d in (df / 2, -df / 2))
                errs.append(max(lo - s, s - hi, 0.0) / dlog)
        out["x2: w^2 R/F = sqrt(4 - pi^2 (f/F)^2)"] = (max(errs) if errs else None), len(errs)
    if "period-3 centre" in F:
        out["period 3: f/F = 2/(3 pi)"] = along_f("period-3 centre", 2 / (3 * math.pi), np.flatnonzero(R >= 40))
    if "no-impact periodic orbit" in F:
        col = F["no-impact periodic orbit"][:, 0][::-1]
        s = _switch(np.log10(R[::-1]), col)
        out["no impact (f = 0): w^2 R/F = 2"] = (None if s is None else abs(s - math.log10(2)) / dlog), int(s is not None)
        sticks = np.where(np.isnan(F["no-impact orbit sticks"]), np.nan, 1 - F["no-impact orbit sticks"])
        errs = [abs(s - STICK_ATTRACTOR) / df for i in np.flatnonzero(R >= 10)
                if (s := _switch(fF, sticks[i])) is not None]
        out["attractor sticks: f/F = 1/sqrt(1 + pi^2/4)"] = (max(errs) if errs else None), len(errs)
    return out


def _edges(v, log=False):
    v = np.log10(v) if log else np.asarray(v, float)
    mid = 0.5 * (v[1:] + v[:-1])
    e = np.concatenate([[v[0] - (mid[0] - v[0])], mid, [v[-1] + (v[-1] - mid[-1])]])
    return 10.0 ** e if log else e


def _closed_forms(ax, claim):
    f = np.linspace(0, 1, 400)
    if claim in ("symmetric", "subharmonic-islands"):
        ax.axvline(FOLD, color="k", ls="--", lw=1, label="fold f/F = 2/pi")
    if claim == "symmetric":
        fx = f[f < FOLD]
        ax.plot(fx, np.sqrt(4 - np.pi ** 2 * fx ** 2), "r-", lw=1.2, label="x2: w^2R/F = sqrt(4 - pi^2 f^2/F^2)")
    if claim == "subharmonic-islands":
        for m, c in ((3, "tab:orange"), (5, "tab:green")):
            ax.axvline(2 / (m * np.pi), color=c, ls=":", lw=1.2, label=f"f/F = 2/({m} pi)")
    if claim == "no-impact":
        ax.axhline(2.0, color="k", ls="--", lw=1, label="w^2R/F = 2 (f = 0)")
        ax.axvline(STICK_ATTRACTOR, color="r", ls=":", lw=1.2, label="f/F = 1/sqrt(1 + pi^2/4)")


def draw(grid, values, out_dir) -> list:
    """One PNG per claim present (a panel per field); returns the paths."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    F = fields(values)
    fe, Re = _edges(grid.fF), _edges(grid.R, log=True)
    paths = []
    for claim in values:
        names = [n for n, (c, _) in FIELDS.items() if c == claim]
        fig, axes = plt.subplots(1, len(names), figsize=(4.6 * len(names), 4.2), squeeze=False)
        for ax, name in zip(axes[0], names):
            binary = name not in ("Omega_dissip leaves itself (fraction)",) and not name.startswith("log10")
            mesh = ax.pcolormesh(fe, Re, np.ma.masked_invalid(F[name]), shading="flat",
                                 cmap="Greys" if binary else "viridis", vmin=0 if binary else None,
                                 vmax=1.6 if binary else None)
            if not binary:
                fig.colorbar(mesh, ax=ax, shrink=0.8)
            _closed_forms(ax, claim)
            ax.set_yscale("log")
            ax.set_ylim(Re[0], Re[-1])
            ax.set_xlim(fe[0], fe[-1])
            ax.set_xlabel("f/F")
            ax.set_ylabel("w^2 R/F")
            ax.set_title(name + (" (grey: yes)" if binary else ""), fontsize=9)
            if ax.get_legend_handles_labels()[0]:
                ax.legend(fontsize=7, loc="lower right")
        fig.suptitle(f"atlas: {claim} ({grid.n} x {grid.n}, F = w = 1)", fontsize=10)
        fig.tight_layout()
        path = f"{out_dir}/atlas_{claim}.png"
        fig.savefig(path, dpi=100)
        plt.close(fig)
        paths.append(path)
    return paths
