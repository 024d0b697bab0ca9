"""A kind that fails costs a few budgets, not one per start (issue 37): the per-kind cut-off and the
short budget of ``cross_check.score`` (``cutoff``, ``runner.Budget``).

Three layers:

* the cut-off's bookkeeping alone (``KindCutoff``, ``SceneCut``): K timeouts cut a kind, band starts
  count apart, a kind cut in 3 scenes running gets a probe;
* the whole scorer on a *virtual* runner: calls take no time, a start that sticks "times out" at
  once and its budget is charged to a virtual clock.  Which starts hang is drawn at random
  (hypothesis), so the claims are checked on many integrators, not one: the flagged kinds are
  those of a run without the cut-off, no kind has more than K timeouts in a scene (its probe
  aside), the time charged stays within what the cut-off promises, and an integrator that hangs
  nowhere is scored start for start as without it;
* real runs in a worker process: the naive ``solve_ivp`` integrator (``adapters_for_tests.NAIVE``:
  ``f sign(v)`` in its right-hand side, a hang where the motion sticks) on two sticking scenes,
  its time measured as a guard against a hang; and a slow but correct kind (just under the cap,
  80 times the median start) in an integrator that hangs elsewhere: never cut.
"""
import json
import time

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from cross_check import __main__ as cli
from cross_check.score import runner, score
from cross_check.score.cutoff import BAND, NOT_RUN, KindCutoff, kind_timeouts_arg
from cross_check.score.golden import all_cases, scene_cases
from reference.scene import EFFECTS

pytest_plugins = ["pytester"]

#: seconds a worker restart may take beside the budget it ends (a spare process, warmed in the
#: background, takes over: 0.1 s idle, up to 1 s at load 7 on 2 cores), and for the warm-up call and
#: the scoring itself in a run of two scenes (3 s at load 7)
RESTART, SLACK = 1.0, 10.0


# --- the bookkeeping --------------------------------------------------------------------------
def test_k_timeouts_cut_a_kind_and_band_starts_count_apart():
    cut = KindCutoff(2).scene("s", [("sticking", True), ("impact", True), ("sticking", False)])
    cut.record("sticking", False, True)          # a band start: counts for the band only
    cut.record("sticking", True, True)
    assert cut.reason("sticking") is None and cut.reason("sticking", False) is None
    cut.record("impact", True, False)
    cut.record("sticking", True, True)
    assert cut.reason("sticking") == f"{NOT_RUN}: kind sticking timed out 2 times in this scene"
    assert cut.reason("sticking", False) == cut.reason("sticking")      # its band starts go with it
    assert cut.reason("impact") is None
    cut.record("impact", False, True)                                    # the band's second timeout
    assert cut.reason("impact") is None and "the band" in cut.reason("impact", False)
    off = KindCutoff(0).scene("s", [("sticking", True)])
    for _ in range(5):
        off.record("sticking", True, True)
    assert off.reason("sticking") is None


def test_a_kind_cut_in_three_scenes_running_gets_one_probe():
    owner = KindCutoff(2)

    def scene(timeouts, completed=0, kind="sticking"):
        cut = owner.scene("s", [(kind, True)])
        probe = cut.is_probe(kind, True)
        for _ in range(timeouts):
            cut.record(kind, True, True)
        for _ in range(completed):
            cut.record(kind, True, False)
        cut.close()
        return probe, cut.reason(kind)

    assert scene(2) == (False, f"{NOT_RUN}: kind sticking timed out 2 times in this scene")
    assert scene(1) == (False, None)                  # its only start timed out: the run goes on
    scene(0, kind="impact")                           # a scene without the kind does not break it
    assert scene(2)[0] is False and owner.suspect("sticking")
    probe, why = scene(1)                             # the probe times out: the kind is cut at once
    assert probe and why.startswith(f"{NOT_RUN}: kind sticking timed out 1 time in this scene (its probe")
    assert scene(0, completed=1) == (True, None)      # the probe passes: trusted again
    assert not owner.suspect("sticking")
    with pytest.raises(ValueError, match="kind_timeouts must be an integer >= 0"):
        KindCutoff(-1)
    assert kind_timeouts_arg("0") == 0
    with pytest.raises(Exception, match="integer >= 0"):
        kind_timeouts_arg("-1")


# --- the scorer on a virtual runner -----------------------------------------------------------
SCENES = ["fig:narrow-with-friction", "fig:many:wide/f=0.2", "fig:many:wide/f=0.4", "fig:many:wide/f=0.5",
          "fig:resonance/R=0.89", "stuck/F<f"]
