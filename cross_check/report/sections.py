"""The report's sections: agreement per scene, the hard cases, solve_ivp's itineraries, the
claims table, the machine.  Each section is a function returning markdown lines (and its data)."""
from __future__ import annotations

import math
import os
import platform
import time

import mpmath
import numpy as np

from cross_check import golden, scenes
from cross_check.agreement import baseline, compare
from cross_check.agreement.compare import Summary
from cross_check.score import adapters
from cross_check.tolerances import tol

REF_DPS = 50
TRUTH_DPS = 120


# --- 1. per-scene agreement -----------------------------------------------------------
def _batch(cases):
    return np.array([c.float()[0] for c in cases]), np.array([c.float()[1] for c in cases])


def golden_reference(doc) -> dict:
    """``{(case, input label): (phi, events, band)}`` from a golden document (mpf at 50 digits,
    events as ``compare.Event``): the reference's answers at dps 90, checked at dps 110 and
    proved.  ``verify`` hands them to ``scene_agreement`` and ``hard_case_rows`` instead of
    running the reference again at ``REF_DPS`` (issue 33: under position forcing those runs
    were ~15 of a scene's CPU seconds)."""
    out = {}
    with mpmath.workdps(REF_DPS):
        for case in doc["cases"]:
            for label, inp in case["inputs"].items():
                evs = [compare.Event(k, mpmath.mpf(t), mpmath.mpf(x), mpmath.mpf(v),
                                     None if vb is None else mpmath.mpf(vb)) for k, t, x, v, vb in inp["events"]]
                out[(case["name"], label)] = (tuple(mpmath.mpf(z) for z in inp["phi"]), evs, inp.get("band"))
    return out


def scene_agreement(name: str, n_sample: int, n_ten: int, reference=None) -> dict:
    """Fast vs reference on the sample states of one scene (see ``compare``); ``reference``
    (``golden_reference``) gives the reference's one-period answers where it has them."""
    reference = reference or {}
    sc = scenes.scene(name)
    cases = scenes.sample_states(name, n_sample)
    X, V = _batch(cases)
    phis, fail = compare.fast_safe(compare.fast_map, sc, X, V)
    f_evs, fail_e = compare.fast_safe(compare.fast_events, sc, X, V)
    band = compare.band_mask(sc, X, V)
    rows, raw = [], []
    for i, c in enumerate(cases):
        r_phi, r_evs, _ = reference.get((c.name, "exact")) or (
            compare.ref_map(sc, c, 1, REF_DPS), compare.ref_events(sc, c, None, REF_DPS), None)
        ca = compare.compare_case(c.name, r_evs, f_evs[i], r_phi, phis[i], scene=sc)
        ca.in_band = bool(band[i])
        rows.append(ca)
        if phis[i] is not None:
            raw.append(min(compare.digits(phis[i][0], r_phi[0]), compare.digits(phis[i][1], r_phi[1])))
    out = compare.summarize(rows)
    out["failures"] = {cases[i].name: msg for i, msg in {**fail_e, **fail}.items()}
    ten = []
    for c in cases[:n_ten]:
        got, _ = compare.fast_safe(compare.fast_map, sc, *map(np.array, zip(c.float())), periods=10)
        if got[0] is not None:
            ref10 = compare.ref_map(sc, c, 10, REF_DPS)
            ten.append(min(compare.digits(got[0][0], ref10[0]), compare.digits(got[0][1], ref10[1])))
    out["map10"] = Summary.of(ten)
    out["map_raw"] = Summary.of(raw)
    return out


