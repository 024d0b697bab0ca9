"""The atlas on Dask: a grid of parameter points, cut into chunks, computed on a cluster,
gathered in grid order.

``python -m cross_check atlas [--claim ID ...] [--grid N] [--scheduler ADDRESS] [--workers K]
[--out DIR]``.  The grid is ``N x N`` cell-centred points of ``f/F`` in ``(0, 1)`` (plus the
column ``f = 0``, where the frictionless closed forms hold) and of ``w^2 R/F`` in ``[0.5, 100]``
(log-spaced: the paper's scenes sit at 0.8 ... 79).  A task is a chunk of ``CHUNK`` points
(every listed claim at each); ``dask.distributed`` runs them: by default on a ``LocalCluster`` of
``--workers`` processes started here, or on an existing cluster with ``--scheduler
tcp://HOST:PORT`` (the same code path; start one with ``dask scheduler`` and ``dask worker
tcp://HOST:8786`` on each machine).  Results are put back by chunk index, so the output is the
same for any number of workers and any completion order; a worker that dies loses nothing
(dask recomputes its chunks elsewhere, ``retries`` covers a chunk lost mid-run).  Progress: a
line per completed chunk with the rate and an ETA.
"""
from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass

import numpy as np

from cross_check.atlas import claims as C

CHUNK = 32
R_RANGE = (0.5, 100.0)
RETRIES = 3


@dataclass(frozen=True)
class Grid:
    """``f/F`` values (first 0, then ``n`` cell centres of ``(0, 1)``) and ``w^2 R/F`` values."""

    n: int

    @property
    def fF(self):
        return np.concatenate([[0.0], (np.arange(self.n) + 0.5) / self.n])

    @property
    def R(self):
        lo, hi = (math.log10(r) for r in R_RANGE)
        return 10.0 ** (lo + (np.arange(self.n) + 0.5) / self.n * (hi - lo))

    def points(self):
        """``(i, j, f/F, R)`` in row-major order (``i`` over ``R``, ``j`` over ``f/F``)."""
        return [(i, j, float(f), float(r)) for i, r in enumerate(self.R) for j, f in enumerate(self.fF)]


def evaluate_chunk(points, claims):
    """One task: every claim at every point of the chunk (runs on a worker)."""
    return [(i, j, {c: C.CLAIMS[c](f, r) for c in claims}) for i, j, f, r in points]


def _chunks(grid, size):
    pts = grid.points()
    return [pts[k:k + size] for k in range(0, len(pts), size)]


def compute(claims, n, *, scheduler=None, workers=2, chunk=CHUNK, progress=None, client=None):
    """The atlas values ``{claim: [[value per f/F] per R]}`` and the run's ``stats``.

    ``client``: an existing ``distributed.Client`` (tests), else one on ``scheduler`` or on a new
    ``LocalCluster(n_workers=workers, threads_per_worker=1)``."""
    unknown = [c for c in claims if c not in C.CLAIMS]
    if unknown:
        raise ValueError(f"unknown atlas claim(s) {unknown}; known: {', '.join(C.CLAIMS)}")
    if not (isinstance(n, int) and 2 <= n <= 512):
        raise ValueError(f"grid must be an int in [2, 512], got {n!r}")
    if not (isinstance(workers, int) and 1 <= workers <= 256):
        raise ValueError(f"workers must be an int in [1, 256], got {workers!r}")
    try:
        from distributed import Client, LocalCluster, as_completed
    except ModuleNotFoundError as exc:
        raise ValueError("the atlas needs dask.distributed: python -m pip install -e '.[atlas]'") from exc

    grid = Grid(n)
    own = client is None
    cluster = None
    if own:
        if scheduler:
            client = Client(scheduler)
        else:
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                   dashboard_address=":0")
            client = Client(cluster)
    try:
        chunks = _chunks(grid, chunk)
        t0 = time.perf_counter()
        futures = {client.submit(evaluate_chunk, pts, tuple(claims), key=f"atlas-{k}-{n}-{'+'.join(claims)}",
                                 retries=RETRIES, pure=False): k for k, pts in enumerate(chunks)}
        results = [None] * len(chunks)
        for done, fut in enumerate(as_completed(futures), 1):
            results[futures[fut]] = fut.result()
            if progress:
                rate = done * chunk / (time.perf_counter() - t0)
                eta = (len(chunks) - done) * chunk / rate
                progress(f"atlas: chunk {done}/{len(chunks)}, {rate:.1f} points/s, ETA {eta:.0f} s")
        seconds = time.perf_counter() - t0
        n_workers = len(client.scheduler_info()["workers"])
    finally:
        if own:
            client.close()
            if cluster is not None:
                cluster.close()
    values = {c: [[None] * len(grid.fF) for _ in grid.R] for c in claims}
    for chunk_out in results:
        for i, j, vals in chunk_out:
            for c in claims:
                values[c][i][j] = vals[c]
    stats = {"seconds": seconds, "points": len(grid.points()), "workers": n_workers,
             "points_per_second": len(grid.points()) / seconds}
    return grid, values, stats


