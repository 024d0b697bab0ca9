"""The atlas on Dask: a grid of parameter points, cut into square blocks, each block computed by
one task that writes it into the Zarr store (``cross_check.atlas.store``) as soon as it is done.

``python -m cross_check atlas [--claim ID ...] [--grid NF[xNR]] [--chunk C] [--scheduler ADDRESS]
[--workers K] [--out DIR]``.  The grid is ``NF`` cell centres of ``f/F`` in ``(0, 1)`` plus the
column ``f = 0`` (where the frictionless closed forms hold) by ``NR`` log-spaced cell centres of
``w^2 R/F`` in ``[0.5, 100]`` (the paper's scenes sit at 0.8 ... 79); ``--grid 256`` is
``256x256``, ``--grid 256x64`` has 256 ``f/F`` columns (+1) and 64 ``w^2 R/F`` rows.  A task is a
``C x C`` block of points (every listed claim at each), exactly one zarr chunk of every variable
(``C = CHUNK``, or less on a small grid: ``Grid.default_chunk``).
``dask.distributed`` runs the tasks: by default on a ``LocalCluster`` of ``--workers`` processes
started here, or on an existing cluster with ``--scheduler tcp://HOST:PORT`` (the same code path;
the workers write the store, so ``DIR`` must be on a file system they share).  Each task writes
its block, then the block's ``done`` markers.  Rerunning the same command on the same ``DIR``
skips the blocks already done (a run killed at any point loses only the blocks in flight) and
gives the same store as an uninterrupted run; a store made with another grid, chunk or claims is
refused (exit 2).  The values do not depend on the number of workers, the chunk or the
completion order; a worker that dies loses nothing (dask reruns its task elsewhere, ``RETRIES``).
Progress: a line per written block with the rate and an ETA.
"""
from __future__ import annotations

import math
import re
import sys
import time
import uuid
from dataclasses import dataclass, field

import numpy as np

from cross_check import cluster, outputs
from cross_check.atlas import claims as C
from cross_check.atlas import store
from cross_check.progress import Progress

CHUNK = 16
R_RANGE = (0.5, 100.0)
RETRIES = 3
GRID_MAX = 4096


@dataclass(frozen=True)
class Grid:
    """``nf`` cell centres of ``f/F`` in ``(0, 1)`` after the column ``f = 0`` (``nf + 1`` columns)
    by ``nr`` log-spaced ``w^2 R/F`` rows (``nr = nf`` if not given)."""

    nf: int
    nr: int = field(default=0)

    def __post_init__(self):
        if not self.nr:
            object.__setattr__(self, "nr", self.nf)
        for name, n in (("NF", self.nf), ("NR", self.nr)):
            if not (isinstance(n, (int, np.integer)) and not isinstance(n, bool) and 2 <= n <= GRID_MAX):
                raise ValueError(f"grid: {name} must be an int in [2, {GRID_MAX}], got {n!r}")

    @classmethod
    def parse(cls, text) -> "Grid":
        """``"N"`` (``N x N``) or ``"NFxNR"`` (``NF`` columns of ``f/F``, ``NR`` rows of ``w^2 R/F``)."""
        m = re.fullmatch(r"\s*(\d+)\s*(?:[xX]\s*(\d+))?\s*", str(text))
        if not m:
            raise ValueError(f"grid must be N or NFxNR (e.g. 64 or 256x64), got {text!r}")
        return cls(int(m.group(1)), int(m.group(2) or m.group(1)))

    @property
    def name(self) -> str:
        return f"{self.nf}x{self.nr}"

    @property
    def shape(self):
        """``(rows, columns)`` = ``(nr, nf + 1)``."""
        return self.nr, self.nf + 1

    @property
    def fF(self):
        return np.concatenate([[0.0], (np.arange(self.nf) + 0.5) / self.nf])

    @property
    def R(self):
        lo, hi = (math.log10(r) for r in R_RANGE)
        return 10.0 ** (lo + (np.arange(self.nr) + 0.5) / self.nr * (hi - lo))

    def default_chunk(self) -> int:
        """``CHUNK`` points per side, fewer on a small grid (at least 4 blocks along its shorter
        side, so that a few workers share it)."""
        return max(1, min(CHUNK, math.ceil(min(self.shape) / 4)))

    def blocks(self, chunk):
        """``[(k, rows, cols)]``: the ``chunk x chunk`` blocks (slices; the last ones are cut at the
        edge), row-major."""
        rows, cols = self.shape
        return [(k, slice(i, min(i + chunk, rows)), slice(j, min(j + chunk, cols)))
                for k, (i, j) in enumerate((i, j) for i in range(0, rows, chunk) for j in range(0, cols, chunk))]


