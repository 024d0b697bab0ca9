"""The atlas's store: one xarray Dataset in a chunked Zarr store, written chunk by chunk.

``DIR/atlas.zarr`` (Zarr format 2 with consolidated metadata, so any xarray or zarr reader opens
it: ``xarray.open_zarr("DIR/atlas.zarr")`` or ``open_atlas("DIR")``):

* dimensions ``w2R_over_F`` (rows) and ``f_over_F`` (columns), both coordinates; ``example``
  (``N_EXAMPLES``) for the stored counterexamples;
* one variable per quantity (``VARIABLES``), by kind:
  ``bool`` (always defined), ``tri`` (int8: 1 true, 0 false, -1 undefined, the ``_FillValue``,
  so xarray decodes it to a float 1/0/NaN), ``float`` (float64, NaN where undefined), ``count``
  (int16); each variable's attributes give its claim, meaning and how "undefined" is written;
* ``done`` (bool): True once the point's chunk is in the store, written only after the chunk's
  data (a chunk whose ``done`` is False is computed again: a crash loses at most the chunks in
  flight);
* provenance in the attributes (command, versions, grid, chunk, claims, date) -- ``date`` is
  the only run-specific one: a resumed store equals an uninterrupted run's in every value.

Every variable is chunked ``(chunk, chunk)`` over ``(w2R_over_F, f_over_F)`` and a task is one
such block of points, so a task writes whole zarr chunks that no other task touches: workers
write their regions concurrently without locks (zarr's local store writes each chunk to a
temporary file and renames it, so a chunk is never half written).
"""
from __future__ import annotations

import datetime
import os
import pathlib
import shutil

import numpy as np

#: the store's name inside the output directory
NAME = "atlas.zarr"
#: layout version of the store (a store of another version is refused, never mixed)
SCHEMA = 1
#: counterexamples of Omega_dissip's invariance kept per point
N_EXAMPLES = 3
DIMS = ("w2R_over_F", "f_over_F")

#: variable -> (claim, kind, meaning)
VARIABLES = {
    "x1": ("symmetric", "bool", "x1 exists as a non-sticking 2-impact fixed point of Phi (centre or "
           "parabolic), found by Newton from the closed form"),
    "x2": ("symmetric", "bool", "x2 exists as a non-sticking 2-impact fixed point of Phi (saddle or parabolic)"),
    "x1_trace": ("symmetric", "float", "trace of Phi' at x1 (NaN where x1 does not exist)"),
    "x2_trace": ("symmetric", "float", "trace of Phi' at x2 (NaN where x2 does not exist)"),
    "printed": ("symmetric", "tri", "the paper's printed non-sticking condition (eq. nonstick:cond) is > 0 "
                "(undefined beyond the fold f/F > 2/pi)"),
    "period1": ("subharmonic-islands", "bool", "a non-sticking elliptic symmetric period-1 centre, one round "
                "trip (2 impacts) per period, of either branch"),
    "period3": ("subharmonic-islands", "bool", "the same with period 3 (2 impacts in 3 periods)"),
    "period5": ("subharmonic-islands", "bool", "the same with period 5 (2 impacts in 5 periods)"),
    "no_impact": ("no-impact", "bool", "a start across the gap settles within 80 periods on a periodic "
                  "orbit without impacts"),
    "sticks": ("no-impact", "tri", "that no-impact orbit sticks (else it turns; undefined without one)"),
    "dissip_fraction": ("dissip-invariance", "float", "fraction of the Omega_dissip starts of a 6 x 6 grid "
                        "whose image leaves Omega_dissip (NaN for f = 0 or no such start)"),
    "dissip_starts": ("dissip-invariance", "count", "number of the 6 x 6 starts in Omega_dissip"),
    "dissip_confirmed": ("dissip-invariance", "tri", "the reference (30 digits) confirms the first "
                         "violation (undefined without one)"),
    "dissip_example_x": ("dissip-invariance", "examples", "x of up to 3 violating starts, exact float64 "
                         "(NaN pads)"),
    "dissip_example_v": ("dissip-invariance", "examples", "v of the same starts (NaN pads)"),
    "area_defect": ("area-preservation", "float", "max |det Phi' - 1| over the non-sticking starts of a "
                    "4 x 4 grid (NaN where every start reaches zero velocity)"),
}
_KIND = {  # kind -> (dtype, fill value, how undefined is written)
    "bool": (bool, False, "always defined"),
    "tri": (np.int8, -1, "int8: 1 true, 0 false, -1 (_FillValue, NaN when decoded) undefined"),
    "float": (np.float64, np.nan, "NaN where undefined"),
    "count": (np.int16, 0, "always defined (0 before the chunk is written: see done)"),
    "examples": (np.float64, np.nan, "NaN pads"),
}


