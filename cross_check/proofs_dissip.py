"""``python -m cross_check prove --claim dissip-invariance``: the paper's observation
``Phi(Omega_dissip) in Omega_dissip`` proved or refuted by proof, scene by scene.

For each scene (built-in ``--scenes NAME ...``, or the user's ``--scene "F=1 f=0.3 ..."``,
``--scenes-file FILE``) one of three results:

* **refuted**: a proved counterexample, a ball of starts each proved in ``Omega_dissip`` and
  each image proved in ``Omega_pres`` (``reference.enclosure.invariance.prove_counterexample``).
  The candidates come from ``fast`` (``cross_check.dynamics.violations``: the deepest
  violations of a grid), the ball is shrunk until its proof closes;
* **proved**: no counterexample found, and the cover of every rest state ``(x, 0)`` at every
  phase ``tau`` by boxes, each proved to return to rest within one period
  (``reference.enclosure.invariance.cover``, ``reference.enclosure.rest``): a theorem for the
  scene, the boxes with their bounds are its certificate;
* **undecided**: neither closed; the boxes the cover left, each with its reason.

Output ``DIR/dissip_invariance.json`` (``--out DIR``, default ``dissip_invariance/``), format
``FORMAT``: for one scene the record itself, for several ``{"format_version", "claim",
"scenes": [record, ...]}``.  A record: ``format_version``, ``claim``, ``scene`` (its exact
parameters), ``T``, ``verdict``, ``reason``, ``boxes`` (``x``, ``tau``: float intervals
rounded *inwards* from the exact box ``x = l + xi (r - l)``, ``tau = phase T`` with ``xi``,
``phase`` exact fractions; ``stuck``; ``return_within``: the proved bound rounded up, 0 for a
stuck box, null if not proved; ``reason`` for a box not proved), ``counterexample`` (``x``,
``v``: ``[mid, radius]`` floats, exactly the ball proved; ``zero_before``: a time before
which ``v`` has vanished; ``itinerary``), ``stats``, ``provenance``.

Exit status: 0 when every scene is proved or refuted (both are results), 1 when one is
undecided, 2 on bad input.  ``--shipped`` proves the scenes of the claims table
(``cross_check.paper.claims.regions``) and writes the shipped file it reads.
"""
from __future__ import annotations

import json
import math
import pathlib
import sys
import time

from flint import arb

from cross_check import golden, outputs, scenefile, scenes
from cross_check.dynamics import violations
from cross_check.paper.claims import regions
from cross_check.progress import Progress
from reference.enclosure.balls import BallModel, from_fraction, workprec
from reference.enclosure.invariance import MAX_BOXES, PREC, cover, prove_counterexample

FORMAT = 1
CLAIM = "dissip-invariance"


def _float_in(ball, up: bool) -> float:
    """The float nearest an exact ball end, moved inwards (``up``: at least the lower end)."""
    end = ball.upper() if up else ball.lower()
    value = float(end)
    while (arb(value) < end) if up else (arb(value) > end):
        value = math.nextafter(value, math.inf if up else -math.inf)
    return value


def _bound_up(ball) -> float:
    """A float at least the ball's upper end (a bound rounded up)."""
    return _float_in(ball, up=True)


def box_record(m, leaf) -> dict:
    """One box of the certificate (module docstring), at the cover's precision."""
    xi, phi, res = leaf.xi, leaf.phi, leaf.result
    gap = m.r - m.l
    x_lo, x_hi = m.l + from_fraction(xi[0]) * gap, m.l + from_fraction(xi[1]) * gap
    t_lo, t_hi = from_fraction(phi[0]) * m.T, from_fraction(phi[1]) * m.T
    tau_hi = _float_in(t_hi, False)
    if phi[1] == 1:                   # tau in [0, T): below T's own float too
        tau_hi = math.nextafter(min(tau_hi, float(m.T)), 0.0)
    return {"x": [_float_in(x_lo, True), _float_in(x_hi, False)],
            "tau": [_float_in(t_lo, True), tau_hi],
            "xi": [str(xi[0]), str(xi[1])], "phase": [str(phi[0]), str(phi[1])],
            "stuck": bool(res.stuck),
            "return_within": (0.0 if res.stuck else _bound_up(res.within)) if res.proved else None,
            "reason": None if res.proved else res.reason}


