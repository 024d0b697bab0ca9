"""Fail fast per kind (issue 37): a kind that keeps running out of time costs a few budgets, not one
budget per start.

An integrator that cannot handle a regime (a smooth solver with ``f sgn(v)`` in its right-hand
side, on sticking) runs out of time on *every* start of that kind; after two such starts the
scorecard has learnt all it will learn.  So:

* **within a scene**: after ``kind_timeouts`` (K, default 2; 0 switches the cut-off off) timeouts
  on *graded* starts (outside the near-grazing band) of one kind, the scene's remaining starts of
  that kind are *not run*.  Each is a failure of failure kind ``not run`` with the reason
  ``not run: kind KIND timed out N times in this scene``; the scorecard counts them apart from
  real failures (``sheet``) and adds up the time saved (the starts not run times their budget);
* **across scenes**: a kind cut in ``SCENES_RUNNING`` (3) scenes running -- consecutive scenes with
  graded starts of that kind; scenes without it neither continue nor break the run; a scene
  where every graded start of it that ran timed out counts as cut (it may hold fewer than K) --
  is *suspect*: in each later scene its first graded start is a probe, run alone before the others
  (``runner.run_starts``), and if the probe times out the kind's other starts in that scene are
  not run.  A scene where the kind is not cut ends the run of scenes (the probe passed and fewer
  than K timeouts followed): the kind is trusted again.

Starts in the near-grazing band are never graded; their timeouts count apart, under ``BAND`` (the
band of a scene is cut after K of them, with probes as for a kind), and they are cut with their
kind too.  A caller may count other ungraded calls as a kind of their own (the scorer's
ten-period calls: ``card.TEN``).

**Why the flagged kinds never change.**  Only timeouts of graded starts count for a kind, and a
timeout of a graded start is a failure that flags its kind (``sheet``: any failure grades F).  A
kind is therefore cut only once it is flagged already, and a start not run only adds a failure to
a kind that is flagged anyway; a band start is not graded either way.  A correct integrator -- no
timeouts -- is never cut, so its card is the same start for start.

The scorer (``card``) keeps one ``KindCutoff`` per run and the pytest plugin one per test
function; each scene gets a ``SceneCut`` (``KindCutoff.scene``), closed when the scene ends.
This module is light (standard library only): the plugin and the worker side import it.
"""
from __future__ import annotations

import argparse
import collections

#: timeouts of graded starts of one kind in one scene after which the kind's other starts there
#: are not run (``score --kind-timeouts``, the plugin's ``--golden-kind-timeouts``; 0: off)
KIND_TIMEOUTS = 2
#: scenes running in which a kind was cut, after which it gets one probe start per later scene
SCENES_RUNNING = 3
#: the failure kind of a start that was not run
NOT_RUN = "not run"
#: what starts in the near-grazing band count under (never graded, so cut apart from their kinds)
BAND = "near-grazing band"


def kind_timeouts_arg(text) -> int:
    """A command-line ``K``: an integer >= 0 (else argparse's error naming the option, exit 2)."""
    try:
        value = int(text)
    except ValueError:
        value = -1
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be an integer >= 0 (0: no cut-off), got {text!r}")
    return value


def _key(kind: str, graded: bool) -> str:
    """What a start counts under: its kind, or ``BAND`` for a start in the band."""
    return kind if graded else BAND


class SceneCut:
    """The cut-off's state in one scene: timeouts per kind, the kinds cut (with why), the probes."""

    def __init__(self, owner: "KindCutoff", name: str, kinds=()):
        self.owner, self.name = owner, name
        self.kinds = {_key(k, graded) for k, graded in kinds if k is not None}   # kinds with starts here
        self.timeouts = collections.Counter()
        self.completed: set[str] = set()         # kinds with a start run in time
        self.cut: dict[str, str] = {}
        self.probed: set[str] = set()

    def reason(self, kind: str, graded: bool = True) -> str | None:
        """Why a start of ``kind`` (``graded``: outside the band) is not run in this scene, or
        ``None``: run it.  A band start is cut with its kind, or with the band."""
        return self.cut.get(kind) or (None if graded else self.cut.get(BAND))

    def is_probe(self, kind: str, graded: bool = True) -> bool:
        """Whether a start of ``kind`` is the probe of a suspect kind (or of the band), still to run
        in this scene."""
        key = _key(kind, graded)
        return (kind is not None and self.owner.suspect(key) and key not in self.probed
                and self.reason(kind, graded) is None)

    def record(self, kind: str, graded: bool, timed_out: bool) -> None:
        """Note the outcome of a start of ``kind`` that was run; cut the kind (or the band) when the
        count is reached: K timeouts, or the probe's timeout for a suspect kind."""
        if not (self.owner.kind_timeouts > 0 and kind is not None):
            return
        key = _key(kind, graded)
        self.kinds.add(key)
        probe = self.owner.suspect(key) and key not in self.probed
        self.probed.add(key)
        if not timed_out:
            self.completed.add(key)
            return
        if key in self.cut:
            return
        self.timeouts[key] += 1
        n = self.timeouts[key]
        what = f"kind {kind}" if graded else f"the band ({BAND} starts, any kind)"
        times = f"{n} time{'s' * (n != 1)}"
        if n >= self.owner.kind_timeouts:
            self.cut[key] = f"{NOT_RUN}: {what} timed out {times} in this scene"
        elif probe:
            self.cut[key] = (f"{NOT_RUN}: {what} timed out {times} in this scene (its probe start; it was "
                             f"cut in {self.owner.scenes_running} scenes running before)")

    def close(self) -> None:
        """The scene is done: each of its kinds continues its run of scenes -- it was cut here, or
        every start of it that ran timed out (a scene with fewer than K of them cannot reach the
        count) -- or ends it."""
        for key in self.kinds:
            kept_failing = key in self.cut or (self.timeouts[key] and key not in self.completed)
            self.owner.streak[key] = self.owner.streak[key] + 1 if kept_failing else 0


class KindCutoff:
    """The per-kind cut-off of one run (module docstring): ``kind_timeouts`` K (0: off) and
    ``scenes_running``."""

    def __init__(self, kind_timeouts: int = KIND_TIMEOUTS, scenes_running: int = SCENES_RUNNING):
        for name, value, low in (("kind_timeouts", kind_timeouts, 0), ("scenes_running", scenes_running, 1)):
            if isinstance(value, bool) or not isinstance(value, int) or value < low:
                raise ValueError(f"{name} must be an integer >= {low}, got {value!r}")
        self.kind_timeouts, self.scenes_running = kind_timeouts, scenes_running
        self.streak: collections.Counter = collections.Counter()

    def suspect(self, kind: str) -> bool:
        """Whether ``kind`` was cut in ``scenes_running`` scenes running (it gets a probe)."""
        return self.kind_timeouts > 0 and self.streak[kind] >= self.scenes_running

    def scene(self, name: str, kinds=()) -> SceneCut:
        """The cut-off of the scene ``name``; ``kinds``: ``(kind, graded)`` of each of its starts (those
        not given are added as they are run)."""
        return SceneCut(self, name, kinds)


__all__ = ["BAND", "KIND_TIMEOUTS", "KindCutoff", "NOT_RUN", "SCENES_RUNNING", "SceneCut", "kind_timeouts_arg"]