def variables(claims) -> list:
    """The store's variables for the listed claims, in table order."""
    return [name for name, (claim, _, _) in VARIABLES.items() if claim in claims]


def encode(claims, rows: list) -> dict:
    """``{variable: array}`` of a block from its points' flat dicts (``claims.evaluate``), ``rows``
    a list of rows of dicts; ``None`` becomes the kind's fill value."""
    shape = (len(rows), len(rows[0]))
    out = {}
    for name in variables(claims):
        kind = VARIABLES[name][1]
        dtype, fill, _ = _KIND[kind]
        arr = np.full(shape + ((N_EXAMPLES,) if kind == "examples" else ()), fill, dtype)
        for i, row in enumerate(rows):
            for j, d in enumerate(row):
                if kind == "examples":
                    for k, ex in enumerate(d["dissip_examples"][:N_EXAMPLES]):
                        arr[i, j, k] = ex[0 if name.endswith("_x") else 1]
                elif d[name] is not None:
                    arr[i, j] = d[name]
        out[name] = arr
    return out


def template(grid, claims, chunk, attrs):
    """The empty Dataset (lazy dask arrays of fill values) that ``create`` writes the metadata of."""
    import dask.array as da
    import xarray as xr

    shape = (grid.nr, grid.nf + 1)
    data = {}
    for name in variables(claims) + ["done"]:
        claim, kind, meaning = VARIABLES.get(name, ("all", "bool", "the point's chunk is written "
                                                                   "(set after its data)"))
        dtype, fill, undefined = _KIND[kind]
        dims, sh, ch = DIMS, shape, (chunk, chunk)
        if kind == "examples":
            dims, sh, ch = DIMS + ("example",), shape + (N_EXAMPLES,), (chunk, chunk, N_EXAMPLES)
        data[name] = xr.Variable(dims, da.full(sh, fill, dtype=dtype, chunks=ch),
                                 {"claim": claim, "long_name": meaning, "units": "1", "undefined": undefined})
    coords = {"f_over_F": ("f_over_F", grid.fF, {"long_name": "f/F", "units": "1",
                                                 "description": "0, then the cell centres (j + 1/2)/NF, j < NF"}),
              "w2R_over_F": ("w2R_over_F", grid.R, {"long_name": "w^2 R / F", "units": "1",
                                                    "description": "log-spaced cell centres of [0.5, 100], NR rows"})}
    return xr.Dataset(data, coords=coords, attrs=attrs)


def _encoding(ds):
    enc = {}
    for name, var in ds.data_vars.items():
        kind = VARIABLES.get(name, (None, "bool"))[1]
        dtype, fill, _ = _KIND[kind]
        enc[name] = {"chunks": var.data.chunksize}
        if kind not in ("bool", "count"):          # these stay integers when read
            enc[name]["_FillValue"] = fill
    return enc


def identity(grid, claims, chunk) -> dict:
    """The attributes a resumed run must match: what the store's values depend on."""
    return {"grid": grid.name, "chunk": int(chunk), "claims": list(claims), "schema": SCHEMA}


