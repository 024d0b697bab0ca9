"""A results file as one more adapter (issue 32): an integrator in any language, graded by the very
code that grades a Python adapter (``card.score``).

``python -m cross_check score --results FILE`` (with the selection flags the problems were
exported with, ``problems``) reads ``FILE`` -- ``results.csv`` or ``results.json`` -- checks it
against the schema below, and scores ``ResultsAdapter(FILE, problems)``: its ``step`` answers
each start from the file, its ``events`` (when the file has event logs) likewise.  Same kinds,
tolerances, scorecard and exit status as any adapter.

**results.csv** -- a header, then one row per problem id, every line ending with a newline:

* required columns ``id, x, v``: the id of ``problems.csv`` and ``Phi^periods`` of its start;
* optional ``j11, j12, j21, j22`` (all four or none: ``Phi'``, read and checked, not graded yet),
  ``seconds`` (the integrator's time on the start, >= 0; not graded) and ``status``: ``ok``
  (default), ``failed`` (the start is a failure) or ``timeout`` (a failure of kind timeout).
  ``x`` and ``v`` may be empty on a row whose status is not ``ok``.

**results.json** -- ``{"results": [{"id": 1, "x": ..., "v": ..., "jacobian": [[j11, j12], [j21,
j22]], "seconds": ..., "status": "ok", "events": [[kind, t, x, v_before, v_after], ...]}, ...]}``:
the same fields (``id``, ``x``, ``v`` required), and per id the one-period event log, ``kind`` one
of ``EVENT_KINDS`` (the scorer compares it with the golden itinerary, kind by kind).

**Malformed** (``ResultsFileError``, a ``ValueError``: the CLI prints its one line and exits 2):
no such file, not UTF-8, no header, an unknown or repeated column, a missing required column, a
row with too few or too many fields, a last line without its newline (a truncated file), an id
that is not an integer, not a problem of the selection, or given twice, a number that is not a
number, NaN or infinite, a negative ``seconds``, a status not in ``STATUSES``, an event that is not
``[kind, t, x, v_before, v_after]``.  The message names the file, the line (for JSON: the line of
the entry's ``"id"`` where it can be told) and the field.  **A problem without a row** is not
malformed: its start fails, named in the scorecard ("no result for id ...").
"""
from __future__ import annotations

import csv
import io
import json
import math
import pathlib
import re
from dataclasses import dataclass

import numpy as np

from cross_check.score.problems import params_key
from cross_check.score.protocol import ReportedTimeout
from reference.scene import EFFECTS

REQUIRED = ("id", "x", "v")
JACOBIAN = ("j11", "j12", "j21", "j22")
OPTIONAL = JACOBIAN + ("seconds", "status")
STATUSES = ("ok", "failed", "timeout")
EVENT_KINDS = ("impact", "turn", "stick", "slip", "contact", "release", "chatter")
_NUMBER = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")
_ENTRY_KEYS = ("id", "x", "v", "jacobian", "seconds", "status", "events")


class ResultsFileError(ValueError):
    """A results file that breaks the schema: the message names the file, the line and the field."""


@dataclass(frozen=True)
class Result:
    """One row of a results file."""

    x: float | None
    v: float | None
    status: str = "ok"
    jacobian: tuple | None = None
    seconds: float | None = None
    events: tuple | None = None         # protocol order: (kind, t, x, v_after, v_before)


class _Where:
    """How a message names a place in the file: ``FILE: line N, field 'F'``."""

    def __init__(self, name: str):
        self.name = name

    def error(self, message: str, line=None, field=None) -> ResultsFileError:
        place = "".join([f": line {line}" if line is not None else "", f", field {field!r}" if field else ""])
        return ResultsFileError(f"{self.name}{place}: {message}")


def _float(text, where: _Where, line, field, *, optional=False):
    """A finite number from a CSV field or a JSON value (``None`` for an empty optional one)."""
    if text is None or text == "":
        if optional:
            return None
        raise where.error("missing (a number is required here)", line, field)
    if isinstance(text, bool) or not isinstance(text, (str, int, float)):
        raise where.error(f"{text!r} is not a number", line, field)
    if isinstance(text, str):
        stripped = text.strip()
        if stripped.lower().lstrip("+-") in ("nan", "inf", "infinity"):
            raise where.error("NaN" if "nan" in stripped.lower() else "infinite", line, field)
        if not _NUMBER.fullmatch(stripped):
            raise where.error(f"{text!r} is not a number", line, field)
    value = float(text)
    if math.isnan(value):
        raise where.error("NaN", line, field)
    if not math.isfinite(value):
        raise where.error("infinite (out of the float64 range)", line, field)
    return value


