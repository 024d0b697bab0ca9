"""``python -m cross_check prove``: the computer-assisted proofs, end to end.

* ``--golden``: re-prove every golden input (``reference.enclosure.enclose_map`` on the exact
  input), check that the stored record (``cross_check/data/golden``, written by
  ``python -m cross_check golden``) is what the proof gives, and that every written digit of
  ``Phi`` lies in its ball; one line per scene, then the counts, the widest proved radius and
  the time.
* ``--orbits``: the claims whose verdict rests on a periodic orbit
  (``cross_check.paper.claims``, ``ORBIT_CLAIMS``), each with its orbits proved by the Krawczyk
  operator (``reference.enclosure.prove_periodic``): box radius, multipliers, type, or the
  reason a proof fails.

Without either flag both run (with ``--golden-dir`` or user scenes, ``--golden`` alone).
``--golden-dir DIR`` re-proves the golden data of DIR (``golden`` or ``verify`` wrote it) instead of
the shipped data; ``--scenes-file``/``--scene`` (``cross_check.scenefile``) name user scenes whose
golden data it holds.  ``--json FILE`` writes what was proved.  Exit status 1 if a
stored golden record disagrees with its proof or a digit lies outside its ball.

* ``--atlas``: the claims proved over parameter boxes (``cross_check.atlas.proved``; its own
  options: ``prove --atlas --help``);
* ``--intervals``: the paper's branches proved on parameter intervals, written to the shipped
  ``cross_check/data/proved_intervals.json`` (``cross_check.paper.claims.intervals``; its own
  options: ``prove --intervals --help``);
* ``--claim dissip-invariance``: ``Phi(Omega_dissip) in Omega_dissip`` proved or refuted by
  proof per scene (``cross_check.proofs_dissip``; its own options: ``prove --claim
  dissip-invariance --help``).
"""
from __future__ import annotations

import json
import sys
import time
from decimal import Decimal
from fractions import Fraction

from cross_check import golden, outputs, scenefile, scenes
from cross_check.paper import claims


def _digits_inside(text, ball) -> bool:
    """The written decimal ``text``, as the interval its last digit's rounding denotes, meets
    the ball ``[mid, radius]``."""
    value = Decimal(text)
    half_unit = Fraction(10) ** value.as_tuple().exponent / 2
    return abs(Fraction(value) - Fraction(ball[0])) <= Fraction(ball[1]) + half_unit


def prove_golden(names=None, progress=print, directory=None) -> dict:
    """Re-prove every golden input of the scenes ``names`` (default: all) in the golden data of
    ``directory`` (default: the shipped data; a directory carries its scenes' parameters)."""
    names = golden.names_in(directory) if names is None else list(names)
    totals = {"inputs": 0, "proved": 0, "cases": 0, "cases_proved": 0, "mismatch": [],
              "outside": [], "widest": 0.0, "unproved": []}
    start = time.perf_counter()
    for name in names:
        data, t = golden.load(name, directory), time.perf_counter()
        sc = scenes.scene(name) if directory is None else golden.scene_of(data, f"golden file of {name!r}")
        proved_here = 0
        for case in data["cases"]:
            all_proved = True
            for label, inp in case["inputs"].items():
                exact = case["exact"] if label == "exact" else "float64"
                as_case = scenes.Case(case["name"], inp["x"], inp["v"], exact, case["how"])
                record = golden.input_proof(sc, as_case)
                where = f"{name} / {case['name']} / {label}"
                totals["inputs"] += 1
                if record != inp["enclosure"]:
                    totals["mismatch"].append(where)
                if not record["proved"]:
                    all_proved = False
                    totals["unproved"].append(f"{where}: {record['reason']}")
                    continue
                proved_here += 1
                totals["widest"] = max(totals["widest"], float(record["radius"]))
                if not all(_digits_inside(d, b) for d, b in zip(inp["phi"], record["phi"])):
                    totals["outside"].append(where)
            totals["cases"] += 1
            totals["cases_proved"] += all_proved
        totals["proved"] += proved_here
        progress(f"[{time.perf_counter() - start:6.1f}s] {name:28} {proved_here:3d} proved "
                 f"({time.perf_counter() - t:.1f}s)")
    totals["seconds"] = round(time.perf_counter() - start, 1)
    return totals