def counterexample_record(got, m) -> dict:
    return {"x": [float(got.x[0]), float(got.x[1])], "v": [float(got.v[0]), float(got.v[1])],
            "zero_before": _bound_up(got.zero), "itinerary": got.events,
            "statement": "every start of the ball has v = 0 at some time before zero_before <= T "
                         "(Omega_dissip), and its motion has v != 0 on all of [T, 2T] (the image "
                         "is in Omega_pres)"}


def decide(sc, *, max_boxes=MAX_BOXES, progress=print, search=True) -> dict:
    """The record (module docstring) of one scene: a counterexample first (``search``), else
    the cover."""
    start = time.perf_counter()
    with workprec(PREC):
        m = BallModel(sc)
        T = float(m.T)
    rec = {"format_version": FORMAT, "claim": CLAIM, "scene": golden.scene_record(sc), "T": T,
           "verdict": "undecided", "reason": None, "boxes": [], "counterexample": None, "stats": {}}
    got, tried = (None, 0)
    if search:
        progress(f"{sc.name}: searching for a counterexample (fast grid, then proofs of balls)")
        got, tried = violations.refute(lambda x, v, rx, rv: prove_counterexample(sc, x, v, rx, rv), sc,
                                       progress=progress)
    rec["stats"]["counterexample_balls_tried"] = tried
    rec["stats"]["counterexample_seconds"] = round(time.perf_counter() - start, 2)
    if got is not None:
        with workprec(PREC):
            rec.update(verdict="refuted", counterexample=counterexample_record(got, m),
                       reason="a proved counterexample: Omega_dissip is not invariant")
        progress(f"{sc.name}: refuted by the ball x = {got.x[0]!r} +- {got.x[1]:.3g}, "
                 f"v = {got.v[0]!r} +- {got.v[1]:.3g}")
        rec["stats"]["seconds"] = round(time.perf_counter() - start, 2)
        return rec
    progress(f"{sc.name}: no counterexample proved ({tried} balls tried); covering the rest states")
    cov = cover(sc, max_boxes=max_boxes, progress=progress)
    with workprec(PREC):
        m = BallModel(sc)
        rec["boxes"] = [box_record(m, leaf) for leaf in cov.leaves]
    left = cov.undecided()
    rec["stats"].update(boxes_tried=cov.tried, boxes=len(cov.leaves), undecided=len(left),
                        cover_seconds=round(cov.seconds, 2))
    if not left:
        worst = max((b["return_within"] for b in rec["boxes"]), default=0.0)
        rec.update(verdict="proved", reason=f"every rest state (x, 0) at a time tau in [0, T) returns to "
                                            f"rest by 2T, within {worst:.6g} (T = {T:.6g}; "
                                            f"{len(cov.leaves)} boxes)")
    else:
        tried = [leaf for leaf in left if not leaf.result.reason.startswith("not tried")] or left
        rec["reason"] = (f"{len(left)} of {len(cov.leaves)} boxes not proved (e.g. "
                         f"{tried[0].result.reason}); no counterexample proved")
    rec["stats"]["seconds"] = round(time.perf_counter() - start, 2)
    progress(f"{sc.name}: {rec['verdict']} ({rec['reason']})")
    return rec


def dumps(data) -> str:
    """JSON, indented, with one line per box (a certificate holds thousands of boxes)."""
    boxes = []

    def strip(obj):
        if isinstance(obj, dict):
            return {k: (_mark(boxes, v) if k == "boxes" and isinstance(v, list) else strip(v))
                    for k, v in obj.items()}
        return [strip(v) for v in obj] if isinstance(obj, list) else obj
    text = json.dumps(strip(data), indent=1)
    for k, rows in enumerate(boxes):
        inner = ",\n  ".join(json.dumps(b, separators=(", ", ": ")) for b in rows)
        text = text.replace(f'"@boxes{k}@"', f"[\n  {inner}\n ]" if rows else "[]")
    return text + "\n"


def _mark(store, rows):
    store.append(rows)
    return f"@boxes{len(store) - 1}@"


