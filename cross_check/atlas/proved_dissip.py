"""The proved atlas's ``dissip-invariance``: ``Phi(Omega_dissip) in Omega_dissip`` per box.

``python -m cross_check prove --atlas --claim dissip-invariance --grid N`` (beside the orbit
claims of ``cross_check.atlas.proved``).  On each box ``B`` of ``(f/F, w^2 R/F)`` (the atlas's
``F = w = 1``, ``l = 0``, ``r = w^2 R/F``):

* the numerical verdict: the violations (``cross_check.dynamics.violations``, a
  ``SAMPLE_GRID`` grid) at ``B``'s four corners and centre; ``inside_numerical`` True when none
  of the five has one (the claim holds numerically), False when all five have, else None;
* **proved**: the cover of the rest states (``reference.enclosure.invariance.cover``) over the
  parameter box itself -- every leaf holds for every parameter of its part of ``B`` (the cover
  halves parameters where their spread is what fails), at most ``MAX_BOXES`` tries;
* **refuted**: a counterexample ball proved for every parameter of ``B``
  (``prove_counterexample`` on the ``ParamBox``, candidates from the centre's grid);
* **undecided** otherwise, with the reason.  A box whose samples show violations but which
  is not refuted as a whole is searched for a sub-box (``2^-k`` of it, ``k`` in
  ``SUB_STEPS``, about its most violating sample) on which a ball is proved for every
  parameter: ``refuted_inside`` holds it -- the claim is then *false somewhere in* ``B``,
  proved, though not on all of it.

The proofs of ``B`` need one itinerary for every parameter: at grid 16 the boxes are wide
(``f/F`` by 1/16, ``w^2 R/F`` by a factor 1.39), and a counterexample ball rarely survives
the whole box (the violating sets move with the parameters); ``refuted_inside`` says where
the claim is proved false all the same.
"""
from __future__ import annotations

import math
import time
from fractions import Fraction

from cross_check.dynamics import violations
from reference.enclosure.balls import DEFAULT_PREC
from reference.enclosure.invariance import cover, prove_counterexample

CLAIM = "dissip-invariance"
#: cover tries per atlas box (more rarely helps: the boxes below the fold that 600 do not
#: prove, 8000 did not either); the sample grid of the numerical verdict; the sub-box search's
#: halvings (each sub-box 2^-k of the box, k in SUB_STEPS)
MAX_BOXES, SAMPLE_GRID, SUB_STEPS = 600, 48, (2, 4, 6, 8)
#: candidate balls and radii tried per (sub-)box; the proofs run at one precision
CANDIDATES, TRIES = 2, 5


def _samples(box):
    f, r = (box.lo("f"), box.hi("f")), (box.lo("r"), box.hi("r"))
    return [(a, b) for a in f for b in r] + [((f[0] + f[1]) / 2, (r[0] + r[1]) / 2)]


def numerical(box):
    """``(inside, samples)``: ``inside`` as in the module docstring, ``samples`` the
    ``(f/F, w^2 R/F, violations)`` of the five samples."""
    out = []
    for f, r in _samples(box):
        mask = violations.violations(box.point(f=f, r=r), SAMPLE_GRID)[2]
        out.append((float(f), float(r), int(mask.sum())))
    hits = [s[2] > 0 for s in out]
    return (not any(hits)) if (all(hits) or not any(hits)) else None, out


def _refute(box, count=CANDIDATES, zoomed=True):
    got, _ = violations.refute(lambda x, v, rx, rv: prove_counterexample(box, x, v, rx, rv,
                                                                         max_prec=DEFAULT_PREC),
                               box.midpoint(), count=count, tries=TRIES, zoomed=zoomed)
    return got


def _ball(got):
    return {"x": [float(got.x[0]), float(got.x[1])], "v": [float(got.v[0]), float(got.v[1])],
            "itinerary": got.events}


def _sub_box(box, f, r, k):
    """The sub-box of ``box`` of ``2^-k`` its widths about ``(f, r)`` (clamped inside)."""
    out = {}
    for name, centre in (("f", Fraction(f)), ("r", Fraction(r))):
        lo, hi = box.lo(name), box.hi(name)
        half = (hi - lo) / 2 ** (k + 1)
        c = min(max(centre, lo + half), hi - half)
        out[name] = (c - half, c + half)
    return box.replace(**out)


def refuted_inside(box, samples):
    """A sub-box about the sample with the most violations with a ball proved for every
    parameter of it (``{"f_over_F", "w2R_over_F", "ball"}``), else None."""
    for f, r, hits in sorted(samples, key=lambda s: -s[2])[:1]:
        if not hits:
            break
        for k in SUB_STEPS:
            sub = _sub_box(box, Fraction(f), Fraction(r), k)
            got = _refute(sub, count=1, zoomed=False)
            if got is not None:
                return {"f_over_F": [float(sub.lo("f")), float(sub.hi("f"))],
                        "w2R_over_F": [float(sub.lo("r")), float(sub.hi("r"))], "ball": _ball(got)}
    return None


