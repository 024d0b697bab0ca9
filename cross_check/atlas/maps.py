"""The atlas's maps and its agreement with the closed forms, read from the store.

``fields`` turns the store's variables into float arrays (``w2R_over_F`` rows, ``f_over_F``
columns, NaN where undefined); ``boundaries`` measures, for each closed-form boundary, where the
computed region actually switches, in grid cells (the checks: within one cell); ``counts`` the
points where each variable holds; ``draw`` writes one PNG per claim, the computed region shaded
and the closed-form boundaries drawn over it, labelled.  Each takes the ``xarray.Dataset`` of
``store.open_atlas``.
"""
from __future__ import annotations

import math

import numpy as np

from cross_check.atlas.claims import FOLD, STICK_ATTRACTOR, x2_nonstick_boundary

#: field name -> (claim, the store's variable)
FIELDS = {
    "x1 exists, non-sticking": ("symmetric", "x1"),
    "x2 exists, non-sticking": ("symmetric", "x2"),
    "printed condition > 0": ("symmetric", "printed"),
    "period-1 centre": ("subharmonic-islands", "period1"),
    "period-3 centre": ("subharmonic-islands", "period3"),
    "period-5 centre": ("subharmonic-islands", "period5"),
    "no-impact periodic orbit": ("no-impact", "no_impact"),
    "no-impact orbit sticks": ("no-impact", "sticks"),
    "Omega_dissip leaves itself (fraction)": ("dissip-invariance", "dissip_fraction"),
    "log10 max |det Phi' - 1| (non-sticking)": ("area-preservation", "area_defect"),
}


def fields(ds) -> dict:
    """``{field: float array (w2R_over_F rows, f_over_F columns)}``, NaN where undefined, for the
    variables in the store."""
    out = {}
    for name, (_, var) in FIELDS.items():
        if var in ds:
            a = np.asarray(ds[var].values, float)
            out[name] = np.log10(np.maximum(a, 1e-17)) if var == "area_defect" else a
    return out


def counts(ds) -> dict:
    """``{variable: {"true": n, "defined": n}}`` for the yes/no variables, ``{"defined": n}`` for
    the numbers: the atlas's summary."""
    out = {}
    for var in ds.data_vars:
        if var == "done" or "example" in ds[var].dims:
            continue
        a = np.asarray(ds[var].values, float)
        entry = {"defined": int(np.isfinite(a).sum())}
        if ds[var].attrs.get("undefined", "").startswith(("always", "int8")):
            entry["true"] = int((a == 1).sum())
        out[var] = entry
    return out


def _switch(xs, column):
    """Midpoint of the first True -> False switch along ``xs`` (``None`` if there is none)."""
    for k in range(len(xs) - 1):
        if column[k] == 1 and column[k + 1] == 0:
            return 0.5 * (xs[k] + xs[k + 1])
    return None


def boundaries(ds) -> dict:
    """Each closed-form boundary against the computed switch, in grid cells: ``{name: (worst
    |computed - closed form| / cell, lines compared)}`` over the rows or columns where the
    closed form applies."""
    F = fields(ds)
    fF, R = ds["f_over_F"].values, ds["w2R_over_F"].values
    df = 1.0 / (fF.size - 1)
    dlog = (math.log10(R[-1]) - math.log10(R[0])) / (R.size - 1)
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


def draw(ds, out_dir) -> list:
    """One PNG per claim in the store (a panel per field); returns the paths."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    F = fields(ds)
    fe, Re = _edges(ds["f_over_F"].values), _edges(ds["w2R_over_F"].values, log=True)
    paths = []
    for claim in ds.attrs["claims"]:
        names = [n for n, (c, _) in FIELDS.items() if c == claim and n in F]
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
        fig.suptitle(f"atlas: {claim} ({fe.size - 2} x {Re.size - 1} + the f = 0 column, F = w = 1)",
                     fontsize=10)
        w = 4.6 * len(names)                      # fixed margins (tight_layout doubles the time)
        fig.subplots_adjust(left=0.7 / w, right=1 - 0.15 / w, bottom=0.12, top=0.88, wspace=0.35)
        path = f"{out_dir}/atlas_{claim}.png"
        fig.savefig(path, dpi=100)
        plt.close(fig)
        paths.append(path)
    return paths