def prove_orbits(ids=None, quick=False, progress=print) -> list[dict]:
    """The claims that rest on periodic orbits, run with their proofs (``row["proved"]``)."""
    ids = list(claims.ORBIT_CLAIMS) if ids is None else list(ids)
    rows = []
    for row in claims.run_claims(quick=quick, ids=ids):
        rows.append(row)
        for proof in row.get("proved", []):
            status = "proved" if proof["proved"] else "NOT proved"
            what = (f"{proof['kind']}, radius {proof['radius']:.1e}, multipliers "
                    f"{proof['multipliers']}" if proof["proved"] else proof["reason"])
            progress(f"{row['id']:22} {proof['orbit']:34} {status}: {what}")
    return rows


def main(argv=None) -> int:
    """``prove [--golden] [--orbits] [--scenes NAME ...] [--json FILE]``; ``--atlas`` and
    ``--intervals`` hand the rest of the line to their own commands."""
    import argparse

    argv = list(sys.argv[1:] if argv is None else argv)
    for flag, module in (("--atlas", "cross_check.atlas.proved"), ("--intervals", "cross_check.paper.claims.intervals")):
        if flag in argv:
            import importlib
            return importlib.import_module(module).main([a for a in argv if a != flag])
    if "--claim" in argv or any(a.startswith("--claim=") for a in argv):
        from cross_check import proofs_dissip
        return proofs_dissip.main(argv)
    ap = argparse.ArgumentParser(prog="python -m cross_check prove", description=__doc__.splitlines()[0],
                                 epilog="Without --golden or --orbits both run (about a minute on 2 cores).  Exit status: 0 done "
                                        "(an unproved input or orbit is reported, not an error), 1 a stored golden "
                                        "record differs from its proof, 2 bad input.")
    ap.add_argument("--golden", action="store_true", help="re-prove every golden input and check the stored balls")
    ap.add_argument("--orbits", action="store_true", help="prove the periodic orbits the paper's claims rest on")
    ap.add_argument("--scenes", nargs="+", metavar="NAME", choices=list(scenes.SCENES),
                    help="--golden: only these built-in scenes")
    ap.add_argument("--golden-dir", metavar="DIR", default=None,
                    help="--golden: the golden data of DIR (written by `golden` or `verify`), not the shipped data")
    scenefile.add_arguments(ap, "--golden: prove the golden data of")
    ap.add_argument("--json", metavar="FILE", type=outputs.check_file, help="write what was proved as JSON")
    ap.add_argument("--out", metavar="DIR", type=outputs.check_folder,
                    help="write what was proved as DIR/proofs.json")
    ap.add_argument("--atlas", action="store_true",
                    help="the proved atlas over (f/F, w^2 R/F) boxes, on Dask (see prove --atlas --help)")
    ap.add_argument("--intervals", action="store_true",
                    help="the branches proved on parameter intervals (see prove --intervals --help)")
    ap.add_argument("--claim", choices=["dissip-invariance"],
                    help="prove or refute a claim per scene (see prove --claim dissip-invariance --help)")
    args = ap.parse_args(argv)
    try:
        user = scenefile.from_args(args)
        names = (args.scenes or []) + user
        have = golden.names_in(args.golden_dir)
    except ValueError as exc:           # a bad scene file (SceneFileError) or golden directory
        print(f"prove: {exc}", file=sys.stderr)
        return 2
    missing = [n for n in names if n not in have]
    if missing:
        print(f"prove: no golden data for {missing} in {golden.files(args.golden_dir)} (--golden-dir)", file=sys.stderr)
        return 2
    run_golden = args.golden or not args.orbits
    run_orbits = args.orbits or not (args.golden or args.golden_dir or user)
    out, status = {}, 0
    if run_golden:
        totals = prove_golden(names or None, progress=lambda m: print(m, flush=True), directory=args.golden_dir)
        print(f"golden: {totals['proved']} of {totals['inputs']} inputs proved, "
              f"{totals['cases_proved']} of {totals['cases']} cases ({100 * totals['cases_proved'] / max(1, totals['cases']):.1f}%), "
              f"widest proved relative radius {totals['widest']:.1e}, {totals['seconds']} s")
        for line in totals["unproved"]:
            print(f"  not proved: {line}")
        for key, words in (("mismatch", "stored record differs from its proof"),
                           ("outside", "a written digit lies outside its ball")):
            for where in totals[key]:
                print(f"  ERROR {words}: {where}", file=sys.stderr)
                status = 1
        out["golden"] = totals
    if run_orbits:
        out["orbits"] = prove_orbits(progress=lambda m: print(m, flush=True))
    for path in filter(None, (args.json, args.out and args.out / "proofs.json")):
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(out, indent=1, default=str))
        print(f"wrote {path}")
    return status
