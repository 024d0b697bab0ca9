"""``impact_at_T`` under position forcing where no single flight reaches it (issue 33).

``hardcases_position`` builds its cases as one flight from ``t = 0`` to the event, run backward
from the event state.  An impact at exactly ``t = T`` then needs a flight of a whole period with
no other event; on a narrow gap (``r - l`` below about ``f T^2 / 2 + 2 F / w^2``) every such
flight meets a wall or stops, and the kind was not admitted.  Here it is built forward, as an
itinerary from rest, and certified by the forward proof of that itinerary:

1. **screen** (fast, float64): ``N_SCAN`` starts from rest, ``x0 = l + (r - l) i / N_SCAN``,
   ``v0 = 0``, each run over ``[0, 5T/4]``.  Two neighbours whose event logs agree up to an
   impact at the same wall, one before ``T`` and one after, bracket a start whose impact is at
   ``T`` exactly (the impact time is continuous in ``x0`` while the itinerary before it stays
   the same).  Where the starts from rest give no bracket that step 2 and 3 accept, the same
   scan is made at the speeds ``v0 = +-V/2, +-V, +-2V``, ``V = max(F/w, f T)`` (``speeds``: the
   forced speed, or the speed that friction takes a period to stop, so that a stop does not
   make every start forget where it began; two significant digits: an exact decimal); and
   where those give none either, at the speeds that the backward screen proposes
   (``impact_backward``: the motion run back from an impact at ``T``), then at ``FAST_SPEEDS``;
2. **refine** (fast narrows the bracket, ``_narrowed``; then the reference, ``REFINE_DPS``
   digits): regula falsi (Illinois) on
   ``h(x0) = t_j(x0) - T`` in that bracket, the itinerary before the impact held fixed (a change
   is a ``ConstructionError``, and so is a jump of ``t_j``: ``JUMP_SLOPE``), at most ``MAX_REFINE``
   runs, to ``|h| < 10^-(STATE_DIGITS + 3)``;
   the start is ``x0`` to ``STATE_DIGITS`` digits and the bracket's ``v0``;
3. **certify**: ``reference.enclosure.enclose_map`` proves the start's itinerary over ``[0, T]``
   forward, on validated flights (``reference.enclosure.lohner``): every other event excluded,
   each event time in a ball.  A start it cannot prove is refused.

fast only orders the candidates (a wrong screen costs a bracket, never a wrong case): the
reference places the impact and the enclosure proves the itinerary.
"""
from __future__ import annotations

import itertools

import mpmath
import numpy as np

import fast
import reference
from cross_check.agreement import impact_backward
from cross_check.agreement.case import ConstructionError, HardCase, decimal_text, first_built
from reference.enclosure import enclose_map
from reference.enclosure.balls import DEFAULT_PREC

