"""Golden data: the reference's answers on the paper's scenes, at 40 significant digits.

``python -m cross_check golden [--out DIR] [--scenes NAME ...] [--scenes-file FILE] [--scene "..."]``
writes one JSON file per scene (default ``cross_check/data/golden/``, shipped as package data:
``files()`` reads it with ``importlib.resources``, so a ``pip install`` of the suite has it too;
user scenes, from ``cross_check.scenefile``, go to ``golden/`` unless ``--out`` says otherwise).
A golden directory is self-describing: each file records its scene's exact parameters, so
``names_in``, ``load`` and ``scene_of`` read any directory (``--golden-dir`` of ``score``,
``prove`` and the pytest plugin; ``verify`` writes one) the way they read the shipped one.  Each file holds, for every state of interest
(``cross_check.scenes.states_of_interest``: a seeded sample and the constructed hard cases):

* the state (strings; ``exact`` says whether they denote float64 numbers or decimals);
* for each *input* -- ``exact`` (the state itself) and, for decimal hard cases, ``float64``
  (the state rounded to float64, what a float integrator actually sees) -- the map
  ``Phi(x, v)``, the Jacobian ``Phi'`` (or ``null`` with the reason, e.g. at grazing where it
  is undefined; written with ``DIGITS - ceil(log10 kappa)`` digits, ``kappa`` the grazing
  conditioning ``(F/w)/min|v-|``) and the event log over ``[0, T]`` in ``compare.canonical``
  form (kind, t, x, v after, v before); for float64 inputs, ``band``: whether
  the reference's itinerary flips under a ``compare_band_ulps`` move (``compare.reference_in_band``);

* ``enclosure``: the proof (``cross_check.golden_proof``): ``proved`` and balls that provably
  contain ``Phi`` and ``Phi'``, or ``reason``, why no proof holds;

every number from ``reference`` at ``GOLDEN_DPS`` digits, written with ``DIGITS`` significant
digits, after checking that a run at ``GOLDEN_DPS + 20`` digits agrees to those digits
(tolerance ``golden_self_agreement``) and has the same itinerary.  Under position forcing an
input's numbers come from a run at ``PROVED_DPS`` digits instead when its proof (which every
input gets anyway, here with ``Phi'`` to the working precision) puts each written number within
``golden_proved_agreement`` of the truth (``proved_values``; its record says ``"dps": 50``): a
proof in place of the agreement, at a third of the cost (issue 33).  A float64 input's numbers
come from its proof's balls themselves, the proof guided by a ``GUIDE_DPS``-digit run (its record
says ``"guide_dps": 20``; ``first_proof``).  If any check fails, nothing
is written (``GoldenError``).  Provenance (mpmath version and backend, dps, the scene's exact
parameters, how each state was made) is recorded; the date is not, so that regenerating gives
byte-identical files (keys in a fixed order, a list of scalars per line: ``dumps``).
Why dps 90: the chatter accumulation time carries only ~dps/2 + 4 digits (see the tolerance).

The runs and their self-check (``compute``, ``disagreement``, ``record``) are ``golden_runs``'; the
files on disk (``dumps``, ``files``, ``load``, ``names_in``, ``scene_of``) ``golden_files``'; both
are read here, as the suite always has.
"""
from __future__ import annotations

import pathlib
import sys

import mpmath

from cross_check.agreement import compare
from cross_check import golden_chatter, golden_proof, outputs, scenefile, scenes
from cross_check.golden_files import dumps, files, load, names_in, scene_of
from cross_check.golden_runs import (CHECK_DPS, DIGITS, GOLDEN_DPS, _values, compute, disagreement, fmt, jacobian_digits,
                                     kappa, record)
from cross_check.progress import Progress
from cross_check.tolerances import tol
from reference.enclosure.balls import from_mpf