def _id(text, where, line, known, seen):
    if isinstance(text, bool) or not (isinstance(text, int) or (isinstance(text, str) and text.strip().isdigit())):
        raise where.error(f"{text!r} is not an integer id", line, "id")
    value = int(text)
    if value not in known:
        raise where.error(f"unknown id {value}: not a problem of this selection (export it with the same "
                          "--scenes/--golden-dir/--periods)", line, "id")
    if value in seen:
        raise where.error(f"id {value} given twice (first on line {seen[value]})", line, "id")
    seen[value] = line
    return value


def _result(get, where, line, *, events=None) -> Result:
    """A ``Result`` from a row's fields (``get(field)``: the text or value, ``None`` if absent)."""
    status = get("status")
    status = "ok" if status in (None, "") else status
    if status not in STATUSES:
        raise where.error(f"{status!r} is not a status (allowed: {', '.join(STATUSES)})", line, "status")
    optional = status != "ok"
    x, v = (_float(get(k), where, line, k, optional=optional) for k in ("x", "v"))
    if not optional and (x is None or v is None):
        raise where.error("missing", line, "x" if x is None else "v")
    jac = [_float(get(k), where, line, k, optional=True) for k in JACOBIAN]
    if any(j is not None for j in jac) and any(j is None for j in jac):
        missing = JACOBIAN[[j is None for j in jac].index(True)]
        raise where.error(f"the Jacobian needs all of {', '.join(JACOBIAN)}", line, missing)
    seconds = _float(get("seconds"), where, line, "seconds", optional=True)
    if seconds is not None and seconds < 0:
        raise where.error(f"must be >= 0, got {seconds!r}", line, "seconds")
    return Result(x, v, status, None if jac[0] is None else ((jac[0], jac[1]), (jac[2], jac[3])), seconds, events)


def read_csv(text: str, where: _Where, known) -> dict:
    """``results.csv`` -> ``{id: Result}`` (module docstring)."""
    allowed = REQUIRED + OPTIONAL
    expected = f"expected the columns {', '.join(REQUIRED)} and optionally {', '.join(OPTIONAL)}"
    if not text.strip():
        raise where.error(f"empty: no header ({expected})", 1)
    if not text.endswith("\n"):
        raise where.error("truncated: the last line has no newline", text.count("\n") + 1)
    reader = csv.reader(io.StringIO(text))
    header = [h.strip() for h in next(reader)]
    for i, name in enumerate(header):
        if name not in allowed:
            raise where.error(f"unknown column ({expected})", 1, name)
        if name in header[:i]:
            raise where.error("column given twice", 1, name)
    for name in REQUIRED:
        if name not in header:
            raise where.error(f"missing column ({expected})", 1, name)
    if any(j in header for j in JACOBIAN) and not all(j in header for j in JACOBIAN):
        missing = next(j for j in JACOBIAN if j not in header)
        raise where.error(f"missing column: the Jacobian needs all of {', '.join(JACOBIAN)}", 1, missing)
    out, seen = {}, {}
    for row in reader:
        line = reader.line_num
        if not row:
            raise where.error("an empty row", line)
        if len(row) < len(header):
            raise where.error(f"missing: the row has {len(row)} of {len(header)} fields", line, header[len(row)])
        if len(row) > len(header):
            raise where.error(f"{len(row)} fields, expected {len(header)} ({', '.join(header)})", line)
        fields = dict(zip(header, (f.strip() for f in row)))
        key = _id(fields["id"], where, line, known, seen)
        out[key] = _result(fields.get, where, line)
    return out


def _events(value, where, line, eid):
    if not isinstance(value, list):
        raise where.error(f"id {eid}: a list of [kind, t, x, v_before, v_after] is required", line, "events")
    out = []
    for j, e in enumerate(value):
        field = f"events[{j}]"
        if not isinstance(e, list) or len(e) != 5 or e[0] not in EVENT_KINDS:
            raise where.error(f"id {eid}: {e!r} is not [kind, t, x, v_before, v_after] with kind one of "
                              f"{', '.join(EVENT_KINDS)}", line, field)
        t, x, vb, va = (_float(a, where, line, field) for a in e[1:])
        out.append((e[0], t, x, va, vb))
    return tuple(out)