def agreement_table(results: dict) -> list[str]:
    lines = ["| scene | states | same itinerary | band | event t (med/worst) | event state | "
             "Phi digits | Phi^10 digits | mismatches outside band | fast failed |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for name, s in results.items():
        if s is None:
            lines.append(f"| `{name}` | FAILED (see Failures) |" + " |" * 8)
            continue
        share = f"{100 * s['itinerary_share']:.0f}%"
        lines.append(f"| `{name}` | {s['n']} | {share} | {len(s['band'])} | "
                     f"{s['event_time']} | {s['event_state']} | {s['map_raw']} | {s['map10']} | "
                     f"{', '.join(s['mismatch_outside_band']) or '-'} | {len(s['failures']) or '-'} |")
    failures = [f"- `{name}` / {case}: {msg}" for name, s in results.items() if s is not None
                for case, msg in s["failures"].items()]
    if failures:
        lines += ["", "fast raised on these states:", ""] + failures
    return lines


# --- 2. hard cases --------------------------------------------------------------------
def _scipy_on(sc, x, v, ref_kinds, r_phi):
    try:
        b = baseline.stroboscopic(sc, x, v, 1, "DOP853", 1e-10)    # one run gives both map and events
        same = "yes" if tuple(e.kind for e in compare.canonical(b.events, sc)) == ref_kinds else "**no**"
        return same, min(compare.digits(b.x, r_phi[0]), compare.digits(b.v, r_phi[1]))
    except RuntimeError as exc:
        return f"failed: {exc}"[:40], math.nan


def hard_case_rows(name: str, reference=None, cases=None) -> list[dict]:
    """Both integrators (and scipy) on the hard cases of a scene (``cases``, default
    ``scenes.hard_states``); ``reference`` (``golden_reference``) gives the reference's answers
    where it has them."""
    reference = reference or {}
    sc = scenes.scene(name)
    cases = scenes.hard_states(name) if cases is None else cases
    X, V = _batch(cases)
    phis, _ = compare.fast_safe(compare.fast_map, sc, X, V)
    f_evs, _ = compare.fast_safe(compare.fast_events, sc, X, V)
    band = compare.band_mask(sc, X, V)
    rows = []
    for i, c in enumerate(cases):
        fc = c.rounded()
        known = (c.name, "exact") in reference and (c.name, "float64") in reference
        r_exact = reference[(c.name, "exact")][1] if known else compare.ref_events(sc, c, None, REF_DPS)
        r_phi, r_float, r_band = reference[(c.name, "float64")] if known else (
            compare.ref_map(sc, fc, 1, REF_DPS), compare.ref_events(sc, fc, None, REF_DPS), None)
        ca = compare.compare_case(c.name, r_float, f_evs[i], r_phi, phis[i], scene=sc)
        scipy_same, scipy_digits = _scipy_on(sc, X[i], V[i], ca.ref_kinds, r_phi)
        text = compare.itinerary_text
        rows.append({"scene": name, "case": c.name, "built": c.kind, "ref_exact": text(r_exact, sc),
                     "ref_float": text(r_float, sc), "fast": text(f_evs[i], sc), "same": ca.same_itinerary,
                     "digits": min(ca.map_digits), "stable": not band[i], "scipy_same": scipy_same,
                     "scipy_digits": scipy_digits,
                     "ref_band": compare.reference_in_band(sc, fc) if r_band is None else r_band})
    return rows


def hard_table(rows) -> list[str]:
    lines = ["| scene | case | built around | reference (exact state) | reference (float64 state) | fast | "
             "fast = ref? | fast Phi digits | exact itinerary stable (+-ulps)? | fast stable? | "
             "scipy DOP853 1e-10 same? (digits) |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| `{r['scene']}` | {r['case']} | {r['built']} | {r['ref_exact']} | {r['ref_float']} | "
                     f"{r['fast']} | {'yes' if r['same'] else '**no**'} | {r['digits']:.1f} | "
                     f"{'**no** (band)' if r['ref_band'] else 'yes'} | {'yes' if r['stable'] else '**no**'} | "
                     f"{r['scipy_same']} ({r['scipy_digits']:.1f}) |")
    return lines


# --- 4. solve_ivp's itineraries ---------------------------------------------------------
def itinerary_misses(names, n_sample: int, progress=None) -> dict:
    """One-period itineraries of solve_ivp against the reference (dps 50), canonical form.

    For RK45 and DOP853 at rtol 1e-6 and 1e-10 (scoring-protocol adapters,
    ``cross_check.score.adapters``), on the sample states and the float64 roundings of the hard
    cases of the scenes ``names``: ``{(method, rtol): [(where, reference kinds, baseline kinds or
    None if it raised)]}``.
    """
    runs = {(m, r): [] for m in baseline.METHODS for r in (1e-6, 1e-10)}
    peers = {key: adapters.BaselineAdapter(f"{key[0]} rtol {key[1]:.0e}", *key) for key in runs}
    for name in names:
        sc = scenes.scene(name)
        params = sc.floats()
        for c in scenes.sample_states(name, n_sample) + [h.rounded() for h in scenes.hard_states(name)]:
            ref = [e.kind for e in compare.canonical(compare.ref_events(sc, c, None, 50), sc)]
            x, v = (np.array([a]) for a in c.float())
            for key, peer in peers.items():
                try:
                    got = [e.kind for e in adapters.canonical_log(peer.events(params, x, v)[0], sc)]
                except RuntimeError:
                    got = None
                runs[key].append((f"{name}/{c.name}", ref, got))
        if progress:
            progress(f"scipy itineraries: {name}")
    return runs


def scipy_itineraries(hard_scenes, n_sample, progress) -> list[str]:
    """Where solve_ivp misses or invents events (``itinerary_misses``), as a table."""
    runs = itinerary_misses(hard_scenes, n_sample, progress)
    lines = ["| solver | states | same itinerary | fewer impacts (missed) | more impacts | other difference | "
             "failed | examples of misses |", "|---|---|---|---|---|---|---|---|"]
    for (method, rtol), rows in runs.items():
        same = sum(1 for _, a, b in rows if a == b)
        failed = [w for w, _, b in rows if b is None]
        fewer = [w for w, a, b in rows if b is not None and b.count("impact") < a.count("impact")]
        more = [w for w, a, b in rows if b is not None and b.count("impact") > a.count("impact")]
        other = len(rows) - same - len(failed) - len(fewer) - len(more)
        lines.append(f"| {method} rtol {rtol:.0e} | {len(rows)} | {same} | {len(fewer)} | {len(more)} | {other} | "
                     f"{len(failed)} | {', '.join(fewer[:3]) or '-'} |")
    return lines


# --- 5. claims, 6. machine --------------------------------------------------------------
def claims_section(quick: bool, progress, claims=None, first=()) -> list[str]:
    """The claims table, one registered claim at a time (``claims``: id -> object with ``run(quick)``;
    default the registry ``cross_check.paper.claims.CLAIMS``).  A failing claim is reported in its row.
    ``first``: ids computed before the others (the table keeps the registry's order)."""
    if claims is None:
        from cross_check.paper.claims import CLAIMS as claims
    done = {}
    for cid in sorted(claims, key=lambda c: c not in first):
        t0 = time.perf_counter()
        try:
            done[cid] = claims[cid].run(quick)
        except Exception as exc:  # noqa: BLE001 -- one claim's failure is reported, not fatal
            done[cid] = {"id": cid, "verdict": "FAILED", "statement": f"{type(exc).__name__}: {str(exc)[:200]}",
                         "corrected": None, "note": ""}
        done[cid]["seconds"] = round(time.perf_counter() - t0, 2)
        progress(f"claim {cid}: {done[cid]['verdict']}")
    rows = [done[cid] for cid in claims]
    keys = ("id", "verdict", "statement", "corrected", "note", "seconds")

    def cell(d, k):
        return " ".join(str("" if d.get(k) is None else d[k]).split())[:160].replace("|", "/")

    out = ["| " + " | ".join(keys) + " |", "|" + "---|" * len(keys)]
    out += ["| " + " | ".join(cell(d, k) for k in keys) + " |" for d in rows]
    return out + proofs_table(rows) + intervals_table(rows)


def intervals_table(rows) -> list[str]:
    """The statements proved for every parameter of an interval (rows' ``proved_on``, read from
    the shipped ``cross_check/data/proved_intervals.json``)."""
    lines = [(d["id"], p) for d in rows for p in d.get("proved_on", [])]
    if not lines:
        return []
    out = ["", "Proved on an interval (rigorous continuation: a chain of parameter boxes, each orbit "
           "proved for every parameter of its box; `python -m cross_check prove --intervals` writes "
           "`cross_check/data/proved_intervals.json`, which the tests re-prove in part):", "",
           "| claim | proved on an interval | boxes |", "|---|---|---|"]
    for cid, p in lines:
        out.append(f"| {cid} | {p['statement'].replace('|', '/')} | {p.get('boxes', '-')} |")
    return out


def _multipliers_text(mults) -> str:
    def one(m):
        if isinstance(m, dict):
            return f"{m['re'][0][:10]} +- {m['im'][0][:10]} i (+-{max(m['re'][1], m['im'][1]):.0e})"
        return f"{m[0][:10]} (+-{m[1]:.0e})"
    return "; ".join(one(m) for m in mults)


def proofs_table(rows) -> list[str]:
    """The Krawczyk proofs of the orbits the claims rest on (rows' ``proved``)."""
    proofs = [(d["id"], p) for d in rows for p in d.get("proved", [])]
    if not proofs:
        return []
    out = ["", "Orbits the verdicts rest on, proved (`reference.enclosure.prove_periodic`: a unique "
           "fixed point of Phi^k in a box of the given radius, multipliers enclosed; "
           "`python -m cross_check prove --orbits`):", "",
           "| claim | orbit | k | proved | type | box radius | multipliers (enclosed) |", "|---|---|---|---|---|---|---|"]
    for cid, p in proofs:
        if p["proved"]:
            out.append(f"| {cid} | {p['orbit']} | {p['periods']} | yes | {p['kind']} | {p['radius']:.1e} | "
                       f"{_multipliers_text(p['multipliers'])} |")
        else:
            out.append(f"| {cid} | {p['orbit']} | {p['periods']} | no | {p['reason'][:120]} | | |")
    return out


def golden_proofs_section() -> list[str]:
    """What the golden data's stored proofs say (``enclosure`` of each input; no re-proving:
    ``python -m cross_check prove --golden`` re-proves and checks them)."""
    rows, reasons, widest = [], {}, 0.0
    for name in scenes.SCENES:
        inputs = [i for c in golden.load(name)["cases"] for i in c["inputs"].values()]
        proved = [i["enclosure"] for i in inputs if i["enclosure"]["proved"]]
        for i in inputs:
            if not i["enclosure"]["proved"]:
                reasons[i["enclosure"]["reason"][:100]] = reasons.get(i["enclosure"]["reason"][:100], 0) + 1
        worst = max((float(e["radius"]) for e in proved), default=0.0)
        widest = max(widest, worst)
        rows.append(f"| {name} | {len(proved)} / {len(inputs)} | {worst:.1e} | "
                    f"{max((e['prec'] for e in proved), default=0)} |")
    out = ["Each golden input carries a proof (`reference.enclosure`: the itinerary re-proved in Arb "
           "balls, Krawczyk steps for the event times, exclusion of every other event); the balls of "
           "Phi and Phi' are theorems for the exact input.", "",
           "| scene | proved inputs | widest proved relative radius of Phi | bits |", "|---|---|---|---|"]
    out += rows + ["", f"Widest proved relative radius overall: {widest:.1e} (acceptance: 1e-40)."]
    out += [f"- not proved ({n}): {why}" for why, n in reasons.items()]
    return out


def machine_section(n_sample: int, quick: bool) -> list[str]:
    import matplotlib
    import scipy

    return [f"- machine: {platform.machine()}, {os.cpu_count()} cores, {platform.platform()}",
            f"- python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}, "
            f"mpmath {mpmath.__version__} (backend {mpmath.libmp.BACKEND}), matplotlib {matplotlib.__version__}",
            f"- mode: {'quick' if quick else 'full'}; sample seed {scenes.SEED} (+crc32 of the scene name); "
            f"{n_sample} sample states per scene, reference at dps {REF_DPS}, truth at dps {TRUTH_DPS}",
            f"- near-grazing band: itinerary change under {tol('compare_band_ulps').rtol:g} ulps "
            f"(`compare_band_ulps`)"]


def atlas_section(atlas_dir, report_dir) -> list[str]:
    """The atlas's boundary table and maps, read from ``atlas_dir/atlas.zarr`` through xarray
    (the maps drawn from the store into the report when the atlas's own PNGs are missing), or
    how to make one."""
    import pathlib

    make = ("`python -m pip install -e '.[atlas]' && python -m cross_check atlas`; the report then "
            "shows its maps here.")
    if not (pathlib.Path(atlas_dir) / "atlas.zarr").exists():
        return ([f"No atlas in `{atlas_dir}/` yet.  Make one (64 x 64, about 40 CPU seconds): " + make]
                + proved_atlas_lines(atlas_dir, report_dir))
    try:
        from cross_check.atlas import maps, open_atlas
        ds = open_atlas(atlas_dir).load()
    except (ImportError, ValueError) as exc:
        return ([f"The atlas in `{atlas_dir}/` cannot be shown: {exc}.  " + make]
                + proved_atlas_lines(atlas_dir, report_dir))
    nf, nr = ds.sizes["f_over_F"] - 1, ds.sizes["w2R_over_F"]
    lines = [f"{nf} x {nr} grid of (f/F, w^2 R/F) (+ the f = 0 column), {ds.attrs['scene']}; claims: "
             f"{', '.join(ds.attrs['claims'])}; store `{atlas_dir}/atlas.zarr` "
             f"(`cross_check.atlas.open_atlas`).  Computed switch against each closed form, in grid cells:", "",
             "| closed-form boundary | worst distance (cells) | lines compared |", "|---|---|---|"]
    for name, (worst, n) in maps.boundaries(ds).items():
        lines.append(f"| {name} | {'-' if worst is None else f'{worst:.2f}'} | {n} |")
    lines.append("")
    pngs = [pathlib.Path(atlas_dir) / f"atlas_{claim}.png" for claim in ds.attrs["claims"]]
    if not all(p.exists() for p in pngs):
        pathlib.Path(report_dir).mkdir(parents=True, exist_ok=True)
        pngs = [pathlib.Path(p) for p in maps.draw(ds, str(report_dir))]
    for claim, png in zip(ds.attrs["claims"], pngs):
        lines += [f"![atlas {claim}]({os.path.relpath(png, report_dir)})", ""]
    return lines + proved_atlas_lines(atlas_dir, report_dir)


def proved_atlas_lines(atlas_dir, report_dir) -> list[str]:
    """The proved atlas (``python -m cross_check prove --atlas``) when ``proved_atlas_meta.json``
    exists: per claim the boxes proved for every parameter, against the numerical region."""
    import json
    import pathlib

    path = pathlib.Path(atlas_dir) / "proved_atlas_meta.json"
    if not path.exists():
        return []
    meta = json.loads(path.read_text())
    prov = meta["provenance"]
    out = ["", f"Proved over boxes (`python -m cross_check prove --atlas`, {prov['grid']} x {prov['grid']} "
           f"boxes, {prov['stats']['seconds']} s on {prov['stats']['workers']} workers): each claim proved "
           "for every parameter of a box (`reference.enclosure`, parameters as balls).", "",
           "| claim | boxes proved | inside the numerical region | proved inside | off the tr = -2 curve |",
           "|---|---|---|---|---|"]
    for claim, s in meta["summary"].items():
        frac = "-" if s["fraction_inside"] is None else f"{100 * s['fraction_inside']:.1f}%"
        off = "-" if s["fraction_off_tr_minus_2"] is None else f"{100 * s['fraction_off_tr_minus_2']:.1f}%"
        out.append(f"| {claim} | {s['proved']} | {s['inside']} | {s['proved_inside']} ({frac}) | {off} |")
    out.append("")
    for claim in meta["summary"]:
        png = pathlib.Path(atlas_dir) / f"proved_atlas_{claim}.png"
        if png.exists():
            out += [f"![proved {claim}]({os.path.relpath(png, report_dir)})", ""]
    return out
