"""``python -m cross_check verify SCENES.toml [--scene "..."] [--out DIR] [--workers K | --scheduler ADDR] [--quick]``.

The whole V&V of the suite on the user's scenes (``cross_check.scenefile``): per scene the
states and hard cases, the golden data with proofs, fast against the reference, the periodic
orbits proved, a portrait and two scorecards (``verify.tasks``), then one ``report.md``
(``verify.document``).  Everything runs as Dask tasks -- per scene: the states, the golden data
in chunks of states, the agreement, one orbit search per period, the portrait, a scorecard per
adapter -- on a ``LocalCluster`` of ``--workers`` processes, or on a running cluster
(``--scheduler tcp://HOST:8786``; the same code path, as for the atlas).  Results are gathered by
key, so the files do not depend on the number of workers or the completion order; a line of
progress per finished task goes to stderr.

Writes into ``--out`` (default ``verify/``): ``report.md``; ``golden/<scene>.json`` (the format
of the shipped golden data: ``score --golden-dir``, ``prove --golden --golden-dir`` and
``pytest --golden-dir`` read it as it is); ``scenes/<scene>/portrait.png`` and
``scenes/<scene>/scorecard-{fast,scipy}.{md,json}``.

Exit status: 0 when every check of every scene holds (golden self-agreement on every sample
state, every golden input proved, fast's itinerary equal to the reference's outside the
near-grazing band, no kind flagged on fast's scorecard); 1 when one fails (the report's summary
says which); 2 on bad input (a scene file with a mistake: the message names the file, the scene
and the field).
"""
from __future__ import annotations

import pathlib
import sys
import time
import uuid

from cross_check import cluster, outputs, scenefile, scenes
from cross_check.progress import Progress

# ``golden``, ``verify.tasks`` and ``verify.document`` (mpmath, flint, scipy, matplotlib: about a
# second of imports) are imported where they are used, after the scene files are read: a file with
# a mistake, or a hostile value, is refused with exit 2 at once.

ADAPTERS = ("fast", "scipy")
RETRIES = 1
#: what a local cluster's fork server imports for verify's workers besides ``cluster.PRELOAD``:
#: the tasks and every room they reach (``cluster._forked_workers``)
PRELOAD = ("cross_check.verify.tasks",)


def _timed(fn, *args):
    """Run a task, returning ``(result, CPU seconds)``: what each scene costs its workers, whatever
    else the machine runs (a worker has one thread of work, so its process time is the task's)."""
    t0 = time.process_time()
    out = fn(*args)
    return out, time.process_time() - t0


def _result(value):
    return value[0]


class _Run:
    """The futures of one verify run, keyed by ``(scene, what)``, and their progress."""

    def __init__(self, client, progress):
        self.client, self.progress = client, progress
        self.tag = uuid.uuid4().hex[:8]
        self.futures = {}
        self.t0 = time.perf_counter()

    def submit(self, name, what, fn, *args, priority=0):
        key = f"verify-{self.tag}-{scenes.slug(name)}-{what}"
        fut = self.client.submit(_timed, fn, *args, key=key, retries=RETRIES, pure=False, priority=priority)
        self.futures[(name, what)] = fut
        return fut

    def value(self, name, what):
        """A future of the task's result without its timing (for a dependent task)."""
        return self.client.submit(_result, self.futures[(name, what)], key=f"verify-{self.tag}-{scenes.slug(name)}"
                                  f"-{what}-value", pure=False)

    def gather(self, pairs=None):
        """Wait for the futures (all, or those of ``pairs``); ``{(scene, what): (result, seconds)
        or exception}`` and a progress line per finished task."""
        want = {self.futures[p]: p for p in (pairs or list(self.futures))}
        out = {}
        for done, fut, eta in cluster.as_done(want):
            where = want[fut]
            try:
                out[where] = fut.result()
            except Exception as exc:  # noqa: BLE001 -- a failed task is reported, the rest goes on
                out[where] = exc
            self.progress(f"verify: task {done}/{len(want)} ({where[0]}: {where[1]}"
                          f"{', FAILED' if isinstance(out[where], Exception) else ''}), ETA {eta:.0f} s")
        return out


def _first_of_each_engine(records) -> dict:
    """``{scene: record}``: the first scene of each of ``fast``'s engines (position forcing or
    not), whose ``kernels`` task compiles that engine for every scene (``tasks.kernels``)."""
    first = {}
    for rec in records:
        first.setdefault(rec.get("wavenumber") is not None, rec)
    return {rec["name"]: rec for rec in first.values()}


