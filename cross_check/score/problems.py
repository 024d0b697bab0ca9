"""The golden problems as files, for an integrator in any language (issue 32; ``results`` reads
its answers back).

``python -m cross_check score --export-problems DIR`` (the selection flags of ``score``:
``--scenes``, ``--golden-dir``, ``--scenes-file``, ``--scene``, ``--periods``) writes:

* ``DIR/problems.csv`` -- one row per start and horizon, the columns ``COLUMNS``: ``id``,
  ``scene`` and ``case`` (the golden file's names), ``input`` (the golden input's key: ``exact``,
  the state itself, or ``float64``, the rounding of a decimal hard case -- what a float64
  integrator sees), ``periods`` (1, or 10 for the ten-period states), the scene's parameters
  ``F, f, omega, l, r, restitution, damping, wavenumber`` and the start ``x, v``.  Every number is
  its float64 written with 17 significant digits (``omega = 2*pi`` as its float64), so C's
  ``strtod`` or Fortran's ``read`` gives back the very same double; ``wavenumber`` is empty when
  the scene has no position forcing (then the forcing is ``F cos(omega t)``);
* ``DIR/problems.json`` -- ``format``, ``version``, the same rows (numbers as JSON numbers, each
  the shortest decimal that reads back as the same double; ``wavenumber`` ``null`` when absent)
  and, per scene, its exact parameter strings and effects, as the golden file records them;
* ``DIR/FORMAT.md`` -- both files and the results file described (``cross_check/data/examples/
  FORMAT.md``, shipped beside the C example ``vibro_impact.c``).

**Ids** are the rows' positions, from 1, in the full list of problems of the golden directory:
every scene it has (``golden.names_in`` order), per scene its cases over one period, then its
ten-period states (``golden.ten_period_cases``).  A selection keeps its rows' ids, so a results
file graded with another selection than it was exported with comes out as missing ids (failed
starts, named) or unknown ids (a malformed file), never as answers to other problems.
"""
from __future__ import annotations

import csv
import io
import json
import os
import pathlib
from dataclasses import dataclass
from importlib import resources

from cross_check import golden
from cross_check.score.golden import GoldenCase, scene_cases, ten_period_cases

FORMAT = "cross_check.score problems"
VERSION = 1
PARAMETERS = ("F", "f", "omega", "l", "r", "restitution", "damping", "wavenumber")
COLUMNS = ("id", "scene", "case", "input", "periods") + PARAMETERS + ("x", "v")


@dataclass(frozen=True)
class Problem:
    """One start and horizon: ``id`` (module docstring), the golden case, ``periods`` (1 or 10)."""

    id: int
    case: GoldenCase
    periods: int

    def key(self) -> tuple:
        """What an adapter call names it by: the scene's parameters, the start, the horizon."""
        return params_key(self.case.params), self.case.x, self.case.v, self.periods

    def values(self) -> dict:
        """The row as Python values (floats, ``None`` for an absent wavenumber)."""
        c = self.case
        return {"id": self.id, "scene": c.scene, "case": c.name, "input": c.input, "periods": self.periods,
                **{k: c.params[k] for k in PARAMETERS}, "x": c.x, "v": c.v}


def params_key(params: dict) -> tuple:
    return tuple((k, params[k]) for k in PARAMETERS)


def number(value) -> str:
    """A float64 with 17 significant digits (``strtod`` reads back the same double); ``""`` for
    ``None``."""
    return "" if value is None else format(float(value), ".17g")


def problems(names=None, periods=(1, 10), golden_dir=None) -> list[Problem]:
    """The problems of the scenes ``names`` (default: every scene of ``golden_dir``, by default the
    shipped data) over the horizons ``periods``, with their ids (module docstring)."""
    have = golden.names_in(golden_dir)
    names = have if names is None else list(names)
    unknown = [n for n in names if n not in have]
    if unknown:
        raise ValueError(f"unknown scene(s) {unknown}: no golden data for them in {golden.files(golden_dir)}")
    wanted, out, next_id = set(names), [], 1
    for name in have:
        cases = scene_cases(name, golden_dir)
        ten = ten_period_cases(cases)
        rows = [(c, 1) for c in cases] + [(cases[i], 10) for i in ten]
        if name in wanted:
            out += [Problem(next_id + j, c, p) for j, (c, p) in enumerate(rows) if p in periods]
        next_id += len(rows)
    order = {n: i for i, n in enumerate(names)}
    return sorted(out, key=lambda p: (order[p.case.scene], p.id))


def format_text() -> str:
    """FORMAT.md: the problems files and the results file described (shipped with the C example)."""
    return (resources.files("cross_check") / "data" / "examples" / "FORMAT.md").read_text()


def export(out, names=None, periods=(1, 10), golden_dir=None) -> list[pathlib.Path]:
    """Write ``problems.csv``, ``problems.json`` and ``FORMAT.md`` into the directory ``out``
    (module docstring); each file replaced whole.  Returns their paths."""
    rows = problems(names, periods, golden_dir)
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(COLUMNS)
    for p in rows:
        v = p.values()
        writer.writerow([v["id"], v["scene"], v["case"], v["input"], v["periods"]]
                        + [number(v[k]) for k in PARAMETERS + ("x", "v")])
    scenes = {}
    for p in rows:
        if p.case.scene not in scenes:
            record = golden.load(p.case.scene, golden_dir)["scene"]
            scenes[p.case.scene] = {k: record.get(k) for k in PARAMETERS + ("effects",)}
    doc = {"format": FORMAT, "version": VERSION, "periods": sorted(set(periods)),
           "golden_dir": "shipped" if golden_dir is None else str(golden_dir), "columns": list(COLUMNS),
           "scenes": scenes, "problems": [p.values() for p in rows]}
    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    paths = []
    for name, content in (("problems.csv", text.getvalue()), ("problems.json", json.dumps(doc, indent=1) + "\n"),
                          ("FORMAT.md", format_text())):
        tmp = out / f".{name}.part"
        tmp.write_text(content)
        os.replace(tmp, out / name)
        paths.append(out / name)
    return paths


__all__ = ["COLUMNS", "FORMAT", "PARAMETERS", "Problem", "VERSION", "export", "format_text", "number",
           "params_key", "problems"]
