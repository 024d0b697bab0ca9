"""The paper's branches proved on parameter intervals: rigorous continuation, shipped as data.

Three statements, each a chain of parameter boxes proved one after the other
(``reference.enclosure.continuation.prove_interval``; every box a ``ParamBox`` with exact ends,
every orbit proved for every parameter of its box by the parametric Krawczyk operator):

* ``x1-x2`` (Fig. many:wide: F = 1, w = 1, l = 0, r = 20): ``x1`` (a centre, ``|tr| < 2``) and
  ``x2`` (a saddle, ``tr > 2``), both non-sticking with two impacts a period, exist for every
  ``f`` in ``[0, f*]``, and on every box their state balls at one common section are disjoint;
  ``f* = floor(10^FOLD_DIGITS 2/pi) / 10^FOLD_DIGITS``.  With the closed form (eq. existence:
  a symmetric solution needs ``pi f <= 2F``, ``reference.paper.existence_bound``), the fold
  where they merge is enclosed in ``[f*, 2/pi]``, of width ``delta = 2/pi - f*``;
* ``period3`` (Fig. many:2pi: F = 1, w = 2 pi, l = -1, r = 1): the symmetric period-3 orbit
  (two impacts in three periods, non-sticking) exists for every ``f`` in ``[0, f3*]``,
  ``f3* = floor(10^P3_DIGITS 2/(3 pi)) / 10^P3_DIGITS``;
* ``period3-elliptic``: it is elliptic (``|tr| < 2`` proved, ``det = 1``) on
  ``[0, f_res - P3_GAP]`` and ``[f_res + P3_GAP, P3_ELLIPTIC_TO]``, where ``f_res`` is the
  closed form's ``k h = 2``: there ``tr = (kh - 2)^2 - 2 = -2`` exactly (a parabolic point, the
  trace touches -2 without crossing), so no proof of ``|tr| < 2`` can cover it.

The chains take minutes (the fold chain goes to ``1e-30`` of ``2/pi`` with precision growing
as the boxes narrow), longer than the report's budget: ``python -m cross_check prove
--intervals`` computes them and writes ``cross_check/data/proved_intervals.json`` (shipped,
with its provenance); the claims table and the report read that file, and the tests re-prove
boxes of it and check random parameters of its boxes with the point reference.
"""
from __future__ import annotations

import json
import math
import pathlib
import sys
import time
from fractions import Fraction

import mpmath

from cross_check import outputs
from cross_check.progress import Progress
from reference.enclosure.balls import decimal_ball, radius_text, workprec
from reference.enclosure.branches import common_ticks, symmetric_cover
from reference.enclosure.continuation import prove_interval
from reference.enclosure.params import ParamBox

PATH = pathlib.Path(__file__).resolve().parents[2] / "data" / "proved_intervals.json"
FOLD_DIGITS, P3_DIGITS = 30, 12
P3_GAP, P3_ELLIPTIC_TO = Fraction(3, 1000), Fraction(21, 100)
BALL_DIGITS = 30
#: sub-boxes per chain box before the chain halves the box instead
LEAVES = 8


def wide_box(a, b):
    """Fig. many:wide with ``f`` in ``[a, b]``."""
    return ParamBox(F=1, f=(a, b), omega=1, l=0, r=20)


def two_pi_box(a, b):
    """Fig. many:2pi with ``f`` in ``[a, b]``."""
    return ParamBox(F=1, f=(a, b), omega="2*pi", l=-1, r=1)


def prec_of(width):
    """Bits for a box of this width: 128, and 2.5 bits per bit of ``1/width`` near a fold
    (the fixed points there move like ``sqrt`` of the distance; measured to be enough)."""
    return max(128, int(2.5 * math.log2(1 / float(width))) + 64)


def _floor_digits(value_fn, digits):
    with mpmath.workdps(digits + 20):
        return Fraction(int(mpmath.floor(value_fn() * 10 ** digits)), 10 ** digits)