#: starts from rest scanned across the gap by fast
N_SCAN = 256
#: digits of the reference's runs in the refinement
REFINE_DPS = 40
#: the refinement's bound on reference runs per bracket (regula falsi takes ~10 from fast's
#: bracket; the bound keeps a stalled one to a few seconds)
MAX_REFINE = 24
#: a bracket whose ends both stay farther from ``T`` than ``JUMP_SLOPE`` times its first secant
#: slope times its width is a jump of ``t_j``, not a root (``_refine``): a root inside would need
#: a slope ``JUMP_SLOPE`` times that of the whole bracket.  Issue 33, the frictionless far corner
#: ``F=2 f=0 omega=0.5 l=-1 r=1 wavenumber=2``: two brackets from rest straddle a jump of the
#: fourth impact's time (``h`` = +1.11 on one side, -1.12 on the other: an earlier event grazes),
#: and took all ``MAX_REFINE`` runs each (8.6 of the case's 19.7 CPU s)
JUMP_SLOPE = 1000
#: a refinement run goes this many times the larger ``|t_j - T|`` of the bracket's ends past
#: ``T`` (``_impact_time``), then on to ``5T/4`` only if its impact ``j`` is not reached
REACH = 4
#: brackets from rest tried, nearest the middle of the gap first
MAX_BRACKETS = 3
#: the speeds of the other scans, in units of ``V = max(F/w, f T)`` (``speeds``), and the brackets
#: tried from them after those from rest, the best of each speed first.  Issue 33: on 12 unseen
#: scenes drawn at random over every parameter and effect, 5 had no bracket from rest, and neither
#: had the frictionless ``F=2 f=0 omega=0.5 l=-1 r=1 wavenumber=2``
SPEEDS = (0.5, -0.5, 1, -1, 2, -2)
MAX_MOVING_BRACKETS = 4
#: the speeds scanned last (units of ``V``, slowest first), after those the backward screen
#: proposes: a fast start whose bounces have not died into contact or rest by ``T``, or that
#: reaches ``T`` through a stop, which the backward screen cannot run back through.  Issue 33, on
#: unseen scenes drawn at random: cases from ``3.5V`` (through 14 impacts, a stop and a slip) and
#: ``5.5V``, in bands of speeds narrower than ``V``
FAST_SPEEDS = tuple(s for j in range(5, 17) for s in (j / 2, -j / 2))
#: fast's events that the scans of ``FAST_SPEEDS`` (and ``forward_position``'s last scans) may
#: simulate, a deterministic budget: the two cases above took 42,000 and 89,000; on a narrow gap
#: without friction where none is found, all of them took 920,000 events and 19 CPU s
MORE_EVENTS = 150_000
#: brackets tried from the speeds the backward screen proposes and ``FAST_SPEEDS`` (each a
#: reference refinement)
MAX_MORE_BRACKETS = 2
#: fast's narrowing of a bracket before the reference refines it (``_narrowed``: 64^4 ~ 1.7e7
#: times narrower; on D, ``F=3 f=0.5 omega=0.8 l=-2 r=1.5 wavenumber=2.5``, the reference's runs
#: 10 -> 6 runs, 3.1 -> 2.1 CPU s, the same start to its 30 digits)
NARROW_ROUNDS, NARROW_STARTS = 4, 64
#: kinds allowed before the impact at T (a chatter tail or contact has no isolated time).  At
#: restitution 0 an impact that leaves at once is one of them: the walk follows it (it was left
#: out while the walk refused every such impact; issue 33, the scene of
#: ``test_impact_at_T_at_restitution_0_through_plastic_impacts``: built through two now)
PREFIX_KINDS = frozenset({"impact", "turn", "stick", "slip"})
#: the forward proof's most bits: where the walk cannot prove the itinerary at ``DEFAULT_PREC``
#: (320) on the hard cases seen the cause was structural, and ``enclose_map``'s climb to 1280 bits
#: cost 3 to 12 CPU s a start (issue 33: an impact with restitution 0, which the walk did not follow)
PROOF_MAX_PREC = DEFAULT_PREC
#: the bits of the forward proof's first try (``forward_proof``); ``PROOF_MAX_PREC`` where it fails.
#: The proof certifies the itinerary, not digits: at 128 bits the Taylor flights' order is 44
#: instead of 110.  Issue 33, scene W (``F=3 f=0.3 omega=0.5 l=-2 r=2 wavenumber=2``): its
#: impact at T and its sticking start proved at 128, and the states task took 7.4 -> 6.3 CPU s
#: (one run each), the same cases
PROOF_FIRST_PREC = 128


def forward_proof(scene, x_text, v0):
    """``enclose_map`` of one period from a hard case's start: at ``PROOF_FIRST_PREC`` bits,
    then (where that fails) from ``DEFAULT_PREC`` up to ``PROOF_MAX_PREC``."""
    enc = enclose_map(scene, x_text, v0, prec=PROOF_FIRST_PREC, max_prec=PROOF_FIRST_PREC)
    return enc if enc.proved else enclose_map(scene, x_text, v0, max_prec=PROOF_MAX_PREC)


def logs(scene, x, v0, t_end, spent=None):
    """fast's event logs from ``(x[i], v0)`` over ``[0, t_end]``; ``spent`` (a list, if given)
    receives their number of events (``MORE_EVENTS``)."""
    out = fast.events(scene, x, np.full_like(x, float(v0)), t_end)
    if spent is not None:
        spent.append(int(out.n.sum()))
    return out


