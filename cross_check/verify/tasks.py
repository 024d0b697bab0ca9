"""The units of work of ``verify``, one scene each, run as Dask tasks: each composes a room.

Every task takes the scene as its record (``golden.scene_record``: exact strings, picklable and
readable on any worker) and registers it there (``cross_check.scenes.register``), so the rooms
below find it by name as they find a built-in scene.  Results are plain data (dicts, lists,
strings, PNG bytes): the client writes every file, so a remote cluster needs no shared disk.

* ``states``    -- the sample states and the hard cases the scene admits (``scenes``), with the
  reasons for the kinds it does not admit (``agreement.hardcases``);
* ``golden``    -- golden entries for a chunk of states (``golden.case_entry``): 40 digits after
  the dps 90 / 110 self-check, a proof per input; a state whose self-check fails is *left out*
  with the reason (never written with a doubtful digit);
* ``agreement`` -- fast against the reference, itinerary first, then digits, on the samples and
  on the hard cases (``report.sections``), the reference's answers read from the golden data;
* ``orbits``    -- periodic points of one period by Newton from a grid of seeds
  (``dynamics.periodic``), each classified, and proved by Krawczyk up a ladder of precisions
  (``verify.ladder``; each rung ``paper.claims.base.prove``:
  ``reference.enclosure.prove_periodic``; a segment of no-impact fixed points by ``prove_segment``);
* ``portrait``  -- the PNG (``verify.portrait``);
* ``scorecard`` -- an adapter scored on the scene's own golden data (``score.card``); ``scorecards``
  scores every adapter in one task.
"""
from __future__ import annotations

import math
import tempfile
from dataclasses import dataclass

import numpy as np

from cross_check import golden, scenefile, scenes
from cross_check.agreement import compare
from cross_check.dynamics import periodic
from cross_check.report import sections
from cross_check.score import card
from cross_check.verify import ladder


@dataclass(frozen=True)
class Depth:
    """How much a verify run does per scene (``FULL``; ``QUICK`` drops what ``--quick`` says)."""

    n_sample: int          # seeded sample states (golden data and agreement)
    n_ten: int             # sample states also compared after 10 periods (fast vs reference)
    periods: tuple         # orbit periods searched
    seeds: tuple           # Newton seed grid (nx, nv)
    max_proofs: int        # orbits proved per period (the rest are listed, not attempted)
    score_periods: tuple   # scorecard horizons
    pixels: int            # portrait: Omega_pres / Omega_dissip pixels per side
    n_iter: int            # portrait: iterates per orbit
    hard_agreement: bool   # fast vs reference on the hard cases too (else fast's scorecard alone grades them)
    name: str


FULL = Depth(8, 2, (1, 2, 3), (16, 16), 16, (1, 10), 120, 300, True, "full")
QUICK = Depth(4, 0, (1,), (10, 10), 8, (1,), 48, 60, False, "quick")
#: sample states per golden task (a hard case has a task of its own: two inputs, and chatter is slow)
SAMPLES_PER_TASK = 4


def golden_chunks(cases: list) -> list:
    """``[(index, case)]`` chunks for the golden tasks, the costliest first: chatter, the other
    hard cases one each, then the samples ``SAMPLES_PER_TASK`` at a time."""
    hard = sorted((ic for ic in enumerate(cases) if ic[1].exact == "decimal"), key=lambda ic: ic[1].kind != "chatter")
    soft = [ic for ic in enumerate(cases) if ic[1].exact != "decimal"]
    return [[ic] for ic in hard] + [soft[i:i + SAMPLES_PER_TASK] for i in range(0, len(soft), SAMPLES_PER_TASK)]


def scene_of(rec: dict) -> str:
    """Register the scene of a record on this worker (idempotent); its name."""
    name = rec["name"]
    if name in scenes.SCENES:
        return name
    return scenes.register(scenefile.from_record(rec, f"scene {name!r}"))


def velocity_range(sc) -> float:
    """``v`` half-range of the seeds and the portrait: the forced speed ``2F/w`` or the speed of
    crossing the gap in half a period ``R w / pi``, whichever is larger."""
    F, w = sc.float("F"), sc.float("omega")
    return max(2 * F / w, (sc.float("r") - sc.float("l")) * w / math.pi, 1e-3)


# ------------------------------------------------------------------------------ the tasks
def states(rec: dict, depth: Depth) -> dict:
    """The states of interest and the hard-case notes.

    Where the time goes under position forcing (issue 33, unseen scene D: ``F=3 f=0.5 omega=0.8
    l=-2 r=1.5 wavenumber=2.5``, 9.7 CPU s before): ``impact_at_t``'s refinement (reference
    runs from rest at 40 digits) 4.7, ``hardcases_position``'s float64 screen 3.0, the forward
    proof of ``impact_at_T`` (``enclose_map``) 1.1, the validated backward flights 0.7.  The
    reference's faster event search (``reference.taylor_float``, a kept state) takes it to 8.4,
    the same cases and notes."""
    name = scene_of(rec)
    return {"cases": scenes.states_of_interest(name, depth.n_sample), "notes": scenes.hard_case_notes(name)}