#: the names of the runs (``golden_runs``) and of the files (``golden_files``) that the suite reads
#: here, with this module's own
__all__ = ["CHECK_DPS", "DIGITS", "GOLDEN_DPS", "compute", "disagreement", "fmt", "jacobian_digits", "kappa", "record",
           "dumps", "files", "load", "names_in", "scene_of", "N_SAMPLE", "FORMAT", "DEFAULT_DIR", "GoldenError",
           "scene_record", "PROVED_DPS", "GUIDE_DPS", "outside_proof", "first_proof", "values_of", "from_balls",
           "proved_values", "proved_jacobian", "input_proof", "case_entry", "document", "scene_file", "generate",
           "main"]

N_SAMPLE = 8
FORMAT = 2
DEFAULT_DIR = pathlib.Path(__file__).resolve().parent / "data" / "golden"   # where `golden` writes in a checkout


class GoldenError(RuntimeError):
    """Self-agreement failed: the golden data would not be trustworthy."""


def scene_record(sc) -> dict:
    """The scene's exact parameters as given (strings), plus its name and effects."""
    rec = {"name": sc.name}
    for k in ("F", "f", "omega", "l", "r", "restitution", "damping", "wavenumber"):
        value = getattr(sc, k)
        rec[k] = None if value is None else str(value)
    rec["effects"] = sorted(sc.effects)
    return rec


#: digits of a position-forced input's point run whose values its proof certifies
#: (``proved_values``) in place of the dps 90 / 110 pair
PROVED_DPS = 50
#: digits of the point run that guides a float64 input's first proof, whose values then come
#: from that proof's balls (``first_proof``, ``from_balls``).  Issue 33, the 20 inputs of the
#: drawn scene ``F=2.74 f=0.54 omega=1.06 l=-0.54 r=0.91 wavenumber=1.22`` (one run): the runs
#: took 4.1 CPU s at 20 digits and 9.0 at 50; every proof guided by a 20-digit run held with
#: the radius of the one guided at 50 but two, the decimal hard cases that sit on an event (a
#: turn at the wall, an impact at ``T``), which 20 digits do not resolve -- decimal inputs keep
#: ``PROVED_DPS`` -- and the 40-digit strings of ``Phi`` and of every event but the chatter
#: times (which restart pairs give, ``golden_chatter``) were the dps-50 run's
GUIDE_DPS = 20


def outside_proof(res: dict, enc, sc, restarted=()) -> str | None:
    """Why the point run ``res`` is not certified by the proof ``enc`` of the same input, or
    ``None``: ``enc`` proved within ``golden_enclosure_floor``, the same canonical itinerary, the
    Jacobian defined in both, and every value ``a`` that ``record`` writes (``Phi``, the events'
    ``t, x, v, v-``, ``Phi'``) with its whole ball within ``golden_proved_agreement`` of it:
    ``|b - a| <= rtol max(1, |a|)`` for every ``b`` of the ball (times ``kappa`` for ``Phi'``, as
    the self-check) -- the true value, which the ball holds, is then that close to ``a``: what the
    dps-110 run establishes by agreement, here by proof.  ``restarted``: the canonical indices of
    chatter events whose time a restart pair checks instead (``golden_chatter``)."""
    floor = tol("golden_enclosure_floor").rtol
    if not enc.proved:
        return f"not proved: {enc.reason}"
    if enc.rel_radius() > floor:
        return f"proved Phi {enc.rel_radius():.1e} wide, above golden_enclosure_floor {floor:g}"
    a = {**res, "events": compare.canonical(res["events"], sc)}
    b = {"phi": enc.phi, "jacobian": enc.jacobian, "events": _proved_events(enc, sc)}
    if [e.kind for e in a["events"]] != [e.kind for e in b["events"]]:
        return f"itineraries differ: {[e.kind for e in a['events']]} vs proved {[e.kind for e in b['events']]}"
    for i in restarted:                 # checked by the restart pair, within the proof's ball
        b["events"][i] = b["events"][i]._replace(t=from_mpf(a["events"][i].t))
    if (a["jacobian"] is None) != (b["jacobian"] is None):
        return "Jacobian defined in one of the point run and the proof only"
    rtol, k = tol("golden_proved_agreement").rtol, kappa(sc, res)
    for jac, scale in ((False, 1.0), (True, k)):
        values, balls = _values(a, jac), _values(b, jac)
        if len(values) != len(balls):
            return "the proof's events carry other values than the point run's"
        why = _unpinned(values, balls, rtol * scale)
        if why is not None:
            return why
    return None