def provenance() -> dict:
    import platform

    import flint
    return {"generator": "python -m cross_check prove --claim dissip-invariance",
            "versions": {"python": platform.python_version(), "python-flint": flint.__version__}}


def write(out_dir, records) -> pathlib.Path:
    """``DIR/dissip_invariance.json``: the record of one scene, or the list of several."""
    out = pathlib.Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    for rec in records:
        rec["provenance"] = provenance()
    data = records[0] if len(records) == 1 else {"format_version": FORMAT, "claim": CLAIM,
                                                   "scenes": records}
    path = out / "dissip_invariance.json"
    path.write_text(dumps(data))
    return path


def main(argv=None) -> int:
    """``prove --claim dissip-invariance [--scenes NAME ...] [--scene ...] [--scenes-file F]
    [--out DIR] [--max-boxes N] [--shipped]``."""
    import argparse

    ap = argparse.ArgumentParser(
        prog="python -m cross_check prove --claim dissip-invariance",
        description="Phi(Omega_dissip) in Omega_dissip, proved (a cover of the rest states at times "
                    "tau in [0, T), each box returning to rest by 2T) or refuted (a proved "
                    "counterexample ball), per scene.  Writes DIR/dissip_invariance.json.",
        epilog="Exit status: 0 every scene proved or refuted, 1 one undecided, 2 bad input.  "
               "Fig. fig:regs (fig:many:wide/f=0.6) takes about a second.")
    ap.add_argument("--claim", choices=[CLAIM], required=True, help="the claim (dissip-invariance)")
    ap.add_argument("--scenes", nargs="+", metavar="NAME", choices=list(scenes.SCENES),
                    help="built-in scenes")
    scenefile.add_arguments(ap, "prove the claim on")
    ap.add_argument("--out", default="dissip_invariance", type=outputs.check_folder,
                    help="output directory (default: dissip_invariance/)")
    ap.add_argument("--max-boxes", type=int, default=MAX_BOXES,
                    help=f"boxes the cover may try per scene (default {MAX_BOXES})")
    ap.add_argument("--no-search", action="store_true", help="skip the counterexample search (cover only)")
    ap.add_argument("--shipped", action="store_true",
                    help="prove the claims table's scenes and write the shipped file it reads")
    args = ap.parse_args(argv)
    try:
        user = scenefile.from_args(args)
    except ValueError as exc:
        print(f"prove: {exc}", file=sys.stderr)
        return 2
    if args.max_boxes < 1:
        print(f"prove: --max-boxes must be >= 1, got {args.max_boxes}", file=sys.stderr)
        return 2
    if args.shipped:
        return shipped(args.max_boxes)
    names = (args.scenes or []) + user
    if not names:
        print("prove: --claim dissip-invariance needs --scenes, --scene or --scenes-file (or --shipped)",
              file=sys.stderr)
        return 2
    progress = Progress()
    records = [decide(scenes.scene(n), max_boxes=args.max_boxes, progress=progress,
                      search=not args.no_search) for n in names]
    path = write(args.out, records)
    for rec in records:
        print(f"{rec['scene']['name']}: {rec['verdict']}: {rec['reason']} ({rec['stats']['seconds']} s)")
    print(path)
    return 0 if all(r["verdict"] != "undecided" for r in records) else 1


def shipped(max_boxes=MAX_BOXES) -> int:
    """Prove the claims table's scenes (``regions.PROOF_SCENES``) and write ``regions.PROOF_PATH``."""
    progress = Progress()
    records = []
    for label, sc in regions.PROOF_SCENES:
        rec = decide(sc, max_boxes=max_boxes, progress=progress)
        rec["label"] = label
        records.append(rec)
    for rec in records:
        rec["provenance"] = provenance()
    regions.PROOF_PATH.write_text(dumps({"format_version": FORMAT, "claim": CLAIM, "scenes": records}))
    for rec in records:
        print(f"{rec['label']}: {rec['verdict']}: {rec['reason']} ({rec['stats']['seconds']} s)")
    print(regions.PROOF_PATH)
    return 0 if all(r["verdict"] != "undecided" for r in records) else 1
