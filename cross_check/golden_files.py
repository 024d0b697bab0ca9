"""Golden files on disk: the deterministic JSON text (``dumps``), the directories that hold them
(``files``: a given one or the shipped package data) and reading them back (``load``, ``names_in``,
``scene_of``).
"""
from __future__ import annotations

import json
import pathlib

from cross_check import scenefile, scenes


def dumps(data: dict) -> str:
    """Deterministic JSON text: fixed key order, one-space indent, a list of scalars (an
    event, a Jacobian row, Phi) on one line, trailing newline."""
    return _dump(data, 0) + "\n"


def _flat(value) -> bool:
    return not isinstance(value, (dict, list)) or (
        isinstance(value, list) and all(not isinstance(v, (dict, list)) for v in value))


def _dump(value, depth: int) -> str:
    if _flat(value):
        return json.dumps(value, ensure_ascii=True)
    pad, inner = " " * depth, " " * (depth + 1)
    if isinstance(value, dict):
        items = [f"{inner}{json.dumps(k)}: {_dump(v, depth + 1)}" for k, v in value.items()]
        return "{\n" + ",\n".join(items) + "\n" + pad + "}"
    items = [inner + _dump(v, depth + 1) for v in value]
    return "[\n" + ",\n".join(items) + "\n" + pad + "]"


def files(directory=None):
    """A golden data directory: ``directory`` (or its ``golden/``, where ``verify --out DIR`` writes,
    if ``directory`` itself holds no JSON), or by default the shipped one (``importlib.resources``:
    works in a checkout and from a wheel alike)."""
    if directory is not None:
        base = pathlib.Path(directory)
        if (base / "golden").is_dir() and not any(base.glob("*.json")):
            return base / "golden"
        return base
    from importlib import resources
    return resources.files("cross_check") / "data" / "golden"


def load(name: str, directory=None) -> dict:
    """Read the golden file of a scene (default: the shipped data, ``files()``); ``ValueError``
    if the directory has none for that scene."""
    path = files(directory) / (scenes.slug(name) + ".json")
    if not path.is_file():
        raise ValueError(f"no golden data for scene {name!r} in {files(directory)} (write it with "
                         "`python -m cross_check golden` or `verify`)")
    return json.loads(path.read_text())


def names_in(directory=None) -> list[str]:
    """The scenes a golden directory has files for: by default the built-in scenes (the shipped
    data), else every ``*.json`` of ``directory`` with a ``scene`` record, by file name."""
    if directory is None:
        return [n for n in scenes.SCENES if (files() / (scenes.slug(n) + ".json")).is_file()]
    base = files(directory)
    if not base.is_dir():
        raise ValueError(f"--golden-dir {directory}: not a directory")
    out = []
    for path in sorted(base.glob("*.json")):
        try:
            name = json.loads(path.read_text())["scene"]["name"]
        except (ValueError, KeyError, TypeError):
            continue                     # not a golden file (e.g. a scorecard): not ours to read
        out.append(name)
    if not out:
        raise ValueError(f"--golden-dir {directory}: no golden files (*.json with a scene record) there")
    return out


def scene_of(data: dict, where: str = "golden file"):
    """The scene a golden file was written for, from its exact record (``scenefile.from_record``)."""
    return scenefile.from_record(data["scene"], where)