def _proved_events(enc, sc) -> list:
    """The events of the proof ``enc`` as ``compare.Event`` balls, in canonical form."""
    return compare.canonical_of(enc.events, sc)


def _unpinned(values, balls, rtol) -> str | None:
    """Why some ``value`` is not within ``rtol`` of all of its ball (``golden_proof.ball_within``)."""
    for value, ball in zip(values, balls):
        if not golden_proof.ball_within(value, ball, rtol):
            return f"value {mpmath.nstr(value, 45)} not within {rtol:g} of all of its proved ball {ball}"
    return None


def first_proof(sc, case):
    """``(run, enc)``: a position-forced input's point run (no Jacobian) and its proof guided by
    that run's point log (``golden_proof.position_proof``); ``None`` without position forcing.
    A float64 input's run is at ``GUIDE_DPS`` digits, and its values come from the proof
    (``proved_values``); where that proof does not hold, or the input is a decimal, the run is at
    ``PROVED_DPS`` and gives the values.  ``run["dps"]`` says which."""
    if not sc.has("position_forcing"):
        return None
    if case.exact == "float64":
        run = compute(sc, case, GUIDE_DPS, jacobian=False)
        enc = golden_proof.position_proof(sc, case, run["points"])
        if enc.proved:
            return run, enc
    run = compute(sc, case, PROVED_DPS, jacobian=False)
    return run, golden_proof.position_proof(sc, case, run["points"])


def values_of(sc, run, enc) -> dict:
    """The values ``proved_values`` holds to the proof ``enc`` of the run ``run``
    (``first_proof``'s): the proof's balls (``from_balls``) for a ``GUIDE_DPS`` run, else the
    run's own with ``Phi'`` from the proof's balls."""
    if run["dps"] == GUIDE_DPS:
        return from_balls(sc, run, enc)
    return {**run, "jacobian": golden_proof.midpoints(enc.jacobian), "jacobian_note": None}


def from_balls(sc, run, enc) -> dict:
    """The run ``run`` with ``Phi``, its events (canonical) and ``Phi'`` read from the proof
    ``enc``'s balls: their midpoints, exact (``golden_proof.midpoint``).  ``outside_proof`` then
    asks of each ball what it asks of a dps-50 value: that the whole ball lie within
    ``golden_proved_agreement`` of it, so the written value is that close to the truth."""
    mid = golden_proof.midpoint
    events = [e._replace(t=mid(e.t), x=mid(e.x), v=mid(e.v), v_before=None if e.v_before is None else mid(e.v_before))
              for e in _proved_events(enc, sc)]
    return {**run, "phi": [mid(b) for b in enc.phi], "events": events,
            "jacobian": golden_proof.midpoints(enc.jacobian), "jacobian_note": None}


def proved_values(sc, case, first=None):
    """``(res, enc)``: a position-forced input's values from one ``PROVED_DPS`` run and its
    Jacobian from its proof's balls (their midpoints: ``Phi'`` to ~1e-47, ``full_derivative``), or,
    for a float64 input, every value from those balls (``values_of``: its run, at ``GUIDE_DPS``,
    only guided the proof), every one certified by that proof (``outside_proof``) -- the
    accumulation times of chatter runs,
    which the proof pins only to ~1e-11, by restart pairs instead (``golden_chatter``:
    ``"restarted"`` in the result) -- or ``None`` where that does not hold
    -- then the dps 90 / 110 pair decides (``_self_checked``), as for every other effect.

    Issue 33, measured on an unseen scene (``F=3 f=0.5 omega=0.8 l=-2 r=1.5 wavenumber=2.5``, 24
    inputs, one run each): the dps 90 and 110 runs took 34 and 48 of the golden task's 104 CPU s
    (the variational columns and the mpf conversions of the Taylor steps, ``reference.taylor``),
    the half-order proof 13, the band 9; now the dps-50 runs take 8.6 (fixed-point steps), the
    full-derivative proofs 12.6 (guided by those runs' point logs), the band 5.8 and the one
    input the proof does not certify (a grazing start: Phi 2e-40 wide) 3.4: 30 CPU s in all.
    The run's own Jacobian (Table 1's product of the flights' variational columns) was 46% of
    its cost (2.6 of 5.6 CPU s on D's first 8 inputs); the proof computes ``Phi'`` anyway, to
    1e-47, so the run no longer does: D's golden task 30.5 -> 24.7 CPU s in a full verify, every
    written string the same (one run each)."""
    first = first_proof(sc, case) if first is None else first
    if first is None:
        return None
    res, enc = first
    if not enc.proved or enc.jacobian is None:
        return None
    res = values_of(sc, res, enc)
    if outside_proof(res, enc, sc) is None:
        return res, enc
    pairs = golden_chatter.restarts(sc, enc)
    if not pairs or outside_proof(res, enc, sc, [i for i, _ in pairs]) is not None:
        return None                     # something besides the accumulation times is unpinned
    got = golden_chatter.chatter_times(sc, res, enc, pairs)
    if got is None or outside_proof(got[0], enc, sc, got[1]) is not None:
        return None
    return {**got[0], "restarted": True}, enc