def kernels(rec: dict) -> dict:
    """Compile ``fast``'s engine for the scene (or load it from numba's cache): ``fast.warm_up``'s
    seconds.  It runs beside the first ``states`` task, on the worker that would otherwise wait.
    On a cold cache (a fresh clone) every task that called ``fast`` first compiled the engine in
    its own worker, both workers at once: a first verify of an unseen position-forced scene took
    46 CPU s where the next took 30 (issue 33; the compilation is ~10 CPU s).  Once written, the
    cache serves every later task, in every worker."""
    import fast

    pf = scenes.scene(scene_of(rec)).has("position_forcing")
    return fast.warm_up(closed_form=not pf, position_forcing=pf)


def golden_entries(rec: dict, cases: list) -> list:
    """``[(index, entry or None, reason)]`` for a chunk of ``(index, case)``."""
    sc = scenes.scene(scene_of(rec))
    out = []
    for i, case in cases:
        try:
            out.append((i, golden.case_entry(sc, case), None))
        except golden.GoldenError as exc:
            out.append((i, None, str(exc)))
    return out


def golden_document(rec: dict, parts: list, depth: Depth) -> dict:
    """The scene's golden file from its chunks (states in order) and the states left out."""
    sc = scenes.scene(scene_of(rec))
    rows = sorted((row for part in parts for row in part), key=lambda r: r[0])
    doc = golden.document(sc, [e for _, e, _ in rows if e is not None], depth.n_sample,
                          generator="python -m cross_check verify")
    return {"document": doc, "dropped": [why for _, e, why in rows if e is None]}


def agreement(rec: dict, golden_file: dict, cases: list, depth: Depth) -> dict:
    """Fast vs reference: the samples (``sections.scene_agreement``) and the hard cases among
    ``cases`` (the ``states`` result: not built again), the reference's one-period answers read
    from the scene's golden data (the ``golden_document`` result: dps 90, checked at 110, proved)
    rather than computed again at dps 50; the ten-period comparisons are the fast scorecard's."""
    name = scene_of(rec)
    hard = [c for c in cases if c.exact == "decimal"] if depth.hard_agreement else []
    ref = sections.golden_reference(golden_file["document"])
    # the ten-period comparisons are fast's scorecard's (the same measurement on the same sample
    # states, against the reference at ``card.TEN_DPS`` digits): ``document`` shows them in this table
    return {"samples": sections.scene_agreement(name, depth.n_sample, 0, reference=ref),
            "hard": sections.hard_case_rows(name, reference=ref, cases=hard) if hard else []}


def _segments(found, tol):
    """Non-isolated points grouped by ``v`` (one no-impact segment of fixed points each)."""
    groups = []
    for p in found:
        for g in groups:
            if abs(g[0].v - p.v) <= tol:
                g.append(p)
                break
        else:
            groups.append([p])
    return groups


def _attempted(kinds, max_proofs) -> set:
    """The indices of the orbits whose proofs are attempted: ``max_proofs`` of them, in order,
    those fast finds parabolic after the others (``ladder.proof``: their proofs rarely hold)."""
    return set(sorted(range(len(kinds)), key=lambda j: kinds[j] == "parabolic")[:max_proofs])