def evaluate_block(grid, rows, cols, claims) -> dict:
    """Every claim at every point of one block: the store's variables as arrays of its shape."""
    fF, R = grid.fF, grid.R
    points = [[C.evaluate(float(fF[j]), float(R[i]), claims) for j in range(cols.start, cols.stop)]
              for i in range(rows.start, rows.stop)]
    return store.encode(claims, points)


def run_block(path, grid, k, rows, cols, claims):
    """One task (runs on a worker): compute the block, write it and its done markers; returns
    ``(k, points, seconds, cpu seconds)`` (the worker's CPU time: what the block costs on a
    machine it shares)."""
    t0, c0 = time.perf_counter(), time.process_time()
    store.write_block(path, rows, cols, evaluate_block(grid, rows, cols, claims))
    return (k, (rows.stop - rows.start) * (cols.stop - cols.start), time.perf_counter() - t0,
            time.process_time() - c0)


def check_args(claims, grid, workers, chunk):
    unknown = [c for c in claims if c not in C.CLAIMS]
    if unknown or not claims:
        raise ValueError(f"unknown atlas claim(s) {unknown}; known: {', '.join(C.CLAIMS)}")
    if not isinstance(grid, Grid):
        raise TypeError(f"grid must be a Grid (Grid.parse('64x32')), got {grid!r}")
    cluster.check_workers(workers)
    if not (isinstance(chunk, int) and 1 <= chunk <= 1024):
        raise ValueError(f"chunk must be an int in [1, 1024], got {chunk!r}")


def compute(claims, grid, out_dir, *, scheduler=None, workers=2, chunk=None, progress=None,
            client=None, command=None) -> dict:
    """Fill ``out_dir/atlas.zarr``, resuming it if it exists; returns the run's ``stats``.

    ``chunk``: points per side of a block (default ``grid.default_chunk()``); ``client``: an
    existing ``distributed.Client`` (tests), else one on ``scheduler`` or on a new
    ``LocalCluster(n_workers=workers, threads_per_worker=1)``.  Bad input, a store of another
    atlas or an unreachable scheduler: ``ValueError`` (before anything is written)."""
    import pathlib

    chunk = grid.default_chunk() if chunk is None and isinstance(grid, Grid) else chunk
    check_args(claims, grid, workers, chunk)
    claims = [c for c in C.CLAIMS if c in claims]           # one order: the store's identity
    try:
        import distributed  # noqa: F401
        import xarray  # noqa: F401
        import zarr  # noqa: F401
    except ModuleNotFoundError as exc:
        raise ValueError(f"the atlas needs {exc.name}: python -m pip install -e '.[atlas]'") from None
    path = store.locate(pathlib.Path(out_dir).resolve())
    existed = store.check(path, grid, claims, chunk)
    blocks = grid.blocks(chunk)
    done = store.done_blocks(path, blocks) if existed else set()
    say = progress or (lambda _msg: None)
    if done:
        ids = sorted(done)
        shown = ", ".join(map(str, ids[:40])) + (", ..." if len(ids) > 40 else "")
        say(f"atlas: resuming {path}: {len(done)} of {len(blocks)} chunks already written, skipped: {shown}")
    todo = [b for b in blocks if b[0] not in done]
    stats = {"chunks": len(blocks), "skipped": len(done), "computed": 0, "points": 0, "seconds": 0.0,
             "workers": 0, "task_seconds": 0.0, "task_cpu_seconds": 0.0}
    if not todo:
        return stats
    with cluster.client(scheduler, workers, given=client, preload=("cross_check.atlas",)) as client:
        path.parent.mkdir(parents=True, exist_ok=True)
        store.prepare(path, grid, claims, chunk, provenance(grid, claims, chunk, command))
        _run(client, path, grid, claims, todo, stats, say)
    stats["points_per_second"] = stats["points"] / stats["seconds"]
    stats["points_per_second_per_worker"] = stats["points"] / stats["task_seconds"]
    stats["points_per_cpu_second"] = stats["points"] / stats["task_cpu_seconds"]
    return stats


def _run(client, path, grid, claims, todo, stats, say):
    """Submit one task per block still to do, count them in as they complete (any order)."""
    t0 = time.perf_counter()
    token = uuid.uuid4().hex[:12]
    futures = {client.submit(run_block, str(path), grid, k, rows, cols, tuple(claims),
                             key=f"atlas-{token}-{k}", retries=RETRIES, pure=False):
               (rows.stop - rows.start) * (cols.stop - cols.start) for k, rows, cols in todo}
    for n, fut, eta in cluster.as_done(futures, futures):
        k, points, seconds, cpu = fut.result()
        stats["computed"] += 1
        stats["points"] += points
        stats["task_seconds"] += seconds
        stats["task_cpu_seconds"] += cpu
        say(f"atlas: chunk {k} written ({n}/{len(todo)}), "
            f"{stats['points'] / (time.perf_counter() - t0):.1f} points/s, ETA {eta:.0f} s")
    stats["seconds"] = time.perf_counter() - t0
    stats["workers"] = len(client.scheduler_info()["workers"])