#: ``jacobian_note`` of a dps 90 / 110 input whose ``Phi'`` comes from its proof (``_self_checked``)
PROVED_JACOBIAN = ("from the midpoints of its enclosure's balls, each within golden_proved_agreement x "
                   "kappa of the true Phi' (the dps 90 / 110 runs check the other values)")


def _pins_jacobian(enc) -> bool:
    """``enc`` is a proof within ``golden_enclosure_floor`` with a Jacobian."""
    return (enc is not None and enc.proved and enc.jacobian is not None
            and enc.rel_radius() <= tol("golden_enclosure_floor").rtol)


def proved_jacobian(sc, res, enc):
    """``Phi'`` of an input from its proof ``enc`` (the balls' midpoints), where that proof holds
    within ``golden_enclosure_floor``, has the run ``res``'s itinerary and pins every entry within
    ``golden_proved_agreement`` times ``kappa`` (the test of ``outside_proof``); else ``None``."""
    if not _pins_jacobian(enc):
        return None
    if [e.kind for e in compare.canonical(res["events"], sc)] != [e.kind for e in _proved_events(enc, sc)]:
        return None
    jac, rtol = golden_proof.midpoints(enc.jacobian), tol("golden_proved_agreement").rtol * kappa(sc, res)
    flat = lambda m: [m[i][j] for i in range(2) for j in range(2)]       # noqa: E731
    return jac if _unpinned(flat(jac), flat(enc.jacobian), rtol) is None else None


def _self_checked(sc, case, where, enc=None) -> dict:
    """The dps-90 run of ``case`` once a dps-110 run agrees with it (else ``GoldenError``).

    ``enc``: the input's proof, if one was made (``first_proof``).  Where it holds within the
    floor, the two runs skip the Jacobian (Table 1's product, 46% of a position-forced run) and
    ``Phi'`` comes from the proof (``proved_jacobian``; ``jacobian_note`` says so), else they
    compute it.  Issue 33: a chatter input, whose proof pins ``Phi`` to ~1e-54 but the
    accumulation time only to ~1e-11, took this route on every position-forced scene; now only
    where its restart pairs do not hold (``golden_chatter``)."""
    from_proof = _pins_jacobian(enc)
    res, check = (compute(sc, case, dps, jacobian=not from_proof) for dps in (GOLDEN_DPS, CHECK_DPS))
    why = disagreement(res, check, sc)
    if why is not None:
        raise GoldenError(f"{where}: dps {GOLDEN_DPS} vs {CHECK_DPS}: {why}")
    if from_proof:
        jac = proved_jacobian(sc, res, enc)
        if jac is None:                      # the proof does not pin it: the runs compute it
            return _self_checked(sc, case, where)
        res["jacobian"], res["jacobian_note"] = jac, PROVED_JACOBIAN
    return res


