"""The claims table: every numerically checkable statement of the paper, with a verdict.

``CLAIMS`` is the registry (``base.Claim`` objects, in the table's order), one module per group:

* ``closed_forms``  -- the symmetric solutions and their conditions, no-impact solutions, the
  lift, the equilibria of the position forcing (and fig:xpotno's non-sticking centre, proved);
* ``bifurcations``  -- the fold at f_crit, the 3:1 resonance, the saddle's eigenvalues;
* ``regions``       -- Omega_dissip's invariance, area preservation, Table 1's matrices;
* ``islands``       -- the focus and period-5 orbit, island A, the central island, the no-impact
  attractor, the subharmonic islands.

``run_claims(quick=False)`` returns one dict per claim: ``id``, ``statement`` (the paper's words),
``verdict`` (``reproduced`` | ``not reproduced`` | ``erratum``), ``corrected`` (for errata),
``parameters`` and ``numbers`` (named values), a ``note`` and the ``seconds`` it took.  Closed
forms come from ``reference.paper``; periodic points are searched on ``fast`` and refined on the
reference at 50 digits (``cross_check.dynamics``); thresholds (f_crit, R*) solve an extended
system by Newton on the reference map.
``python -m cross_check claims [--json FILE] [--quick] [--only ID ...]``.
"""
from __future__ import annotations

import json
import time

from cross_check import outputs
from cross_check.paper.claims import bifurcations, closed_forms, islands, regions  # noqa: F401 (registration)
from cross_check.paper.claims.base import REGISTRY, Claim, Outcome

#: the table's order (the paper's: closed forms, bifurcations, regions, effects, islands)
ORDER = ("symmetric-solutions", "existence-condition", "nonstick-condition", "fold-reduced-condition",
         "fold-fcrit", "resonance-3-1", "eigenvalues-fig7", "dissip-invariance", "area-preservation",
         "table1-matrices", "no-impact-solutions", "lift", "xpot-equilibria", "focus-and-period5",
         "island-A", "fig1b-centre", "fig3-attractor", "subharmonic-islands")
if set(ORDER) != set(REGISTRY):
    raise ImportError(f"claims registry and ORDER differ: {sorted(set(ORDER) ^ set(REGISTRY))}")

#: every claim by id, in the table's order
CLAIMS: dict[str, Claim] = {cid: REGISTRY[cid] for cid in ORDER}

#: the claims whose verdict rests on periodic orbits: their rows carry ``proved``, one Krawczyk
#: proof per orbit (``base.prove``; ``python -m cross_check prove --orbits`` runs just these)
ORBIT_CLAIMS = ("symmetric-solutions", "eigenvalues-fig7", "focus-and-period5", "island-A",
                "fig1b-centre", "subharmonic-islands", "fig3-attractor", "xpot-equilibria")

__all__ = ["CLAIMS", "ORBIT_CLAIMS", "Claim", "Outcome", "run_claims", "main"]


def run_claims(quick=False, ids=None, progress=None) -> list[dict]:
    """Compute the claims (all, or those in ``ids``); each row gets ``seconds``.

    ``progress(row)`` is called as each row completes (the CLI prints it at once).
    """
    ids = list(CLAIMS) if ids is None else list(ids)
    unknown = [i for i in ids if i not in CLAIMS]
    if unknown:
        raise ValueError(f"unknown claim id(s) {unknown}; known: {', '.join(CLAIMS)}")
    rows = []
    for cid in ids:
        t = time.perf_counter()
        row = CLAIMS[cid].run(quick)
        row["seconds"] = round(time.perf_counter() - t, 2)
        rows.append(row)
        if progress is not None:
            progress(row)
    return rows


def _short(numbers, width=70):
    text = json.dumps(numbers, default=str)
    return text if len(text) <= width else text[: width - 3] + "..."


def main(argv=None) -> int:
    """``python -m cross_check claims [--quick] [--json FILE] [--out DIR] [--only ID ...]``: print the
    table (and write it as JSON)."""
    import argparse
    ap = argparse.ArgumentParser(prog="python -m cross_check claims", description=__doc__.splitlines()[0],
                                 epilog="Exit status: 0 the table was made (a refuted claim is a verdict in it, "
                                        "not an error), 2 bad arguments or an unwritable output.")
    ap.add_argument("--quick", action="store_true", help="small grids (the test-suite settings)")
    ap.add_argument("--json", metavar="FILE", type=outputs.check_file, help="write the full table as JSON")
    ap.add_argument("--out", metavar="DIR", type=outputs.check_folder, help="write the full table as DIR/claims.json")
    ap.add_argument("--only", nargs="+", metavar="ID", choices=list(CLAIMS), help=f"claim ids: {', '.join(CLAIMS)}")
    args = ap.parse_args(argv)
    print(f"{'id':24} {'verdict':15} {'s':>6}  numbers", flush=True)

    def show(row):
        print(f"{row['id']:24} {row['verdict']:15} {row['seconds']:6.1f}  {_short(row['numbers'])}", flush=True)
        if row["corrected"]:
            print(f"{'':24} corrected: {row['corrected']}", flush=True)

    rows = run_claims(quick=args.quick, ids=args.only, progress=show)
    for path in filter(None, (args.json, args.out and args.out / "claims.json")):
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(rows, indent=1, default=str))
        print(f"wrote {path}")
    return 0