def prove_box(box, max_boxes=MAX_BOXES) -> dict:
    """The record of ``box`` (a ``ParamBox`` of the atlas plane; module docstring)."""
    start = time.perf_counter()
    inside, samples = numerical(box)
    rec = {"claim": CLAIM, "f_over_F": [float(box.lo("f")), float(box.hi("f"))],
           "w2R_over_F": [float(box.lo("r")), float(box.hi("r"))], "status": "undecided",
           "reason": None, "inside_numerical": inside, "crosses_tr_minus_2": False, "leaves": 0,
           "boxes_tried": 0, "counterexample": None, "refuted_inside": None,
           "samples": [list(s) for s in samples]}
    if any(s[2] for s in samples):
        got = _refute(box)
        if got is not None:
            rec.update(status="refuted", counterexample=_ball(got))
        else:
            rec["refuted_inside"] = refuted_inside(box, samples)
            rec["reason"] = ("violations at the samples; no ball proved for every parameter of the box"
                             + ("; refuted on a sub-box (refuted_inside)" if rec["refuted_inside"] else ""))
    else:
        cov = cover(box, max_boxes=max_boxes)
        left = cov.undecided()
        rec.update(leaves=len(cov.leaves), boxes_tried=cov.tried)
        if left:
            rec["reason"] = f"{len(left)} of {len(cov.leaves)} cover boxes not proved ({left[0].result.reason})"
        else:
            rec["status"] = "proved"
            rec["return_within"] = max(float(leaf.result.within) for leaf in cov.leaves)
    rec["seconds"] = round(time.perf_counter() - start, 2)
    return rec


def summary(records) -> dict:
    """Boxes, and the fractions proved / refuted / undecided (and refuted inside)."""
    n = len(records)
    count = {s: sum(r["status"] == s for r in records) for s in ("proved", "refuted", "undecided")}
    inside = sum(bool(r["refuted_inside"]) for r in records)
    out = {"boxes": n, **count, "refuted_inside": inside,
           "inside": sum(r["inside_numerical"] is True for r in records),
           "proved_inside": sum(r["status"] == "proved" and r["inside_numerical"] is True for r in records)}
    for s in ("proved", "refuted", "undecided", "refuted_inside"):
        out[f"fraction_{s}"] = round(out[s] / n, 4) if n else None
    out["fraction_inside"] = round(out["proved_inside"] / out["inside"], 4) if out["inside"] else None
    out["fraction_off_tr_minus_2"] = out["fraction_inside"]
    return out


def draw(records, n, out_dir, window):
    """``proved_atlas_dissip-invariance.png``: the numerical map (the violations' share of the
    five samples) beside the proved map (proved, refuted, refuted inside, undecided)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch, Rectangle

    fig, (left, right) = plt.subplots(1, 2, figsize=(11.5, 4.8), sharey=True)
    colours = {"proved": "tab:green", "refuted": "tab:red", "undecided": "white"}
    for r in records:
        (f0, f1), (R0, R1) = r["f_over_F"], r["w2R_over_F"]
        share = sum(s[2] > 0 for s in r["samples"]) / len(r["samples"])
        left.add_patch(Rectangle((f0, R0), f1 - f0, R1 - R0, color=str(1 - 0.7 * share), lw=0))
        right.add_patch(Rectangle((f0, R0), f1 - f0, R1 - R0, fc=colours[r["status"]], ec="0.8", lw=0.3))
        if r["refuted_inside"]:
            right.add_patch(Rectangle((f0, R0), f1 - f0, R1 - R0, fill=False, hatch="///", ec="tab:red", lw=0))
    s = summary(records)
    for ax, title in ((left, "numerical: share of the 5 samples with violations (dark: all)"),
                      (right, f"proved ({n} x {n}): {s['proved']} proved, {s['refuted']} refuted, "
                              f"{s['undecided']} undecided ({s['refuted_inside']} false inside)")):
        ax.set_yscale("log")
        ax.set_xlim(float(window[0]), float(window[1]))
        ax.set_ylim(float(window[2]), float(window[3]))
        ax.axvline(2 / math.pi, color="k", ls="--", lw=0.8)
        ax.set_xlabel("f/F")
        ax.set_title(title, fontsize=8)
    left.set_ylabel("w^2 R/F")
    right.legend(handles=[Patch(color="tab:green", label="proved for every parameter"),
                          Patch(color="tab:red", label="refuted: a ball for every parameter"),
                          Patch(fill=False, hatch="///", ec="tab:red", label="refuted on a sub-box"),
                          Patch(fc="white", ec="0.5", label="undecided")], fontsize=7, loc="upper right")
    fig.suptitle("dissip-invariance: Phi(Omega_dissip) in Omega_dissip (fold f/F = 2/pi dashed)", fontsize=9)
    fig.tight_layout()
    path = f"{out_dir}/proved_atlas_{CLAIM}.png"
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path