def input_proof(sc, case) -> dict:
    """The proof record of an input as ``case_entry`` made it (``prove --golden`` makes it again):
    under position forcing the first proof guided by a point run's log (``GUIDE_DPS`` or
    ``PROVED_DPS`` digits: ``first_proof``), kept where it holds within the floor, whichever route the values took
    (issue 33: a dps 90 / 110 input's proof was made again unguided, 1.1 of a chatter input's
    6.6 CPU s on an unseen scene); otherwise ``golden_proof.enclosure`` alone."""
    first = first_proof(sc, case)
    return golden_proof.enclosure(sc, case, first and first[1])


def _route(res) -> dict:
    """The record's word on where a proved input's values come from: ``{"dps": 50}`` (that run)
    or ``{"guide_dps": 20}`` (the proof's balls, the proof guided by a 20-digit run)."""
    return {"guide_dps": GUIDE_DPS} if res["dps"] == GUIDE_DPS else {"dps": PROVED_DPS}


def case_entry(sc, case) -> dict:
    """The golden record of one state of interest (every input of it), after the self-check
    (``GoldenError`` names the scene, the case and the input whose two runs disagree).  Under
    position forcing an input's values may come from ``proved_values`` instead (``_route``: its
    record says ``"dps": 50`` or ``"guide_dps": 20``; the proof checks every written value)."""
    inputs = {"exact": case}
    if case.exact == "decimal":
        inputs["float64"] = case.rounded()
    entry = {"name": case.name, "exact": case.exact, "x": case.x, "v": case.v, "how": case.how,
             "constructed_kind": case.kind or None, "t_event": case.t_event or None, "inputs": {}}
    for label, inp in inputs.items():
        first = first_proof(sc, inp)
        proved = proved_values(sc, inp, first)
        if proved is not None:
            res, enc = proved
            head = {"x": inp.x, "v": inp.v, **_route(res)}
            if res.get("restarted"):
                head["chatter_dps"] = list(golden_chatter.RESTART_DPS)
        else:       # the dps 90 / 110 pair; its proof record is still the first proof (input_proof)
            where = f"{sc.name} / {case.name} / {label}"
            enc = None if first is None else first[1]
            res, head = _self_checked(sc, inp, where, enc), {"x": inp.x, "v": inp.v}
        out = entry["inputs"][label] = {**head, **record(sc, res)}
        if inp.exact == "float64":       # the first proof's run (position forcing) guides the band's proofs
            # too, and the moves are compared with the itinerary written
            out["band"] = (golden_proof.band(sc, inp, first[0]["points"], res["events"]) if first
                           else golden_proof.band(sc, inp))
        out["enclosure"] = golden_proof.enclosure(sc, inp, enc)
    return entry


def document(sc, cases: list, n_sample: int = N_SAMPLE, generator: str = "python -m cross_check golden") -> dict:
    """The golden file of a scene from its case entries (``case_entry``), with the provenance."""
    doc = _document(sc, cases, n_sample, generator)
    if sc.has("position_forcing"):
        doc["provenance"]["proved_values"] = (
            f"an input with \"dps\": {PROVED_DPS} has its values from a dps-{PROVED_DPS} run and its "
            "Jacobian from the midpoints of its enclosure's balls (192 bits, Phi' to the working "
            "precision), every written number of which that enclosure proves within "
            "golden_proved_agreement (1e-40; Phi' x kappa) of the true value, in place of the "
            f"dps-{CHECK_DPS} run; an input with \"guide_dps\": {GUIDE_DPS} has its values from the "
            f"midpoints of that enclosure's balls (guided by a dps-{GUIDE_DPS} run), every one of which "
            "lies within golden_proved_agreement of all of its ball; the others: dps "
            f"{GOLDEN_DPS} checked at {CHECK_DPS}")
    if any("chatter_dps" in inp for case in cases for inp in case["inputs"].values()):
        doc["provenance"]["chatter_restart"] = golden_chatter.PROVENANCE
    return doc