def compute(records, depth, *, scheduler=None, workers=2, progress=None, client=None) -> dict:
    """Every task of every scene; ``{scene: {what: (result, seconds) or exception}}`` and the wall time.

    ``client``: an existing ``distributed.Client`` (tests); else one made by ``cluster.client``."""
    from cross_check.verify import tasks

    progress = progress or (lambda msg: None)
    with cluster.client(scheduler, workers, given=client, preload=PRELOAD) as cl:
        run = _Run(cl, progress)
        for rec in records:
            run.submit(rec["name"], "states", tasks.states, rec, depth)
        for name, rec in _first_of_each_engine(records).items():
            run.submit(name, "kernels", tasks.kernels, rec)
        states = run.gather()
        for rec in records:
            name = rec["name"]
            got = states[(name, "states")]
            if isinstance(got, Exception):
                continue
            chunks = tasks.golden_chunks(got[0]["cases"])
            for j, chunk in enumerate(chunks):     # the golden data first: the scorecards wait for it
                run.submit(name, f"golden {j + 1}/{len(chunks)}", tasks.golden_entries, rec, chunk, priority=1)
            parts = [run.value(name, f"golden {j + 1}/{len(chunks)}") for j in range(len(chunks))]
            run.submit(name, "golden file", tasks.golden_document, rec, parts, depth)
            doc = run.value(name, "golden file")
            run.submit(name, "scorecards", tasks.scorecards, rec, doc, ADAPTERS, depth)
            run.submit(name, "agreement", tasks.agreement, rec, doc, got[0]["cases"], depth)
            for k in depth.periods:
                run.submit(name, f"orbits {k}", tasks.orbits, rec, k, depth)
            run.submit(name, "portrait", tasks.portrait, rec,
                       [run.value(name, f"orbits {k}") for k in depth.periods], depth)
        rest = run.gather([p for p in run.futures if p[1] != "states"])
        n_workers = len(cl.scheduler_info()["workers"])
    out = {rec["name"]: {} for rec in records}
    for (name, what), value in {**states, **rest}.items():
        if what != "scorecards":
            out[name][what] = value
            continue
        for adapter in ADAPTERS:          # one task, one result (and its own CPU seconds) per adapter
            out[name][f"scorecard {adapter}"] = value if isinstance(value, Exception) else value[0][adapter]
    return {"scenes": out, "seconds": time.perf_counter() - run.t0, "workers": n_workers}


def write(out_dir, records, results, depth) -> tuple[pathlib.Path, list]:
    """Golden files, portraits, scorecards and ``report.md``; returns the report's path and the
    failed checks (``[(scene, check)]``)."""
    from cross_check import golden
    from cross_check.verify import document

    out = pathlib.Path(out_dir)
    (out / "golden").mkdir(parents=True, exist_ok=True)
    for rec in records:
        name, got = rec["name"], results["scenes"][rec["name"]]
        here = out / "scenes" / scenes.slug(name)
        here.mkdir(parents=True, exist_ok=True)
        doc = got.get("golden file")
        if doc is not None and not isinstance(doc, Exception):
            (out / "golden" / (scenes.slug(name) + ".json")).write_text(golden.dumps(doc[0]["document"]))
        pic = got.get("portrait")
        if pic is not None and not isinstance(pic, Exception):
            (here / "portrait.png").write_bytes(pic[0])
        for adapter in ADAPTERS:
            card = got.get(f"scorecard {adapter}")
            if card is not None and not isinstance(card, Exception):
                (here / f"scorecard-{adapter}.md").write_text(card[0]["markdown"])
                (here / f"scorecard-{adapter}.json").write_text(card[0]["json"])
    text, failed = document.render(records, results, depth)
    path = out / "report.md"
    path.write_text(text)
    return path, failed


def main(argv=None) -> int:
    """CLI entry (module docstring)."""
    import argparse

    parser = argparse.ArgumentParser(
        prog="python -m cross_check verify",
        description="The whole V&V on your scenes: golden data with proofs, hard cases, fast vs reference, "
                    "periodic orbits proved, a portrait and scorecards, one report.md.  Exit 0: every check "
                    "holds; 1: a check failed (the report says which); 2: bad input.",
        epilog="Scene files: TOML, one [[scene]] table per scene with name, F, f, omega, l, r and optionally "
               "restitution, damping, wavenumber; values numbers or exact strings ('0.8', '2*pi').  Example: "
               "cross_check/data/scenes/example.toml.  --quick: 4 sample states instead of 8, period-1 orbits "
               "only (a 10 x 10 seed grid, at most 8 proofs), no 10-period comparisons or scores, fast against "
               "the reference on the samples only (fast's scorecard still grades every hard case against its "
               "golden record), a coarser portrait.")
    parser.add_argument("files", nargs="*", metavar="SCENES.toml", help="scene files (cross_check.scenefile)")
    parser.add_argument("--scene", action="append", default=[], dest="inline_scene",
                        metavar='"F=1 f=0.3 omega=1 l=0 r=3"', help="one scene inline (optional name=...); repeatable")
    parser.add_argument("--out", default="verify", type=outputs.check_folder, help="output directory (default: verify/)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, default=2, help="local worker processes (default 2)")
    where.add_argument("--scheduler", default=None, help="tcp://HOST:PORT of a running dask scheduler")
    parser.add_argument("--quick", action="store_true", help="a smaller run (see below), under 15 s a scene")
    args = parser.parse_args(argv)
    if not 1 <= args.workers <= cluster.MAX_WORKERS:
        parser.error(f"--workers must be in [1, {cluster.MAX_WORKERS}]")
    try:
        import fast

        found = scenefile.collect(args.files, args.inline_scene, check=fast.validate_scene)
    except scenefile.SceneFileError as exc:
        print(f"verify: {exc}", file=sys.stderr)
        return 2
    if not found:
        parser.error("give a scene file or --scene \"F=... f=... omega=... l=... r=...\"")
    scenefile.register_all(found)
    from cross_check import golden
    from cross_check.verify import tasks

    records = [golden.scene_record(sc) for sc in found]
    depth = tasks.QUICK if args.quick else tasks.FULL
    progress = Progress()
    try:
        results = compute(records, depth, scheduler=args.scheduler, workers=args.workers, progress=progress)
    except cluster.ClusterError as exc:
        print(f"verify: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"verify: cannot reach or start the Dask cluster: {exc}", file=sys.stderr)
        return 2
    path, failed = write(args.out, records, results, depth)
    progress(f"wrote {path}" + (f": {len(failed)} check(s) FAILED" if failed else ": every check holds"))
    print(path)
    return 1 if failed else 0