CAP = 10.0
STEP = 0.01           # virtual seconds per start that does not hang
SLOW = 0.8            # virtual seconds of a slow but correct start: 80 x STEP, under the 1 s floor x 1


class VirtualRun:
    """The golden answer, at no real cost: each start takes ``STEP`` virtual seconds (``SLOW`` for a
    start of ``slow``: correct, but 80 times the typical start) charged to ``clock``; a call holding a
    start of ``hangs``, or over its budget, "times out": its budget is charged and nothing comes
    back (what the worker process does, without the wait)."""

    isolated, note, restarts, who = False, "virtual", 0, "'virtual'"

    def __init__(self, hangs, slow=frozenset()):
        self.slow = slow
        self.meta = {"name": "virtual", "effects": sorted(EFFECTS), "events": False}
        # by scene and start (two scenes may share a start); the warm-up may come from any scene
        self.by_start = {(_key(c.params), c.x, c.v): c for c in all_cases()}
        self.hangs, self.clock, self.calls = hangs, 0.0, []

    def call(self, method, args, budget, on_slow=None):
        params, x, v, periods = args
        cases = [self.by_start[(_key(params), float(a), float(b))] for a, b in zip(x, v)]
        self.calls.append(([c.id for c in cases], budget))
        took = sum(SLOW if c.id in self.slow else STEP for c in cases)
        if any(c.id in self.hangs for c in cases) or took > budget:
            self.clock += budget
            return runner.Outcome(failure="the worker process was stopped", kind="timeout", seconds=budget,
                                  budget=budget)
        self.clock += took
        return runner.Outcome(value=(np.array([float(c.phi[0]) for c in cases]),
                                     np.array([float(c.phi[1]) for c in cases])), seconds=took)

    def close(self):
        pass


def _key(params):
    return tuple(sorted(params.items()))


def virtual_card(hangs, monkeypatch, slow=frozenset(), **kw):
    run = VirtualRun(hangs, slow)
    monkeypatch.setattr(runner, "runner", lambda *a, **k: run)
    return score("virtual", scenes=SCENES, periods=(1,), case_timeout=CAP, **kw), run


def sticks(c) -> bool:
    return any(e[0] in ("stick", "contact") for e in c.events)


ALL = [c for n in SCENES for c in scene_cases(n)]
STICKING = frozenset(c.id for c in ALL if sticks(c))


def promise(hangs, k) -> float:
    """The most the cut-off lets a run spend on timeouts, in budgets of the cap: per scene, K per
    kind and K for the band, one probe per suspect kind included in K, and one batch."""
    total = 0
    for name in SCENES:
        keys = {c.kind if not c.band else BAND for c in scene_cases(name) if c.id in hangs}
        total += k * len(keys) + 1
    return total * CAP


def test_the_naive_integrators_card_costs_what_the_cutoff_promises(monkeypatch):
    cut, run = virtual_card(STICKING, monkeypatch)
    full, run0 = virtual_card(STICKING, monkeypatch, kind_timeouts=0, budget_multiple=0)     # as before
    assert cut.flagged() == full.flagged() and "sticking" in cut.flagged()
    assert {c.id: (c.digits, c.failure_kind) for c in cut.cases if c.failure_kind != NOT_RUN} == \
        {c.id: (c.digits, c.failure_kind) for c in full.cases if c.id not in {n.id for n in cut.not_run()}}
    assert run.clock <= promise(STICKING, 2) < run0.clock
    for name in SCENES:                 # every sticking start past the K-th (or past the probe) is not run
        rows = [c for c in cut.cases if c.id.startswith(name + "/") and c.kind == "sticking" and not c.band]
        timeouts = sum(c.failure_kind == "timeout" for c in rows)
        assert timeouts == min(2, len(rows)) or "(its probe" in (rows[1].failure or ""), name
        assert all(c.failure_kind == NOT_RUN for c in rows if c.failure_kind != "timeout"), name
    assert cut.seconds_saved() == sum(c.budget for c in cut.not_run()) > 0
    stuck = [c for c in cut.not_run() if c.id.startswith("stuck/F<f/")]
    assert stuck and all("(its probe start" in c.failure for c in stuck)       # the 6th scene: a probe
    kinds = cut.kinds()
    assert kinds["sticking"]["not_run"] > 0 and kinds["sticking"]["failures"] == kinds["sticking"]["timeouts"]
    md, data = cut.to_markdown(), json.loads(cut.to_json())
    assert "Not run (the per-kind cut-off" in md and f"{cut.seconds_saved():.0f} s saved" in md
    assert data["not_run"] == len(cut.not_run())
    assert data["kinds"]["sticking"]["not_run"] == kinds["sticking"]["not_run"]
    assert data["budget"]["kind_timeouts"] == 2 and data["budget"]["short_budget"] == runner.BUDGET_FLOOR