def budgeted(speeds_list, spent):
    """``speeds_list`` in turn, while the scans made so far (``spent``) have simulated at most
    ``MORE_EVENTS`` events."""
    for v0 in speeds_list:
        if sum(spent) > MORE_EVENTS:
            return
        yield v0


def _crossings(scene, x, v0="0", spent=None):
    """Indices ``i`` of neighbouring starts ``(x[i], v0), (x[i + 1], v0)`` (fast, over
    ``[0, 5T/4]``; ``v0`` a decimal string, ``"0"``: from rest) whose ``j``-th event is an impact
    at the same wall, before ``T`` for one and after it for the other, with the same kinds before
    it (once per such ``j``: ``_crossing_times``)."""
    starts = np.arange(len(x) - 1)
    return [i for i, _ in _crossing_times(scene, logs(scene, x, v0, 1.25 * scene.period, spent), starts, starts + 1)]


def _crossing_times(scene, log, a, b):
    """``[(p, (t_j - T, t'_j - T))]`` for each ``j`` at which the logs of starts ``a[p]`` and
    ``b[p]`` of fast's ``EventLog`` cross ``T``: along their common prefix of kinds in
    ``PREFIX_KINDS``, the ``j``-th events are impacts at the same wall, one before ``T`` and one
    after it.  In order of ``p``, then ``j``.  Read on the log's arrays, column by column: issue
    33, reading the scans' logs event by event (``EventLog[i]``, one ``Event`` record each) was
    ~3 CPU s of the states task of two unseen scenes (seed 5151's P1 and P3 of the verify
    benchmark's distribution); 649 scans of 21 scenes 40.1 -> 2.8 CPU s, the same brackets."""
    l, r, T = scene.float("l"), scene.float("r"), scene.period
    kind, t, x = (arr.reshape(len(log), -1) for arr in (log.kind, log.t, log.x))
    n = log.n.ravel()
    prefix = np.array([fast.KINDS.index(k) for k in sorted(PREFIX_KINDS)])
    impact = fast.KINDS.index("impact")
    alive = np.ones(len(a), bool)
    hits = []
    for j in range(kind.shape[1]):
        ka, kb = kind[a, j], kind[b, j]
        alive &= (j < n[a]) & (j < n[b]) & (ka == kb) & np.isin(ka, prefix)
        if not alive.any():
            break
        xa, xb, ta, tb = x[a, j], x[b, j], t[a, j] - T, t[b, j] - T
        same_wall = (np.abs(xa - r) < np.abs(xa - l)) == (np.abs(xb - r) < np.abs(xb - l))
        hits += [(int(p), j, (float(ta[p]), float(tb[p])))
                 for p in np.flatnonzero(alive & (ka == impact) & same_wall & (ta * tb < 0))]
    return [(p, times) for p, _, times in sorted(hits)]


def speeds(scene, units=None) -> list:
    """The speeds of the scans after the one from rest (``units``, by default ``SPEEDS``, times
    ``V = max(F/w, f T)``, two significant digits), as decimal strings.  Other ``units``: those
    not already among the ``SPEEDS``' (two digits may round two units alike)."""
    scale = impact_backward.speed_scale(scene)
    out = [repr(float(f"{s * scale:.2g}")) for s in (SPEEDS if units is None else units)]
    first = [] if units is None else speeds(scene)
    return [v for i, v in enumerate(out) if v not in first and v not in out[:i]]


def speeds_text(scene, more=()) -> str:
    """The scanned speeds in words, for a refusal: ``SPEEDS``' list, and the range of ``more``."""
    rest = speeds(scene, more) if more else []
    tail = f", and {len(rest)} more with |v0| from {min(rest, key=lambda v: abs(float(v))).lstrip('-')} to " \
           f"{max(rest, key=lambda v: abs(float(v))).lstrip('-')}" if rest else ""
    return ", ".join(speeds(scene)) + tail