def fold_end():
    return _floor_digits(lambda: 2 / mpmath.pi, FOLD_DIGITS)


def period3_end():
    return _floor_digits(lambda: 2 / (3 * mpmath.pi), P3_DIGITS)


def resonance_f():
    """``f`` where the period-3 closed form of Fig. many:2pi has ``k h = 2`` (``tr = -2``):
    ``S_3 = 2 R w^2 / (9 pi^2 - 2)``, ``S_3 = sqrt(4 F^2 - 9 pi^2 f^2)``."""
    with mpmath.workdps(40):
        Rw2 = 2 * (2 * mpmath.pi) ** 2
        S = 2 * Rw2 / (9 * mpmath.pi ** 2 - 2)
        return Fraction(mpmath.nstr(mpmath.sqrt((4 - S ** 2) / (9 * mpmath.pi ** 2)), 30))


def _record(cover, ticks):
    with workprec(max(p.prec for p in cover.leaves)):
        x, v, tr = cover.hull()
        return {"phase_over_T": str(ticks - (ticks.numerator // ticks.denominator)), "ticks": str(ticks),
                "x": _ball(x), "v": _ball(v), "trace": _ball(tr), "leaves": len(cover.leaves),
                "unique_in_ball": all(p.unique_in_point for p in cover.leaves)}


def _ball(b):
    mid, rad = decimal_ball(b, BALL_DIGITS)
    return [mid, radius_text(rad)]


def fold_box(a, b):
    """x1 (elliptic) and x2 (saddle) over ``f`` in ``[a, b]`` at one section; their balls
    disjoint.  ``(record, None)`` or ``(None, reason)``."""
    box = wide_box(a, b)
    ticks = common_ticks(box.midpoint(), (1, 2))
    if ticks is None:
        return None, "no symmetric solution at the box's midpoint"
    got = {}
    for name, branch, kind in (("x1", 1, "elliptic"), ("x2", 2, "saddle")):
        cover, why = symmetric_cover(box, branch, kind=kind, ticks=ticks, max_leaves=LEAVES, prec=prec_of(b - a))
        if cover is None or not cover.proved:
            return None, f"{name}: {why if cover is None else cover.reason}"
        got[name] = cover
    (x1, v1, _), (x2, v2, _) = got["x1"].hull(), got["x2"].hull()
    if x1.overlaps(x2) and v1.overlaps(v2):
        return None, "the state balls of x1 and x2 overlap"
    return {name: _record(c, ticks) for name, c in got.items()}, None


def period3_box(kind):
    def prove(a, b):
        cover, ticks = symmetric_cover(two_pi_box(a, b), 1, 3, kind=kind, max_leaves=LEAVES,
                                       prec=prec_of(b - a))
        if cover is None or not cover.proved:
            return None, ticks if cover is None else cover.reason
        return {"period3": _record(cover, ticks)}, None
    return prove


def _chain(prove_box, lo, hi, first, min_width, progress, label):
    t0 = time.perf_counter()

    def tick(iv):
        progress(f"{label}: {float(iv.reached):.15g} ({len(iv.boxes)} boxes, {time.perf_counter() - t0:.0f} s)")

    iv = prove_interval(prove_box, lo, hi, first=first, min_width=min_width, max_boxes=600,
                        progress=tick)
    return {"interval": [str(iv.lo), str(iv.reached)], "complete": iv.complete, "reason": iv.reason,
            "seconds": round(time.perf_counter() - t0, 1),
            "boxes": [{"f": [str(a), str(b)], **rec} for a, b, rec in iv.boxes]}


def compute(progress=print) -> dict:
    """Every statement's chain (module docstring), JSON-ready."""
    f_star, f3_star, f_res = fold_end(), period3_end(), resonance_f()
    out = {}
    out["x1-x2"] = _chain(fold_box, 0, f_star, Fraction(1, 8), Fraction(1, 10 ** (FOLD_DIGITS + 8)),
                          progress, "x1-x2")
    out["period3"] = _chain(period3_box(None), 0, f3_star, Fraction(1, 64), Fraction(1, 10 ** (P3_DIGITS + 6)),
                            progress, "period3")
    elliptic = [_chain(period3_box("elliptic"), lo, hi, Fraction(1, 256), Fraction(1, 10 ** 8), progress,
                       f"period3-elliptic [{float(lo):.4g}, {float(hi):.4g}]")
                for lo, hi in ((Fraction(0), f_res - P3_GAP), (f_res + P3_GAP, P3_ELLIPTIC_TO))]
    out["period3-elliptic"] = {"pieces": elliptic, "f_res": str(f_res)}
    return out


def provenance(seconds) -> dict:
    import platform

    import flint

    return {"generator": "python -m cross_check prove --intervals",
            "fold_digits": FOLD_DIGITS, "period3_digits": P3_DIGITS, "period3_gap": str(P3_GAP),
            "leaves_per_box": LEAVES, "precision": "max(128, 2.5 log2(1/width) + 64) bits",
            "seconds": seconds,
            "versions": {"python": platform.python_version(), "mpmath": mpmath.__version__,
                         "python-flint": flint.__version__}}


def load(path=PATH):
    """The shipped statements (None if the file is missing: ``prove --intervals`` writes it)."""
    path = pathlib.Path(path)
    return json.loads(path.read_text()) if path.exists() else None


def _fold_gap(data):
    with mpmath.workdps(60):
        hi = Fraction(data["x1-x2"]["interval"][1])
        return float(2 / mpmath.pi - mpmath.mpf(hi.numerator) / hi.denominator)


def problems(data) -> list:
    """What is wrong with a statements file: a chain that does not start at its ``lo``, has a
    hole or an overlap between boxes, does not end at its ``interval``'s end, a fold box whose
    x1 and x2 balls meet, or the required ranges not covered (``[0.005, 0.2]`` for period 3)."""
    out = []

    def chain(name, c):
        lo, hi = (Fraction(e) for e in c["interval"])
        ends = [(Fraction(b["f"][0]), Fraction(b["f"][1])) for b in c["boxes"]]
        if not ends or ends[0][0] != lo or ends[-1][1] != hi:
            out.append(f"{name}: the boxes do not run from {lo} to {hi}")
        out.extend(f"{name}: a hole or overlap at {a1}" for (_, a1), (b0, _) in zip(ends, ends[1:]) if a1 != b0)
        out.extend(f"{name}: an empty box at {a}" for a, b in ends if not a < b)

    chain("x1-x2", data["x1-x2"])
    chain("period3", data["period3"])
    for k, piece in enumerate(data["period3-elliptic"]["pieces"]):
        chain(f"period3-elliptic[{k}]", piece)
    for b in data["x1-x2"]["boxes"]:
        balls = [[Fraction(b[o][c][0]) - Fraction(b[o][c][1]), Fraction(b[o][c][0]) + Fraction(b[o][c][1])]
                 for o in ("x1", "x2") for c in ("x", "v")]
        if not (balls[0][1] < balls[2][0] or balls[2][1] < balls[0][0]
                or balls[1][1] < balls[3][0] or balls[3][1] < balls[1][0]):
            out.append(f"x1-x2: the balls of x1 and x2 meet on {b['f']}")
    if Fraction(data["x1-x2"]["interval"][0]) != 0 or _fold_gap(data) <= 0:
        out.append("x1-x2: the interval must be [0, f*] with f* < 2/pi")
    p3 = [Fraction(e) for e in data["period3"]["interval"]]
    if not (p3[0] <= Fraction(5, 1000) and p3[1] >= Fraction(2, 10)):
        out.append(f"period3: [{p3[0]}, {p3[1]}] does not contain [0.005, 0.2]")
    return out


def lines(claim_id, data=None, path=PATH) -> list:
    """The "proved on an interval" lines of a claim (the claims table's ``proved_on``), from
    ``data`` or the file at ``path``."""
    data = load(path) if data is None else data
    if data is None:
        return [{"statement": "not computed: python -m cross_check prove --intervals writes "
                              "cross_check/data/proved_intervals.json", "interval": None}]
    src = "cross_check/data/proved_intervals.json (python -m cross_check prove --intervals)"
    fold, p3 = data["statements"]["x1-x2"], data["statements"]["period3"]
    f_star = Fraction(fold["interval"][1])
    delta = _fold_gap(data["statements"])
    if claim_id == "existence-condition":
        return [{"statement": f"x1 (centre, -2 < tr < 2) and x2 (saddle, tr > 2) of Fig. many:wide exist, "
                              f"non-sticking with two impacts, for every f/F in [0, f*], f* = 2/pi - "
                              f"{delta:.2e}", "interval": fold["interval"], "boxes": len(fold["boxes"]),
                 "gap_to_2_over_pi": delta, "source": src}]
    if claim_id == "fold-fcrit":
        return [{"statement": f"the fold is enclosed in [2/pi - {delta:.2e}, 2/pi]: x1 and x2 proved "
                              f"distinct (disjoint state balls) for every f <= f* = {float(f_star):.17g}, "
                              "and no symmetric solution for f > 2/pi (closed form, eq. existence)",
                 "interval": fold["interval"], "boxes": len(fold["boxes"]), "delta": delta, "source": src}]
    if claim_id == "subharmonic-islands":
        ell = data["statements"]["period3-elliptic"]
        pieces = " and ".join(f"[{float(Fraction(p['interval'][0])):.4g}, {float(Fraction(p['interval'][1])):.4g}]"
                              for p in ell["pieces"])
        return [{"statement": f"the period-3 orbit of Fig. many:2pi (two impacts in three periods, "
                              f"non-sticking) exists for every f in [0, {float(Fraction(p3['interval'][1])):.12g}]",
                 "interval": p3["interval"], "boxes": len(p3["boxes"]), "source": src},
                {"statement": f"it is elliptic (-2 < tr < 2 proved, det = 1) on {pieces}; at f = "
                              f"{float(Fraction(ell['f_res'])):.6f} (k h = 2) tr = -2 exactly (closed form)",
                 "interval": [p["interval"] for p in ell["pieces"]],
                 "boxes": sum(len(p["boxes"]) for p in ell["pieces"]), "source": src}]
    return []


def main(argv=None) -> int:
    """``prove --intervals [--out FILE]``: compute the chains and write the statements file."""
    import argparse

    ap = argparse.ArgumentParser(
        prog="python -m cross_check prove --intervals",
        description="The paper's branches proved on parameter intervals (rigorous continuation): "
                    "x1 and x2 of Fig. many:wide up to 1e-30 of the fold, the period-3 orbit of "
                    "Fig. many:2pi.  Writes the shipped statements file the claims table reads.",
        epilog="Exit status: 0 written and consistent, 1 a chain has a problem (listed).  Takes "
               "about ten minutes on one core.")
    ap.add_argument("--out", default=str(PATH), type=outputs.check_file, help=f"where to write (default: {PATH.relative_to(PATH.parents[2])})")
    args = ap.parse_args(argv)
    progress = Progress()
    statements = compute(progress=progress)
    data = {"provenance": provenance(round(progress.elapsed, 1)), "statements": statements}
    pathlib.Path(args.out).write_text(json.dumps(data, indent=1) + "\n")
    bad = problems(statements)
    for line in bad:
        print(f"problem: {line}", file=sys.stderr)
    for cid in ("existence-condition", "fold-fcrit", "subharmonic-islands"):
        for line in lines(cid, data):
            print(f"{cid}: {line['statement']}")
    print(args.out)
    return 1 if bad else 0