def test_an_integrator_that_never_hangs_is_scored_as_without_the_cutoff(monkeypatch):
    cut, run = virtual_card(frozenset(), monkeypatch)
    full, run0 = virtual_card(frozenset(), monkeypatch, kind_timeouts=0, budget_multiple=0)
    assert [vars(c) for c in cut.cases] == [vars(c) for c in full.cases]
    assert run.calls == run0.calls
    assert cut.budget["short_budget"] is None and not cut.not_run()


@settings(max_examples=12, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1), share=st.floats(0.0, 1.0), k=st.integers(1, 3),
       floor=st.sampled_from([0.1, 0.5]))
def test_on_random_hangs_the_flagged_kinds_are_those_without_the_cutoff(seed, share, k, floor):
    """Any set of hanging starts -- every sticking start with probability ``share``, any other with
    ``share / 4`` -- and of slow but correct ones (any other, probability 1/4: ``SLOW``, above the
    short budget ``max(floor, 20 x STEP)``): no kind has more than K timeouts in a scene, the time
    charged stays within the promise, and the flagged kinds and every start that ran agree with a
    run where every start runs with the cap."""
    rng = np.random.default_rng(seed)
    hangs = frozenset(c.id for c in ALL if rng.random() < (share if sticks(c) else share / 4))
    slow = frozenset(c.id for c in ALL if c.id not in hangs and rng.random() < 0.25)
    with pytest.MonkeyPatch.context() as mp:
        cut, run = virtual_card(hangs, mp, slow, kind_timeouts=k, budget_floor=floor)
        full, run0 = virtual_card(hangs, mp, slow, kind_timeouts=0, budget_multiple=0)
    assert cut.flagged() == full.flagged()
    skipped = {c.id for c in cut.not_run()}
    assert all(c.failure_kind in ("timeout", NOT_RUN) for c in cut.cases if c.id in hangs)
    assert all(c.failure is None for c in full.cases if c.id in slow)
    failed = {c.kind for c in cut.cases if c.failure and not c.band}
    assert all(c.failure is None for c in cut.cases if c.id in slow and c.kind not in failed and not c.band)
    assert [(c.id, c.digits) for c in cut.cases if c.id not in skipped and c.failure_kind != "timeout"] == \
        [(c.id, c.digits) for c in full.cases if c.id not in skipped and c.id not in {t.id for t in cut.timeouts()}]
    for name in SCENES:
        rows = [c for c in cut.cases if c.id.startswith(name + "/") and not c.band]
        for kind in {c.kind for c in rows}:
            assert sum(c.failure_kind == "timeout" for c in rows if c.kind == kind) <= k, (name, kind)
    assert run.clock <= promise(hangs, k) + SLOW * len(slow)


# --- real runs: the naive solve_ivp integrator, in a worker process -----------------------------
def test_the_naive_integrator_stops_a_kind_after_k_timeouts():
    """Two sticking scenes (every start sticks but one, in the band) at a 1 s cap: sticking is cut
    after K = 2 timeouts in each, and the run takes at most what the cut-off promises -- per scene
    K budgets for each kind and for the band, one batch -- plus a second per worker restart and
    ``SLACK`` for the warm-up, timed from the first scene on (the worker's start-up apart).
    Without the cut-off it takes 23 budgets and as many restarts (seen by hand)."""
    scenes, cap, k = ["stuck/F<f", "stuck/F=f"], 1.0, 2
    started = []
    t0 = time.perf_counter()
    card = score("adapters_for_tests:NAIVE", scenes=scenes, periods=(1,), case_timeout=cap,
                 progress=lambda m: started or started.append(time.perf_counter()))
    took = time.perf_counter() - started[0]
    budgets = sum(k * len({c.kind if not c.band else BAND for c in scene_cases(n)}) + 1 for n in scenes)
    assert took < budgets * (cap + RESTART) + SLACK, (took, budgets, time.perf_counter() - t0)
    assert card.flagged() == ["sticking"]
    for name in scenes:
        rows = [c for c in card.cases if c.id.startswith(name + "/") and c.kind == "sticking"]
        assert sum(c.failure_kind == "timeout" for c in rows) == k, name
        assert {c.failure for c in rows if c.failure_kind != "timeout"} == \
            {f"{NOT_RUN}: kind sticking timed out 2 times in this scene"}, name
    assert card.budget["restarts"] <= budgets