def _document(sc, cases, n_sample, generator) -> dict:
    return {
        "format": FORMAT,
        "scene": scene_record(sc),
        "provenance": {
            "generator": generator,
            "integrator": "reference (mpmath, event-driven closed-form flights)",
            "mpmath": mpmath.__version__,
            "mpmath_backend": mpmath.libmp.BACKEND,
            "dps": GOLDEN_DPS,
            "check_dps": CHECK_DPS,
            "digits": DIGITS,
            "self_agreement": f"golden_self_agreement: rtol {tol('golden_self_agreement').rtol:g} "
                              "(cross_check/tolerances.py)",
            "states": f"seeded sample (seed {scenes.SEED}, n={n_sample}) + cross_check.hardcases constructions",
            "period": "events and Phi over [0, T], T = 2 pi / omega, from t0 = 0",
            "band": "float64 inputs: true if the reference's itinerary (dps 50, canonical) changes "
                    "under a move of compare_band_ulps ulps (the near-grazing band)",
            "enclosure": "reference.enclosure.enclose_map (python-flint " + _flint_version() + " arb "
                         "balls): the itinerary re-proved by Krawczyk steps and exclusions; balls "
                         "[mid, radius] widened to golden_enclosure_floor",
        },
        "cases": cases,
    }


def scene_file(name: str, n_sample: int = N_SAMPLE, progress=None) -> dict:
    """The golden record of one scene (raises ``GoldenError`` on a failed self-check)."""
    sc = scenes.scene(name)
    cases = []
    for case in scenes.states_of_interest(name, n_sample):
        cases.append(case_entry(sc, case))
        if progress:
            progress(f"golden {name}: {case.name}")
    return document(sc, cases, n_sample)


def _flint_version() -> str:
    import flint
    return flint.__version__


def generate(names=None, out_dir=DEFAULT_DIR, n_sample: int = N_SAMPLE, progress=None) -> list:
    """Compute every scene first, then write all files (nothing written if a check fails)."""
    names = list(scenes.SCENES) if names is None else list(names)
    texts = {}
    for name in names:
        texts[scenes.slug(name) + ".json"] = dumps(scene_file(name, n_sample, progress))
    out = pathlib.Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths = []
    for fname, text in texts.items():
        path = out / fname
        path.write_text(text)
        paths.append(path)
    return paths


def main(argv=None) -> int:
    """CLI entry: ``golden [--out DIR] [--scenes NAME ...] [--scenes-file FILE] [--scene "..."] [--n-sample N]``."""
    import argparse

    parser = argparse.ArgumentParser(prog="python -m cross_check golden",
                                     description="write the golden data (reference at 40 digits, with a proof "
                                                 "per input); exit 1 if a self-check fails (nothing written), "
                                                 "2 on bad input")
    parser.add_argument("--out", default=None, help="output directory (default: cross_check/data/golden for the "
                        "built-in scenes, golden/ when user scenes are given)")
    parser.add_argument("--scenes", nargs="+", metavar="NAME", choices=list(scenes.SCENES),
                        help="only these built-in scenes (default: all, unless user scenes are given)")
    scenefile.add_arguments(parser, "write golden data for")
    parser.add_argument("--n-sample", type=int, default=N_SAMPLE, help=f"sample states per scene ({N_SAMPLE})")
    args = parser.parse_args(argv)
    if args.n_sample < 0:
        parser.error("--n-sample must be >= 0")
    try:
        user = scenefile.from_args(args)
    except scenefile.SceneFileError as exc:
        print(f"golden: {exc}", file=sys.stderr)
        return 2
    names = (args.scenes or ([] if user else list(scenes.SCENES))) + user
    out = args.out or (str(DEFAULT_DIR) if not user else "golden")
    try:
        outputs.check_folder(out)
    except outputs.Unwritable as exc:
        print(f"golden: {exc}", file=sys.stderr)
        return 2
    if not compare.available("reference"):
        print("golden: the reference integrator is not available (reference.stroboscopic_map)", file=sys.stderr)
        return 2
    progress = Progress()
    try:
        paths = generate(names, out, args.n_sample, progress=progress)
    except GoldenError as exc:
        print(f"golden: self-agreement failed, nothing written: {exc}", file=sys.stderr)
        return 1
    size = sum(p.stat().st_size for p in paths)
    print(f"wrote {len(paths)} files ({size / 1024:.0f} KiB) to {out} in {progress.elapsed:.1f}s")
    return 0