def read_json(text: str, where: _Where, known) -> dict:
    """``results.json`` -> ``{id: Result}`` (module docstring)."""
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as exc:
        raise where.error(f"not JSON: {exc.msg} (column {exc.colno})", exc.lineno) from None
    if not isinstance(doc, dict) or not isinstance(doc.get("results"), list):
        raise where.error('expected an object {"results": [...]}', 1, "results")
    entries = doc["results"]
    lines = [text.count("\n", 0, m.start()) + 1 for m in re.finditer(r'"id"\s*:', text)]
    out, seen = {}, {}
    for i, entry in enumerate(entries):
        line = lines[i] if len(lines) == len(entries) else None
        if not isinstance(entry, dict):
            raise where.error(f"results[{i}] is not an object", line)
        unknown = [k for k in entry if k not in _ENTRY_KEYS]
        if unknown:
            raise where.error(f"results[{i}]: unknown field (allowed: {', '.join(_ENTRY_KEYS)})", line, unknown[0])
        if "id" not in entry:
            raise where.error(f"results[{i}]: missing", line, "id")
        key = _id(entry["id"], where, line, known, seen)
        jac = entry.get("jacobian")
        if jac is not None and not (isinstance(jac, list) and len(jac) == 2
                                    and all(isinstance(r, list) and len(r) == 2 for r in jac)):
            raise where.error(f"id {key}: [[j11, j12], [j21, j22]] is required", line, "jacobian")
        flat = dict(zip(JACOBIAN, [a for r in jac for a in r])) if jac is not None else {}
        events = _events(entry["events"], where, line, key) if entry.get("events") is not None else None
        out[key] = _result(lambda k: flat.get(k) if k in JACOBIAN else entry.get(k), where, line, events=events)
    return out


def read(path, problems) -> dict:
    """The results file at ``path`` (``.json``: results.json, else results.csv) for ``problems``
    -> ``{id: Result}``; ``ResultsFileError`` if it is malformed (module docstring)."""
    path = pathlib.Path(path)
    where = _Where(str(path))
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise where.error(f"cannot be read ({exc.strerror or exc})") from None
    try:
        text = raw.decode("utf-8-sig")          # a byte-order mark (some editors write one) is no field
    except UnicodeDecodeError as exc:
        raise where.error(f"not UTF-8 text (byte {exc.start})", raw.count(b"\n", 0, exc.start) + 1) from None
    known = {p.id for p in problems}
    return (read_json if path.suffix.lower() == ".json" else read_csv)(text, where, known)


class MissingResult(LookupError):
    """A problem the results file has no row for: its start fails."""


class ReportedFailure(RuntimeError):
    """The results file reports a failed start."""


class ResultsAdapter:
    """A results file as an adapter (protocol: ``cross_check.score``): every effect, ``step`` from
    the rows, ``events`` and ``jacobian`` when the file has them for every id it gives."""

    def __init__(self, path, problems):
        self.path = pathlib.Path(path)
        self.results = read(self.path, problems)
        self.by_key = {p.key(): p for p in problems}
        self.effects = frozenset(EFFECTS)
        self.name = f"results file {self.path.name}"
        given = [r for r in self.results.values() if r.status == "ok"]
        if given and all(r.events is not None for r in given):
            self.events = self._events
        if given and all(r.jacobian is not None for r in given):
            self.jacobian = self._jacobian

    def _row(self, params, x, v, periods) -> Result:
        problem = self.by_key.get((params_key(params), float(x), float(v), periods))
        if problem is None:
            raise MissingResult(f"no problem ({float(x)!r}, {float(v)!r}) over {periods} period(s) in this selection")
        r = self.results.get(problem.id)
        c = problem.case
        where = f"id {problem.id} ({c.scene}/{c.name}, {periods} period(s))"
        if r is None:
            raise MissingResult(f"no result for {where} in {self.path.name}")
        if r.status == "failed":
            raise ReportedFailure(f"{self.path.name} reports status failed for {where}")
        if r.status == "timeout":
            raise ReportedTimeout(f"{self.path.name} reports status timeout for {where}")
        return r

    def step(self, params, x, v, periods):
        rows = [self._row(params, a, b, periods) for a, b in zip(x, v)]
        return np.array([r.x for r in rows], float), np.array([r.v for r in rows], float)

    def _events(self, params, x, v):
        return [list(self._row(params, a, b, 1).events or ()) for a, b in zip(x, v)]

    def _jacobian(self, params, x, v):
        return np.array([self._row(params, a, b, 1).jacobian for a, b in zip(x, v)], float)


__all__ = ["EVENT_KINDS", "MissingResult", "OPTIONAL", "REQUIRED", "ReportedFailure", "Result", "ResultsAdapter",
           "ResultsFileError", "STATUSES", "read", "read_csv", "read_json"]