def scan_grid(scene):
    """The starting positions of a scan: ``x0 = l + (r - l) i / N_SCAN``, ``0 < i < N_SCAN``."""
    l, r = scene.float("l"), scene.float("r")
    return l + (r - l) * np.arange(1, N_SCAN) / N_SCAN


def _scan(scene, v0, spent=None):
    """The brackets of the scan at speed ``v0``, nearest the middle of the gap first."""
    x, mid = scan_grid(scene), (scene.float("l") + scene.float("r")) / 2
    return sorted(((x[i], x[i + 1], v0) for i in _crossings(scene, x, v0, spent)), key=lambda c: abs(c[0] - mid))


def _brackets(scene, dead_ends=None):
    """``(x_a, x_b, v0)``, lazily: neighbouring starts of a scan that bracket an impact at ``T``
    (``_crossings``; step 1 of the module docstring): ``MAX_BRACKETS`` from rest, then, scanned
    only once those are used up, ``MAX_MOVING_BRACKETS`` at the other ``speeds``, the best of
    each speed first, then the best of each speed that the backward screen proposes
    (``impact_backward``) and of each of ``FAST_SPEEDS`` in turn (within ``MORE_EVENTS``),
    ``MAX_MORE_BRACKETS`` of them (each scan made only when the one before gave nothing that was
    used).  ``dead_ends`` (a
    list) receives the backward runs that found no start, with their reasons."""
    yield from _scan(scene, "0")[:MAX_BRACKETS]
    moving = [_scan(scene, v0) for v0 in speeds(scene)]
    ranked = [found[rank] for rank in range(N_SCAN - 1) for found in moving if rank < len(found)]
    yield from ranked[:MAX_MOVING_BRACKETS]
    proposed, why = impact_backward.proposals(scene)
    if dead_ends is not None:
        dead_ends.extend(why)
    tried, spent = speeds(scene), []
    fastest = [v0 for v0 in speeds(scene, FAST_SPEEDS) if v0 not in proposed]
    scans = itertools.chain((_scan(scene, v0) for v0 in proposed if v0 not in tried),
                            (_scan(scene, v0, spent) for v0 in budgeted(fastest, spent)))
    more = (found[0] for found in scans if found)
    yield from itertools.islice(more, MAX_MORE_BRACKETS)


def _narrowed(scene, xa, xb, v0="0"):
    """The bracket narrowed by fast: ``NARROW_ROUNDS`` rounds of ``NARROW_STARTS`` starts across
    it, each keeping its first pair that still brackets (``_crossings``); as it stands where fast
    finds none.  The reference's regula falsi then starts ~1e7 times closer to its root."""
    for _ in range(NARROW_ROUNDS):
        x = np.linspace(xa, xb, NARROW_STARTS)
        hits = _crossings(scene, x, v0)
        if not hits:
            break
        xa, xb = x[hits[0]], x[hits[0] + 1]
    return xa, xb


def _impact_time(scene, x0, j, kinds, T, v0="0", reach=None):
    """``t_j - T`` of the reference from ``(x0, v0)`` (mpf, decimal string), its events up to
    ``j`` of the ``kinds`` (the last an impact); ``ConstructionError`` if they changed.

    ``reach``: how far past ``T`` the run goes first (the regula falsi's iterates have their
    impact between its ends': ``REACH`` times the larger ``|t_j - T|`` of the two), where the
    whole ``5T/4`` is run only if event ``j`` is not reached by then.  Issue 33: the runs past
    ``T`` were ~a fifth of each refinement run."""
    log = _trajectory(scene, x0, T + reach if reach is not None else 1.25 * T, v0)
    if reach is not None and len(log) <= j:
        log = _trajectory(scene, x0, 1.25 * T, v0)
    got = [e.kind for e in log][:j + 1]
    if got != kinds:
        raise ConstructionError(f"the itinerary changed inside the bracket: {got} != {kinds}")
    return log[j].t - T


def _trajectory(scene, x0, t_end, v0="0"):
    """The reference's event log from ``(x0, v0)`` over ``[0, t_end]``, at ``REFINE_DPS``."""
    return reference.trajectory(scene, x0, mpmath.mpf(v0), t_end, dps=REFINE_DPS)