@pytest.mark.slow
def test_the_naive_integrators_flagged_kinds_are_those_without_the_cutoff():
    """The same two scenes with every start run (``kind_timeouts=0``): the same kinds flagged."""
    scenes = ["stuck/F<f", "stuck/F=f"]
    cut = score("adapters_for_tests:NAIVE", scenes=scenes, periods=(1,), case_timeout=1.0)
    full = score("adapters_for_tests:NAIVE", scenes=scenes, periods=(1,), case_timeout=1.0, kind_timeouts=0,
                 budget_multiple=0)
    assert cut.flagged() == full.flagged() and not full.not_run()
    assert len(full.timeouts()) > len(cut.timeouts()) + 10 and len(cut.not_run()) >= 10


def test_a_slow_but_correct_kind_is_never_cut():
    """``SLOW_CHATTER``: the golden answer, 0.8 s on chatter starts (just under the 1 s cap, 80 times
    its median start of 10 ms) and a hang on sticking starts.  Its sticking start hangs before its
    chatter start runs; then the short budget is max(floor 0.1 s, 20 x 10 ms) = 0.2 s, far below the
    chatter start's time -- but a graded start of a kind without a failure keeps the cap: chatter
    passes, only sticking is flagged."""
    card = score("adapters_for_tests:SLOW_CHATTER", scenes=["fig:many:wide/f=0.2"], periods=(1,), case_timeout=1.0,
                 budget_floor=0.1)
    assert card.flagged() == ["sticking"]
    (chatter,) = [c for c in card.cases if c.kind == "chatter"]
    assert chatter.failure is None and chatter.digits > 15
    assert card.budget["short_budget"] is not None and card.budget["short_budget"] < 0.8
    assert card.budget["median_seconds"] < 0.8 / runner.BUDGET_MULTIPLE


def test_cli_kind_timeouts_and_budget_options(tmp_path, capsys):
    for bad in (["--kind-timeouts", "-1"], ["--kind-timeouts", "x"], ["--budget-floor", "0"],
                ["--budget-multiple", "-2"]):
        assert cli.main(["score", "fast", "--scenes", "fig:narrow", "--out", str(tmp_path)] + bad) == 2, bad
        err = capsys.readouterr().err
        assert "Traceback" not in err and err.count("\n") == 1, err


# --- the pytest plugin: --golden-kind-timeouts ---------------------------------------------------
USER_TESTS = """
import numpy as np
from adapters_for_tests import sticky_in_c

STICKY = sticky_in_c()      # the golden answer, but one C call that never returns on sticking starts


def test_mine(golden_case):
    x, v = STICKY.step(golden_case.params, np.array([golden_case.x]), np.array([golden_case.v]), 1)
    golden_case.assert_close(x[0], v[0])
"""


def test_the_plugin_fails_a_kind_after_k_timeouts_without_running_it(pytester):
    """fig:many:wide/f=0.4 has 7 sticking cases: 2 time out (0.5 s each), the 5 after them fail at
    once with the reason -- a failure, not a silent skip -- and the session ends in a few budgets."""
    pytester.makepyfile(test_user=USER_TESTS)
    t0 = time.perf_counter()
    result = pytester.runpytest("--golden-scenes", "fig:many:wide/f=0.4", "--golden-kinds", "sticking",
                                "--golden-timeout", "0.5", "-p", "no:cacheprovider")
    took = time.perf_counter() - t0
    result.assert_outcomes(failed=7)
    result.stdout.fnmatch_lines(["*fig:many:wide/f=0.4/sample-4 [[]sticking[]]: not run: kind sticking timed out 2 "
                                 "times in this scene*"])
    # count the failure reports, not the short summary (which pytest truncates to the terminal's width
    # except under CI=1, so it holds the phrase 0 or 2 more times)
    reports = [line for line in result.stdout.lines if not line.startswith("FAILED ")]
    assert sum("timeout: no result within 0.5 s" in line for line in reports) == 2
    assert took < 2 * (0.5 + RESTART) + SLACK + 20, took     # 20 s: the session's worker start-up