def check(path, grid, claims, chunk) -> bool:
    """Whether a store for this grid, chunk and claims exists at ``path`` (``False``: none yet);
    ``ValueError`` saying what differs if the store there is another atlas, or no atlas."""
    path = pathlib.Path(path)
    if not path.exists():
        return False
    want, have = identity(grid, claims, chunk), read_identity(path)
    diff = [f"{k} {have.get(k)!r} (this run: {v!r})" for k, v in want.items() if have.get(k) != v]
    if diff:
        raise ValueError(f"{path} holds another atlas: " + "; ".join(diff) +
                         ". Use another --out, or delete it to start again")
    return True


def prepare(path, grid, claims, chunk, provenance) -> bool:
    """Create the store at ``path`` (its metadata and coordinates; no chunk yet) unless ``check``
    finds it there.  The new store is written beside and renamed into place, so a crash never
    leaves a half-made one.  Returns whether the store existed."""
    path = pathlib.Path(path)
    if check(path, grid, claims, chunk):
        return True
    for stale in path.parent.glob(f"{path.name}.partial-*"):   # left by a run killed while creating
        shutil.rmtree(stale, ignore_errors=True)
    tmp = path.with_name(f"{path.name}.partial-{os.getpid()}")
    attrs = {**identity(grid, claims, chunk), **provenance,
             "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")}
    ds = template(grid, claims, chunk, attrs)
    ds.to_zarr(tmp, mode="w-", compute=False, encoding=_encoding(ds), zarr_format=2, consolidated=True)
    os.replace(tmp, path)
    return False


def read_identity(path) -> dict:
    """The identity attributes of an existing store (``ValueError`` if it is not an atlas store)."""
    import zarr

    try:
        attrs = dict(zarr.open_group(str(path), mode="r").attrs)
    except Exception as exc:                       # not a zarr group at all
        raise ValueError(f"{path} exists but is not an atlas store ({type(exc).__name__}: {exc})") from None
    if "schema" not in attrs:
        raise ValueError(f"{path} exists but is not an atlas store (no 'schema' attribute)")
    return {k: attrs.get(k) for k in ("grid", "chunk", "claims", "schema")}


def done_blocks(path, blocks) -> set:
    """The blocks (``(k, rows, cols)``) whose ``done`` markers are all set."""
    import zarr

    done = zarr.open_group(str(path), mode="r")["done"][...]
    return {k for k, rows, cols in blocks if done[rows, cols].all()}


def write_block(path, rows, cols, values: dict):
    """Write one block's variables into their regions, then its ``done`` markers."""
    import zarr

    group = zarr.open_group(str(path), mode="r+")
    for name, arr in values.items():
        group[name][rows, cols] = arr
    group["done"][rows, cols] = np.ones((rows.stop - rows.start, cols.stop - cols.start), bool)


def locate(where) -> pathlib.Path:
    """``DIR`` or ``DIR/atlas.zarr`` -> the store's path."""
    p = pathlib.Path(where)
    return p if p.name.endswith(".zarr") else p / NAME


def open_atlas(where, *, complete=True):
    """The numerical atlas as an ``xarray.Dataset`` (lazy: a variable is read when first used): ``where`` is the
    ``--out`` directory of ``python -m cross_check atlas`` or the ``atlas.zarr`` inside it.

    Rows are ``w2R_over_F``, columns ``f_over_F`` (``F = w = 1``: the scene of a point is
    ``f = f/F, r - l = w^2 R/F``); variables as in ``VARIABLES`` (tri-states decoded to float
    1/0/NaN).  ``complete``: raise ``ValueError`` if some chunk is not written yet (a run that
    was stopped: rerun the same command to finish it)."""
    import xarray as xr

    path = locate(where)
    if not path.exists():
        raise ValueError(f"no atlas store at {path}: make one with `python -m cross_check atlas --out {path.parent}`")
    ds = xr.open_zarr(path, consolidated=True, chunks=None)
    if complete and not bool(ds["done"].all()):
        left = int((~ds["done"]).sum())
        raise ValueError(f"{path} is not complete ({left} points not written): rerun the same "
                         "`python -m cross_check atlas` command to finish it")
    return ds
