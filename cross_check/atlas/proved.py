"""The proved atlas: the claims as theorems over parameter boxes, on Dask.

``python -m cross_check prove --atlas [--grid N] [--workers K | --scheduler ADDR] [--out DIR]``.

The plane is the atlas's: ``F = w = 1``, ``l = 0``, ``r = w^2 R/F``, ``f/F`` in ``[0, 1)`` and
``w^2 R/F`` in ``[0.5, 100]`` (log-spaced), covered by ``N x N`` boxes with exact dyadic edges
(``f/F`` edges ``j/N``; ``w^2 R/F`` edges the log-spaced values rounded to multiples of
``2^-10``, so that every edge is a float64 written exactly in the JSON).  In each box, each
claim is proved for every parameter of the box (``reference.enclosure``: the parametric
Krawczyk operator, ``reference.enclosure.branches``):

* ``x1-centre``: the symmetric solution ``x1`` -- two impacts a period and no other event
  (non-sticking), unique in its Krawczyk box (of impact coordinates, or the shooting boxes), elliptic: ``|tr| < 2`` proved, ``det = 1``;
* ``x2-saddle``: ``x2``, the same but a saddle: ``tr > 2`` proved;
* ``period3-centre``: the symmetric period-3 solution (two impacts in three periods), elliptic;
* ``dissip-invariance`` (on request: ``--claim dissip-invariance``): ``Phi(Omega_dissip)`` in
  ``Omega_dissip``, proved, refuted or undecided per box (``cross_check.atlas.proved_dissip``).

Each sub-box is proved in impact coordinates (``--method impacts``, the default:
``reference.enclosure.impacts``, the impact phases and speeds as the unknowns of closed-form
equations, so that x2's slow impacts near its grazing boundary cost no blow-up), or as the
stroboscopic map in multiple shooting (``--method shooting``: ``reference.enclosure.shooting``).
A box too wide to prove at once is bisected (``continuation.cover``, at most ``MAX_LEAVES``
sub-boxes): a record covers the whole box, ``proved`` only if every sub-box is; its balls are
the union of the sub-boxes' (``x``, ``v`` hold the orbit's state at ``t = phase / w`` for
every parameter of the box; uniqueness holds in each sub-box's shooting boxes, and in the
sub-box's own state ball where ``unique_in_ball``).  A box that fails says why (the first
sub-box that could not be proved, and its reason).

The numerical region of each claim is computed with ``cross_check.atlas.claims``'s evaluators
at the box's four corners and centre; a box lies *inside* when the claim holds at all five.
For the centres the closed form also says where ``tr = -2`` exactly (``k h = 2``: the
parabolic curve ``tr = (kh - 2)^2 - 2`` touches without crossing, invisible to samples): a box
it crosses cannot be proved elliptic and is counted apart (``crosses_tr_minus_2``).

Output in ``DIR``: ``proved_atlas.json`` (the list of records), ``proved_atlas_meta.json``
(grid, per-claim fractions, provenance, timings) and ``proved_atlas_<claim>.png``.  Tasks are
chunks of ``CHUNK`` boxes with ``RETRIES``; results are gathered by chunk index, so the output
does not depend on the number of workers.  python-flint's precision is process-wide: the
proofs run in worker processes (``threads_per_worker=1``) inside ``workprec``.
"""
from __future__ import annotations

import json
import math
import pathlib
import sys
import time
import zlib
from fractions import Fraction

import mpmath
from flint import arb

from cross_check import cluster, outputs
from cross_check.atlas import claims as C
from cross_check.atlas import proved_dissip as D
from cross_check.progress import Progress
from reference import paper as P
from reference.enclosure.balls import decimal_ball, from_fraction, radius_text, workprec
from reference.enclosure.branches import METHODS, symmetric_cover
from reference.enclosure.params import ParamBox

#: claim -> (branch, periods m, proved type)
CLAIMS = {"x1-centre": (1, 1, "elliptic"), "x2-saddle": (2, 1, "saddle"),
          "period3-centre": (1, 3, "elliptic")}