def orbits(rec: dict, period: int, depth: Depth) -> list:
    """Period-``period`` orbits: found by Newton from a seed grid, deduplicated, classified,
    the first ``depth.max_proofs`` proved (those fast finds parabolic after the others:
    ``ladder.proof``, up its precision ladder).  Each a dict (``as_dict`` of the point, ``dissip``,
    ``sticks``, the proof record or why none was attempted).

    Where the time goes (issue 33, CPU seconds of periods 1 + 2 + 3, one run each, on a loaded
    2-core machine): on D (``F=3 f=0.5 omega=0.8 l=-2 r=1.5 wavenumber=2.5``) 30.6 -> 20.7 s
    (48.4 before ``reference.taylor``'s fixed-point steps), of which the Newton search in fast
    ~8 s (5,000 seed maps a period, unchanged) and the proofs 21.2 -> 12.8 s (point logs 9.4 ->
    2.6 s); on F (``F=1 f=0.2 omega=1 l=-1 r=1 wavenumber=1``) 19.0 -> 12.5 s (26.0), proofs
    16.6 -> 10.3 s; on G (``F=2 f=0.35 omega=1.3 l=-0.7 r=1.2 restitution=0.9 damping=0.05
    wavenumber=1.8``) 11.2 -> 8.1 s (14.7).  The same orbits, classified the same,
    proved at the same rung, each point ball overlapping the one before (``PROOF_LADDER``).
    Third pass: the Newton search screens its seeds on ``fast``'s coarse map (``periodic``'s
    ``search_steps``): D's search 8.8 -> 3.6 s, the same points bit for bit (D's orbits task
    21.5 -> 17.0 s in a full verify, one run each).  Fourth pass: the default map polishes the
    screen's ends instead of running from the seeds (``dynamics.newton.NEAR_ONE``): the search 3.4 to 5.1
    -> 2.4 CPU s on the issue's first scene, the same points."""
    import fast

    sc = scenes.scene(scene_of(rec))
    vmax = velocity_range(sc)
    found = periodic.find_periodic_points(sc, period=period, v_range=(-vmax, vmax), grid=depth.seeds,
                                          search_steps=periodic.SEARCH_STEPS)
    flat = [p for p in found if p.kind == "non-isolated"]
    rows = [("orbit", p, None) for p in found if p.kind != "non-isolated"]
    rows += [("segment", g[0], (min(q.x for q in g), max(q.x for q in g))) for g in _segments(flat, 1e-7)]
    attempted = _attempted([p.kind for _, p, _ in rows], depth.max_proofs)
    out = []
    for j, (what, p, seg) in enumerate(rows):
        pts = p.points
        kinds = {e.kind for evs in compare.fast_events(sc, pts[:, 0], pts[:, 1]) for e in evs}
        row = {**p.as_dict(), "what": what, "segment": seg, "orbit": [list(z) for z in p.orbit],
               "dissip": bool(np.asarray(fast.zero_velocity(sc, pts[:, 0], pts[:, 1])).any()),
               "sticks": bool(kinds & {"stick", "contact"})}
        label = f"period {period} {what} {j}"
        if j in attempted:
            row["proof"] = ladder.proof(label, sc, p, period, seg)
        else:
            row["proof"] = {"orbit": label, "proved": False,
                            "reason": f"not attempted: more than {depth.max_proofs} orbits of period "
                                      f"{period} (the parabolic ones last)"}
        out.append(row)
    return out


def portrait(rec: dict, orbit_parts: list, depth: Depth) -> bytes:
    """The scene's portrait as PNG bytes (``verify.portrait``), with the orbits of every period.

    Under position forcing it is ``fast``'s work (scene D of ``states``: 8.6 CPU s, of which the
    120 x 120 pixels' Jacobians 7.2 -- ~0.5 ms a state-period in the compensated flights of
    ``fast.ode`` -- and the orbits 0.7; loading the compiled kernels 0.2: a second portrait in
    the same process takes 8.2).  The pixels are now classed on ``fast``'s coarse map first
    (``portrait.PORTRAIT_STEPS``): D's Jacobians 7.6 -> 1.65 CPU s, the same classes."""
    from cross_check.verify import portrait as draw

    sc = scenes.scene(scene_of(rec))
    return draw.png(sc, [row for part in orbit_parts for row in part], depth, velocity_range(sc))


def scorecards(rec: dict, golden_file: dict, adapters: tuple, depth: Depth) -> dict:
    """``{adapter: (scorecard, CPU seconds)}``: ``scorecard`` for each adapter in turn, in one
    process, so that the reference's ten-period truths (``score.card._ten_periods``: the same
    states for every adapter, half of a scorecard's cost under position forcing) are computed
    once (``compare.ref_map`` keeps its recent results).

    Under position forcing nearly all of it is those truths (scene D of ``states``: 10.5 of
    11.6 CPU s, two reference runs of ten periods at 40 digits; the adapters run in their own
    processes); the reference's event search with float64 far-from-root steps and a kept state
    (``reference.taylor``) takes the task to 7.0 CPU s, the same cards start for start; the
    event search's bounds over windows of ``T / 8`` (``reference.taylor.BOUND_WINDOWS``), not
    over the rest of ten periods, take it from 4.9 to 2.0 in a full verify (one run each); the truths at
    25 digits, not 40 (``card.TEN_DPS``), the same readings, take a third off them."""
    import time

    out = {}
    for adapter in adapters:
        t0 = time.process_time()
        out[adapter] = (scorecard(rec, golden_file, adapter, depth), time.process_time() - t0)
    return out


def scorecard(rec: dict, golden_file: dict, adapter: str, depth: Depth) -> dict:
    """``adapter`` (a shipped name: ``fast``, ``scipy``) on the scene's own golden data (the
    ``golden_document`` result)."""
    import pathlib

    name = scene_of(rec)
    with tempfile.TemporaryDirectory() as tmp:
        (pathlib.Path(tmp) / (scenes.slug(name) + ".json")).write_text(golden.dumps(golden_file["document"]))
        c = card.score(card.load_adapter(adapter), scenes=[name], periods=depth.score_periods, golden_dir=tmp)
    return {"adapter": c.adapter, "flagged": c.flagged(), "kinds": c.kinds(), "markdown": c.to_markdown(),
            "json": c.to_json()}