def provenance(grid, claims, stats) -> dict:
    import platform

    import dask
    import distributed
    import mpmath
    import numba

    return {"generator": "python -m cross_check atlas", "claims": list(claims), "grid": grid.n,
            "scene": "F = 1, f = f/F, omega = 1, l = 0, r = w^2 R/F (dimensionless)",
            "f_over_F": "0 then (j + 1/2)/n, j < n", "w2R_over_F": f"log-spaced cell centres of {list(R_RANGE)}",
            "versions": {"python": platform.python_version(), "numpy": np.__version__, "numba": numba.__version__,
                         "mpmath": mpmath.__version__, "dask": dask.__version__,
                         "distributed": distributed.__version__}}


def write(out_dir, grid, values, stats, claims) -> dict:
    """``atlas.json`` (grid, values, boundaries, provenance; no timings, so reruns are identical),
    ``atlas_stats.json`` (timings) and one PNG per claim; returns the boundary table."""
    import json
    import pathlib

    from cross_check.atlas import maps

    out = pathlib.Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    bounds = {k: {"worst_cells": v[0], "lines": v[1]} for k, v in maps.boundaries(grid, values).items()}
    data = {"provenance": provenance(grid, claims, stats), "f_over_F": grid.fF.tolist(),
            "w2R_over_F": grid.R.tolist(), "values": values, "boundaries": bounds}
    (out / "atlas.json").write_text(json.dumps(data, indent=None, sort_keys=False, default=float) + "\n")
    (out / "atlas_stats.json").write_text(json.dumps(stats, indent=1) + "\n")
    maps.draw(grid, values, str(out))
    return bounds


def main(argv=None) -> int:
    """``python -m cross_check atlas [--claim ID ...] [--grid N] [--scheduler ADDRESS] [--workers K] [--out DIR]``."""
    import argparse

    parser = argparse.ArgumentParser(
        prog="python -m cross_check atlas",
        description="Where each claim holds: the claims evaluated on an N x N grid of (f/F, w^2 R/F) with "
                    "fast, violations confirmed by the reference, on Dask (a local cluster by default).  "
                    "Writes atlas.json and one PNG per claim with the closed-form boundaries.")
    parser.add_argument("--claim", nargs="+", choices=list(C.CLAIMS), default=list(C.CLAIMS),
                        help="claims to map (default: all)")
    parser.add_argument("--grid", type=int, default=64, help="N: the grid is N x N (+ the f = 0 column); default 64")
    parser.add_argument("--scheduler", default=None, help="tcp://HOST:PORT of a running dask scheduler")
    parser.add_argument("--workers", type=int, default=2, help="local worker processes (default 2)")
    parser.add_argument("--out", default="atlas", help="output directory (default: atlas/)")
    args = parser.parse_args(argv)
    t0 = time.perf_counter()
    try:
        grid, values, stats = compute(args.claim, args.grid, scheduler=args.scheduler, workers=args.workers,
                                      progress=lambda m: print(f"[{time.perf_counter() - t0:6.1f}s] {m}",
                                                               file=sys.stderr, flush=True))
    except ValueError as exc:
        print(f"atlas: {exc}", file=sys.stderr)
        return 2
    bounds = write(args.out, grid, values, stats, args.claim)
    for name, b in bounds.items():
        worst = "n/a" if b["worst_cells"] is None else f"{b['worst_cells']:.2f}"
        print(f"{name}: computed switch within {worst} grid cells ({b['lines']} lines)", file=sys.stderr)
    print(f"{args.out}/atlas.json")
    return 0