#: every claim of the proved atlas (the orbit claims run by default)
ALL_CLAIMS = tuple(CLAIMS) + (D.CLAIM,)
#: sub-boxes one box may use (boxes at the edge of the numerical region get BOUNDARY_LEAVES)
MAX_LEAVES, BOUNDARY_LEAVES = 512, 16
CHUNK, RETRIES = 4, 3
#: how each leaf is proved (``branches.METHODS``): in impact coordinates, where the slow
#: impacts near x2's grazing boundary keep their equations smooth (``impacts``)
METHOD = "impacts"
#: digits of the written midpoints; the section's angle is written to PHASE_DIGITS
BALL_DIGITS, PHASE_DIGITS = 30, 40


#: the whole plane: ``(f/F from, to, w^2 R/F from, to)``
PLANE = (Fraction(0), Fraction(1), Fraction(1, 2), Fraction(100))


def _dyadic(value, bits):
    return Fraction(round(value * 2 ** bits), 2 ** bits)


def edges(n, window=PLANE):
    """``(f_edges, R_edges)``: exact dyadic Fractions, ``n + 1`` each (module docstring):
    ``f/F`` evenly spaced (multiples of ``2^-24``), ``w^2 R/F`` log-spaced (multiples of
    ``2^-10``); every edge is a float64 exactly.  ``window`` a sub-rectangle of the plane (a
    zoom: the same construction on its ranges)."""
    f0, f1, R0, R1 = (Fraction(w) for w in window)
    lo, hi = math.log10(R0), math.log10(R1)
    R = [_dyadic(R0, 10)] + [_dyadic(Fraction(10 ** (lo + i * (hi - lo) / n)), 10) for i in range(1, n)]
    return [_dyadic(f0 + (f1 - f0) * Fraction(j, n), 24) for j in range(n + 1)], R + [_dyadic(R1, 10)]


def check_window(n, window):
    """``ValueError`` unless the window lies in the plane with room for ``n`` boxes a side."""
    f0, f1, R0, R1 = (Fraction(w) for w in window)
    if not (PLANE[0] <= f0 < f1 <= PLANE[1] and PLANE[2] <= R0 < R1 <= PLANE[3]):
        raise ValueError(f"window must satisfy 0 <= f0 < f1 <= 1 and 0.5 <= R0 < R1 <= 100, got {window}")
    fe, R = edges(n, window)
    if any(b <= a for e in (fe, R) for a, b in zip(e, e[1:])):
        raise ValueError(f"window {window}: too narrow for {n} boxes a side (edges are multiples of "
                         f"2^-24 in f/F and 2^-10 in w^2 R/F)")


def box_of(n, i, j, window=PLANE):
    """The box ``i`` (over ``w^2 R/F``), ``j`` (over ``f/F``)."""
    fe, Re = edges(n, window)
    return ParamBox(F=1, f=(fe[j], fe[j + 1]), omega=1, l=0, r=(Re[i], Re[i + 1]))


def numerical(fF, R, claims=tuple(CLAIMS)):
    """Whether each claim holds numerically at ``(f/F, w^2 R/F)``: the atlas's evaluators
    (``claims.symmetric`` for x1 and x2; for period 3 the centre ``claims.subharmonic`` tests,
    ``Point.centre`` of either branch with ``|tr| < 2``, without its periods 1 and 5)."""
    pt, out = C.Point(fF, R), {}
    if "x1-centre" in claims or "x2-saddle" in claims:
        sym = C.symmetric(pt)
        out["x1-centre"] = bool(sym["x1"] and sym["x1_trace"] is not None and abs(sym["x1_trace"]) < 2)
        out["x2-saddle"] = bool(sym["x2"] and sym["x2_trace"] is not None and sym["x2_trace"] > 2)
    if "period3-centre" in claims:
        trs = [pt.centre(branch, 3, ("centre",)) for branch in (1, 2)]
        out["period3-centre"] = any(tr is not None and abs(tr) < 2 for tr in trs)
    return out


def _samples(box):
    f, r = (box.lo("f"), box.hi("f")), (box.lo("r"), box.hi("r"))
    pts = [(a, b) for a in f for b in r] + [((f[0] + f[1]) / 2, (r[0] + r[1]) / 2)]
    return [(float(a), float(b)) for a, b in pts]