def provenance(grid, claims, chunk, command=None) -> dict:
    import platform

    import dask
    import distributed
    import mpmath
    import numba
    import xarray
    import zarr

    if command is None:
        command = " ".join(["python -m cross_check atlas", "--grid", grid.name, "--chunk", str(chunk),
                            "--claim", *claims])
    return {"generator": "python -m cross_check atlas", "command": command,
            "grid_axes": "NFxNR: NF f/F cells (columns, after the f = 0 column) by NR w^2 R/F rows",
            "scene": "F = 1, f = f/F, omega = 1, l = 0, r = w^2 R/F (dimensionless)",
            "versions": {"python": platform.python_version(), "numpy": np.__version__, "numba": numba.__version__,
                         "mpmath": mpmath.__version__, "dask": dask.__version__,
                         "distributed": distributed.__version__, "xarray": xarray.__version__,
                         "zarr": zarr.__version__}}


def summarize(out_dir) -> dict:
    """From the store: ``atlas.json`` (the boundaries table and the counts; nothing run-specific)
    and one PNG per claim; returns the boundary table."""
    import json
    import pathlib

    from cross_check.atlas import maps

    ds = store.open_atlas(out_dir).load()
    out = pathlib.Path(out_dir)
    bounds = {k: {"worst_cells": v[0], "lines": v[1]} for k, v in maps.boundaries(ds).items()}
    data = {"store": store.NAME, "grid": ds.attrs["grid"], "claims": ds.attrs["claims"],
            "points": int(ds["done"].size), "counts": maps.counts(ds), "boundaries": bounds}
    (out / "atlas.json").write_text(json.dumps(data, indent=1) + "\n")
    maps.draw(ds, str(out))
    return bounds


def main(argv=None) -> int:
    """``python -m cross_check atlas`` (module docstring); exit 0, or 2 for bad input."""
    import argparse
    import json
    import pathlib

    parser = argparse.ArgumentParser(
        prog="python -m cross_check atlas",
        description="Where each claim holds: the claims evaluated on a grid of (f/F, w^2 R/F) with fast, "
                    "violations confirmed by the reference, on Dask (a local cluster by default).  Writes "
                    "DIR/atlas.zarr (an xarray Dataset, chunk by chunk; rerun the same command to resume a "
                    "stopped run), DIR/atlas.json (boundaries table, counts) and one PNG per claim.  "
                    "Exit status: 0 done, 2 bad input (or DIR holds another atlas).")
    parser.add_argument("--claim", nargs="+", choices=list(C.CLAIMS), default=list(C.CLAIMS),
                        help="claims to map (default: all)")
    parser.add_argument("--grid", default="64", help="N (an N x N grid) or NFxNR: NF f/F columns (plus f = 0) "
                        "by NR w^2 R/F rows, e.g. 256x64; default 64")
    parser.add_argument("--chunk", type=int, default=None, help=f"points per side of a task's block and "
                        f"of a zarr chunk (default {CHUNK}, fewer on grids smaller than {4 * CHUNK})")
    parser.add_argument("--scheduler", default=None, help="tcp://HOST:PORT of a running dask scheduler")
    parser.add_argument("--workers", type=int, default=2, help="local worker processes (default 2)")
    parser.add_argument("--out", default="atlas", type=outputs.check_folder, help="output directory (default: atlas/)")
    args = parser.parse_args(argv)
    log = Progress()
    try:
        grid = Grid.parse(args.grid)
        stats = compute(args.claim, grid, args.out, scheduler=args.scheduler, workers=args.workers,
                        chunk=args.chunk, progress=log)
    except ValueError as exc:
        print(f"atlas: {exc}", file=sys.stderr)
        return 2
    bounds = summarize(args.out)
    (pathlib.Path(args.out) / "atlas_stats.json").write_text(json.dumps(stats, indent=1) + "\n")
    for name, b in bounds.items():
        worst = "n/a" if b["worst_cells"] is None else f"{b['worst_cells']:.2f}"
        print(f"{name}: computed switch within {worst} grid cells ({b['lines']} lines)", file=sys.stderr)
    print(store.locate(args.out))
    return 0