def _nearest_impact(log, T):
    """Index of the impact of ``log`` nearest ``T`` (``None``: no impact)."""
    impacts = [i for i, e in enumerate(log) if e.kind == "impact"]
    return min(impacts, key=lambda i: abs(log[i].t - T)) if impacts else None


def _refine(scene, xa, xb, T, digits, v0="0"):
    """The start ``(x0, v0)``, ``x0`` in ``[xa, xb]``, whose impact nearest ``T`` (in the
    reference's log from ``xa``: event ``j``) is at ``T`` (step 2).  Returns ``(x0, kinds, j)``."""
    a, b = mpmath.mpf(xa), mpmath.mpf(xb)
    log = _trajectory(scene, a, 1.25 * T, v0)
    j = _nearest_impact(log, T)
    if j is None:
        raise ConstructionError(f"the reference from (x0, v0) = ({xa!r}, {v0}) meets no wall")
    kinds = [e.kind for e in log][:j + 1]
    if not set(kinds[:-1]) <= PREFIX_KINDS:
        raise ConstructionError(f"the reference from (x0, v0) = ({xa!r}, {v0}) chatters or rests first: {kinds}")
    ha, hb = log[j].t - T, _impact_time(scene, b, j, kinds, T, v0)
    if not ha * hb < 0:
        raise ConstructionError(f"the reference does not bracket an impact at T in [{xa!r}, {xb!r}]")
    side, slope = 0, abs(hb - ha) / abs(b - a)
    for _ in range(MAX_REFINE):
        c = (a * hb - b * ha) / (hb - ha)
        hc = _impact_time(scene, c, j, kinds, T, v0, REACH * max(abs(ha), abs(hb)))
        if abs(hc) < mpmath.mpf(10) ** -(digits + 3):
            return c, kinds, j
        if hc * ha < 0:
            b, hb = c, hc
            ha, side = (ha / 2, -1) if side == -1 else (ha, -1)
        else:
            a, ha = c, hc
            hb, side = (hb / 2, 1) if side == 1 else (hb, 1)
        if JUMP_SLOPE * slope * abs(b - a) < min(abs(ha), abs(hb)):     # Illinois' halved h: smaller
            raise ConstructionError(f"the impact time jumps in [{mpmath.nstr(a, 17)}, {mpmath.nstr(b, 17)}] "
                                    f"(t_j - T of each sign, at least {mpmath.nstr(min(abs(ha), abs(hb)), 3)} "
                                    f"from 0 at its ends): an earlier event grazes there, no root")
    raise ConstructionError(f"no start with its impact within 1e-{digits + 3} of T after {MAX_REFINE} runs")


def _refined(scene, xa, xb, T, digits, v0="0"):
    """``_refine`` on fast's narrowed bracket (``_narrowed``), or on the bracket itself where the
    reference does not bracket the impact inside the narrowed one.  A narrowed bracket across
    which fast's impact time jumps (``_fast_jump``) is refused before any reference run: its
    refinement would only find the jump.  Issue 33, the frictionless far corner ``F=2 f=0
    omega=0.5 l=-1 r=1 wavenumber=2``: its three brackets from rest are such jumps, and the
    reference's two runs on each (at 40 digits, over ``5T/4``) took 1.3 CPU s a bracket: each
    bracket 1.4 -> 0.2 CPU s, the same case (the whole construction 18.8 and 18.0 CPU s, one run
    each: the bracket that holds took 7.6 and 8.8, this machine's noise)."""
    na, nb = _narrowed(scene, xa, xb, v0)
    if (na, nb) != (xa, xb):
        if _fast_jump(scene, (xa, xb), (na, nb), v0):
            raise ConstructionError(f"the impact time jumps in fast's narrowed bracket [{na!r}, {nb!r}] "
                                    f"(JUMP_SLOPE): an earlier event grazes there, no root")
        try:
            return _refine(scene, na, nb, T, digits, v0)
        except ConstructionError:
            pass
    return _refine(scene, xa, xb, T, digits, v0)