def crosses_tr_minus_2(box, branch, m):
    """The closed form's ``k h - 2`` changes sign over the box's corners (``tr = -2`` inside)."""
    signs = set()
    for fF, R in _samples(box)[:4]:
        sol = P.symmetric_solution(box.point(f=Fraction(fF), r=Fraction(R)), branch, m=m, dps=20)
        if sol is not None:
            signs.add(sol.kh() > 2)
    return len(signs) > 1


def _ball(ball, extra=0):
    """``[mid, radius]`` as decimal strings, the radius rounded up (plus ``extra``)."""
    mid, rad = decimal_ball(ball, BALL_DIGITS)
    return [mid, radius_text(rad + extra)]


def _section(ticks, box, hull):
    """The phase ``w t0`` (decimal string) and the extra radii that make the balls hold at the
    written (rounded) phase: ``|dx| <= |v| dt``, ``|dv| <= (F + f) dt``."""
    phase = ticks - (ticks.numerator // ticks.denominator)
    angle = 2 * arb.pi() * from_fraction(phase)
    text = angle.mid().str(PHASE_DIGITS, radius=False) if phase else "0"
    dt = (abs(from_fraction(Fraction(text)) - angle)).upper()     # w = 1 on the plane
    dx = float((dt * (abs(hull[1]) + 1)).upper())
    dv = float((dt * (1 + from_fraction(box.hi("f")))).upper())
    return text, str(phase), dx, dv


def prove_box(claim, n, i, j, inside, crosses, window=PLANE, max_leaves=MAX_LEAVES, method=METHOD):
    """One record (module docstring) of ``claim`` on box ``(i, j)``."""
    box = box_of(n, i, j, window)
    fe, Re = edges(n, window)
    rec = {"claim": claim, "f_over_F": [float(fe[j]), float(fe[j + 1])],
           "w2R_over_F": [float(Re[i]), float(Re[i + 1])], "status": "unproved", "reason": None,
           "phase": None, "x": None, "v": None, "trace": None,
           "inside_numerical": inside, "crosses_tr_minus_2": crosses, "leaves": 0}
    if inside is None:
        rec["reason"] = "not attempted: the claim does not hold numerically at any corner or the centre"
        return rec
    branch, m, kind = CLAIMS[claim]
    got, ticks = symmetric_cover(box, branch, m, kind=kind,
                                 max_leaves=max_leaves if inside else min(max_leaves, BOUNDARY_LEAVES),
                                 method=method)
    if got is None:
        rec["reason"] = ticks
        return rec
    rec["leaves"] = len(got.leaves)
    if not got.proved:
        rec["reason"] = got.reason
        return rec
    with workprec(max(p.prec for p in got.leaves)):
        hull = got.hull()
        text, over_T, dx, dv = _section(ticks, box, hull)
        rec.update(status="proved", phase=text, phase_over_T=over_T, x=_ball(hull[0], dx),
                   v=_ball(hull[1], dv), trace=_ball(hull[2]),
                   unique_in_ball=all(p.unique_in_point for p in got.leaves))
    return rec


def evaluate_chunk(n, cells, claims, window=PLANE, max_leaves=MAX_LEAVES, method=METHOD,
                   dissip_boxes=D.MAX_BOXES):
    """One task: the records of every claim on the boxes ``cells`` (runs on a worker)."""
    out = []
    orbit = tuple(c for c in claims if c in CLAIMS)
    for i, j in cells:
        box = box_of(n, i, j, window)
        flags = [numerical(*p, orbit) for p in _samples(box)] if orbit else []
        for claim in claims:
            if claim == D.CLAIM:
                out.append(D.prove_box(box, dissip_boxes))
                continue
            hits = [fl[claim] for fl in flags]
            inside = True if all(hits) else (False if any(hits) else None)
            branch, m, kind = CLAIMS[claim]
            crosses = kind == "elliptic" and crosses_tr_minus_2(box, branch, m)
            out.append(prove_box(claim, n, i, j, inside, crosses, window, max_leaves, method))
    return out


def compute(n, claims=tuple(CLAIMS), *, scheduler=None, workers=2, client=None, chunk=CHUNK,
            progress=None, window=PLANE, max_leaves=MAX_LEAVES, method=METHOD, dissip_boxes=D.MAX_BOXES):
    """``(records, stats)``: every claim on every box, in grid order (``i`` over ``w^2 R/F``,
    then ``j`` over ``f/F``, then the claims), on ``client`` or a new cluster."""
    unknown = [c for c in claims if c not in ALL_CLAIMS]
    if unknown:
        raise ValueError(f"unknown proved-atlas claim(s) {unknown}; known: {', '.join(ALL_CLAIMS)}")
    if not (isinstance(dissip_boxes, int) and not isinstance(dissip_boxes, bool) and dissip_boxes >= 1):
        raise ValueError(f"max_boxes must be an int >= 1, got {dissip_boxes!r}")
    if not (isinstance(n, int) and not isinstance(n, bool) and 2 <= n <= 256):
        raise ValueError(f"grid must be an int in [2, 256], got {n!r}")
    cluster.check_workers(workers)
    if not (isinstance(max_leaves, int) and 1 <= max_leaves <= 4096):
        raise ValueError(f"max_leaves must be an int in [1, 4096], got {max_leaves!r}")
    check_window(n, window)
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    cells = [(i, j) for i in range(n) for j in range(n)]
    tag = zlib.crc32(repr((tuple(claims), tuple(window), max_leaves, chunk, method, dissip_boxes)).encode())
    chunks = [cells[k:k + chunk] for k in range(0, len(cells), chunk)]
    with cluster.client(scheduler, workers, given=client, preload=("cross_check.atlas",)) as client:
        t0 = time.perf_counter()
        futures = {client.submit(evaluate_chunk, n, part, tuple(claims), window, max_leaves, method,
                                 dissip_boxes, retries=RETRIES, pure=False,
                                 key=f"proved-atlas-{n}-{k}-{tag}"): k
                   for k, part in enumerate(chunks)}
        results = [None] * len(chunks)
        for done, fut, eta in cluster.as_done(futures):
            results[futures[fut]] = fut.result()
            if progress:
                progress(f"proved atlas: chunk {done}/{len(chunks)}, ETA {eta:.0f} s")
        seconds = time.perf_counter() - t0
        n_workers = len(client.scheduler_info()["workers"])
    records = [r for part in results for r in part]
    return records, {"seconds": round(seconds, 1), "boxes": len(cells), "workers": n_workers,
                     "window": [str(w) for w in window], "max_leaves": max_leaves, "method": method}


def summary(records):
    """Per claim: boxes inside the numerical region, how many proved, the fraction; the same
    without the boxes the closed-form ``tr = -2`` curve crosses; proved boxes in all."""
    out = {}
    for claim in dict.fromkeys(r["claim"] for r in records):
        mine = [r for r in records if r["claim"] == claim]
        if claim == D.CLAIM:
            out[claim] = D.summary(mine)
            continue
        inside = [r for r in mine if r["inside_numerical"]]
        clean = [r for r in inside if not r["crosses_tr_minus_2"]]
        proved = lambda rs: sum(r["status"] == "proved" for r in rs)  # noqa: E731
        out[claim] = {"boxes": len(mine), "proved": proved(mine), "inside": len(inside),
                      "proved_inside": proved(inside),
                      "fraction_inside": round(proved(inside) / len(inside), 4) if inside else None,
                      "inside_off_tr_minus_2": len(clean),
                      "fraction_off_tr_minus_2": round(proved(clean) / len(clean), 4) if clean else None}
    return out


def provenance(n, stats):
    import platform

    import dask
    import distributed
    import flint

    return {"generator": "python -m cross_check prove --atlas", "grid": n,
            "scene": "F = 1, f = f/F, omega = 1, l = 0, r = w^2 R/F (dimensionless)",
            "f_over_F": "edges f0 + (f1 - f0) j/N",
            "w2R_over_F": "edges log-spaced over [R0, R1], inner ones rounded to multiples of 2^-10",
            "max_leaves": stats["max_leaves"], "boundary_leaves": BOUNDARY_LEAVES,
            "method": stats.get("method", METHOD), "stats": stats,
            "versions": {"python": platform.python_version(), "mpmath": mpmath.__version__,
                         "python-flint": flint.__version__, "dask": dask.__version__,
                         "distributed": distributed.__version__}}


def write(out_dir, records, n, stats, window=PLANE):
    """``proved_atlas.json``, ``proved_atlas_meta.json`` and one PNG per claim; the summary."""
    out = pathlib.Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    (out / "proved_atlas.json").write_text(json.dumps(records, indent=0) + "\n")
    summ = summary(records)
    meta = {"provenance": provenance(n, stats), "summary": summ}
    (out / "proved_atlas_meta.json").write_text(json.dumps(meta, indent=1) + "\n")
    draw(records, n, out, window)
    return summ


def _closed_forms(ax, claim):
    """The closed forms the region is held to: the fold ``f/F = 2/(m pi)``; for the centres the
    parabolic curve ``k h = 2`` (``tr = -2``), ``w^2 R/F = S_m (m^2 pi^2 / 2 - 1)``; for ``x2``
    its non-sticking boundary ``w^2 R/F = S_1`` (``S_m = sqrt(4 - m^2 pi^2 (f/F)^2)``)."""
    import numpy as np

    branch, m, kind = CLAIMS[claim]
    fold = 2 / (m * math.pi)
    f = np.linspace(0, fold, 400)
    S = np.sqrt(np.maximum(4 - (m * math.pi * f) ** 2, 0))
    ax.axvline(fold, color="k", ls="--", lw=0.8, label=f"fold f/F = 2/({m} pi)")
    if kind == "elliptic":
        ax.plot(f, S * (m * m * math.pi ** 2 / 2 - 1), color="tab:blue", lw=1.0, label="tr = -2 (k h = 2)")
    else:
        ax.plot(f, S, color="tab:purple", lw=1.0, label="x2 non-sticking boundary")


def draw(records, n, out_dir, window=PLANE):
    """One PNG per claim: the numerical region (grey: inside, light: some samples), the proved
    boxes (green) and the boxes inside the region that failed (red outline)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch, Rectangle

    paths = []
    for claim in dict.fromkeys(r["claim"] for r in records):
        if claim == D.CLAIM:
            paths.append(D.draw([r for r in records if r["claim"] == claim], n, out_dir, window))
            continue
        fig, ax = plt.subplots(figsize=(6.4, 4.8))
        for r in (r for r in records if r["claim"] == claim):
            (f0, f1), (R0, R1) = r["f_over_F"], r["w2R_over_F"]
            shade = {True: "0.55", False: "0.85", None: "white"}[r["inside_numerical"]]
            ax.add_patch(Rectangle((f0, R0), f1 - f0, R1 - R0, color=shade, lw=0))
            if r["status"] == "proved":
                ax.add_patch(Rectangle((f0, R0), f1 - f0, R1 - R0, fc="tab:green", alpha=0.65, lw=0))
            elif r["inside_numerical"]:
                ax.add_patch(Rectangle((f0, R0), f1 - f0, R1 - R0, fill=False, ec="tab:red", lw=1.0))
        ax.set_xscale("linear")
        ax.set_yscale("log")
        ax.set_xlim(float(window[0]), float(window[1]))
        ax.set_ylim(float(window[2]), float(window[3]))
        _closed_forms(ax, claim)
        ax.set_xlabel("f/F")
        ax.set_ylabel("w^2 R/F")
        s = summary([r for r in records if r["claim"] == claim])[claim]
        frac = "n/a" if s["fraction_inside"] is None else f"{100 * s['fraction_inside']:.0f}%"
        ax.set_title(f"proved: {claim} ({n} x {n}); {s['proved_inside']}/{s['inside']} boxes "
                     f"inside the numerical region ({frac})", fontsize=9)
        lines, _ = ax.get_legend_handles_labels()
        ax.legend(handles=[Patch(color="0.55", label="numerical region (5 of 5 samples)"),
                           Patch(color="0.85", label="partly (some samples)"),
                           Patch(color="tab:green", alpha=0.65, label="proved for every parameter"),
                           Patch(fill=False, ec="tab:red", label="inside, not proved")] + lines,
                  fontsize=7, loc="upper right")
        fig.tight_layout()
        path = pathlib.Path(out_dir) / f"proved_atlas_{claim}.png"
        fig.savefig(path, dpi=100)
        plt.close(fig)
        paths.append(path)
    return paths


def main(argv=None) -> int:
    """``prove --atlas [--grid N] [--claim ID ...] [--workers K | --scheduler ADDR] [--out DIR]``."""
    import argparse

    ap = argparse.ArgumentParser(
        prog="python -m cross_check prove --atlas",
        description="The proved atlas: x1-centre, x2-saddle and period3-centre proved for every "
                    "parameter of each box of an N x N cover of (f/F, w^2 R/F), on Dask.  Writes "
                    "proved_atlas.json (one record per claim and box), proved_atlas_meta.json and "
                    "one PNG per claim; --claim dissip-invariance adds Phi(Omega_dissip) in "
                    "Omega_dissip, proved / refuted / undecided per box.",
        epilog="Exit status: 0 written, 2 bad input.  N = 32 takes about a minute on 2 workers (impacts; shooting: about 25 minutes).")
    ap.add_argument("--grid", type=int, default=32, help="N: N x N boxes (default 32)")
    ap.add_argument("--claim", nargs="+", choices=list(ALL_CLAIMS), default=list(CLAIMS),
                    help="claims (default: the orbit claims; dissip-invariance on request)")
    ap.add_argument("--max-boxes", type=int, default=D.MAX_BOXES,
                    help=f"dissip-invariance: cover boxes tried per atlas box (default {D.MAX_BOXES})")
    group = ap.add_mutually_exclusive_group()
    group.add_argument("--workers", type=int, default=2, help="local worker processes (default 2)")
    group.add_argument("--scheduler", default=None, help="tcp://HOST:PORT of a running dask scheduler")
    ap.add_argument("--out", default="atlas", type=outputs.check_folder, help="output directory (default: atlas/)")
    ap.add_argument("--max-leaves", type=int, default=MAX_LEAVES,
                    help=f"sub-boxes one box may use before it is declared unproved (default {MAX_LEAVES})")
    ap.add_argument("--method", choices=METHODS, default=METHOD,
                    help="how a sub-box is proved: 'impacts' (the impacts as unknowns; default) or "
                         "'shooting' (the stroboscopic map in multiple-shooting form)")
    ap.add_argument("--window", nargs=4, metavar=("F0", "F1", "R0", "R1"), default=None,
                    help="zoom: cover [F0, F1] x [R0, R1] of (f/F, w^2 R/F) instead of the whole plane "
                         "(decimal numbers; exact)")
    args = ap.parse_args(argv)
    try:
        window = PLANE if args.window is None else tuple(Fraction(w) for w in args.window)
    except ValueError:
        print(f"prove --atlas: --window needs four decimal numbers, got {args.window}", file=sys.stderr)
        return 2
    try:
        records, stats = compute(args.grid, tuple(args.claim), scheduler=args.scheduler, workers=args.workers,
                                 window=window, max_leaves=args.max_leaves, method=args.method,
                                 dissip_boxes=args.max_boxes, progress=Progress())
    except ValueError as exc:
        print(f"prove --atlas: {exc}", file=sys.stderr)
        return 2
    summ = write(args.out, records, args.grid, stats, window)
    for claim, s in summ.items():
        if claim == D.CLAIM:
            print(f"{claim}: {s['proved']} proved, {s['refuted']} refuted, {s['undecided']} undecided of "
                  f"{s['boxes']} boxes ({s['refuted_inside']} refuted on a sub-box; {stats['seconds']} s)")
            continue
        frac = "n/a" if s["fraction_inside"] is None else f"{100 * s['fraction_inside']:.1f}%"
        print(f"{claim}: {s['proved_inside']} of {s['inside']} boxes inside the numerical region proved "
              f"({frac}; {s['proved']} proved in all, {stats['seconds']} s on {stats['workers']} workers)")
    print(f"{args.out}/proved_atlas.json")
    return 0