def _fast_jump(scene, wide, narrow, v0) -> bool:
    """Whether fast's ``t_j - T`` at the ends of its ``narrow`` bracket (``_narrowed``) are both
    farther from 0 than ``JUMP_SLOPE`` times the ``wide`` bracket's secant slope times the narrow
    width: a jump (an earlier event grazes), which the reference's refinement of ``wide`` would
    only find again (``_refine``: 15 runs on the frictionless far corner of issue 33, twice).
    fast only screens: a jump it sees costs a bracket, never a wrong case."""
    ends = logs(scene, np.array([wide[0], narrow[0], narrow[1], wide[1]]), v0, 1.25 * scene.period)
    hits = _crossing_times(scene, ends, np.array([0, 1]), np.array([3, 2]))
    h = [next((times for q, times in hits if q == p), None) for p in (0, 1)]
    if None in h:
        return False
    slope = abs(h[0][1] - h[0][0]) / (wide[1] - wide[0])
    return JUMP_SLOPE * slope * (narrow[1] - narrow[0]) < min(abs(h[1][0]), abs(h[1][1]))


def construct(scene, digits: int):
    """``(HardCase, None)`` or ``(None, why)``: the kind ``impact_at_T`` from rest or from a
    start at one of ``speeds``, through earlier events (module docstring); ``digits``: the
    start's significant digits."""
    with mpmath.workdps(REFINE_DPS + 10):
        T = 2 * mpmath.pi / scene.mpf("omega")
        dead_ends = []
        most = MAX_BRACKETS + MAX_MOVING_BRACKETS + MAX_MORE_BRACKETS
        case, why, tried = first_built(_brackets(scene, dead_ends), most,
                                       lambda bracket: _certified(scene, *bracket, T, digits))
    if case is not None:
        return case, None
    if not tried and why is None:
        if scene.mpf("restitution") == 0:
            back = ("; at restitution 0 no motion runs backward through an impact (it leaves no speed: the "
                    "speed before it is not determined), so there is no backward screen")
        elif len(dead_ends) == 2 * len(impact_backward.EVENT_SPEEDS):
            back = (f"; run backward from an impact at T (impact_backward: v* = {impact_backward.EVENT_SPEEDS[0]:g} "
                    f"V to {impact_backward.EVENT_SPEEDS[-1]:g} V at each wall, V = max(F/w, f T)), each of the "
                    f"{len(dead_ends)} motions stops or passes {impact_backward.MAX_SPEED:g} V before t = 0 (the "
                    f"last: {dead_ends[-1]}): on every motion screened, the bounces die before T")
        else:
            back = ""
        return None, (f"nor through earlier events: none of {N_SCAN - 1} starts from rest, nor at the "
                      f"speeds {speeds_text(scene, FAST_SPEEDS)} (those within {MORE_EVENTS:,} events of "
                      f"fast), brackets an impact at T{back}")
    return None, f"nor through earlier events: {why}"


def _certified(scene, xa, xb, v0, T, digits):
    """``(HardCase, None)`` or ``(None, why)``: the start of the bracket refined (step 2) and its
    itinerary proved forward (step 3)."""
    try:
        x0, kinds, j = _refined(scene, xa, xb, T, digits, v0)
        x_text = decimal_text(x0, digits)
        enc = forward_proof(scene, x_text, v0)
        if not enc.proved:
            raise ConstructionError(f"the forward proof failed: {enc.reason}")
    except (ValueError, RuntimeError, ArithmeticError) as exc:   # ConstructionError among them
        return None, str(exc)
    path = ", ".join(kinds[:-1]) or "no earlier event"
    start = "from rest" if v0 == "0" else f"from x0 at v0 = {v0}"
    return HardCase("impact_at_T", x_text, v0, decimal_text(T, digits), "impact",
                    f"impact at a wall at exactly t = T, {start} through {path} (event {j + 1}); "
                    f"certified: the itinerary proved forward (validated flights, enclose_map at "
                    f"{enc.prec} bits: no other event on [0, T])"), None
