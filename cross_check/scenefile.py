"""The one reader of user scenes: TOML scene files and the inline ``--scene "F=1 f=0.3 ..."``.

A scene file holds one ``[[scene]]`` table per scene::

    [[scene]]
    name = "gear-rattle"          # required; unique, not a built-in scene's name
    F = 1                         # required: F, f, omega, l, r
    f = 0.3
    omega = "2*pi"
    l = 0
    r = 3
    restitution = 0.85            # optional: restitution (e, default 1), damping (c, default 0),
    damping = 0.05                #           wavenumber (k, default none: F cos(wt), not F cos(kx) cos(wt))

Values are numbers or strings, read exactly as ``reference.scene.Scene`` reads them: a number is
the decimal it is written as (``0.3`` is 3/10, not the float64 nearest to it: the file is read
with ``tomllib``'s ``parse_float=str``), a string a decimal or an expression in ``pi``
(``"2*pi"``, ``"(2*pi)**2"``, ``"pi/2"``).  The ranges are ``Scene``'s: ``F >= 0``, ``f >= 0``,
``omega > 0``, ``l < r``, ``0 <= restitution <= 1``, ``damping >= 0``, ``wavenumber > 0``.  This
module checks the form (tables, keys, names) and leaves every value to ``Scene``: its
``ValueError`` names the parameter and the range, and is passed on with the file and the scene.

Every mistake raises ``SceneFileError`` (a ``ValueError``) whose message names the file, the
scene and the field: a file that is not TOML (with the line), a missing field or an unknown key
(which one, and the allowed keys), a value out of range, a duplicate name, a name of a built-in
scene.  Commands print it and exit with status 2 (``add_arguments`` / ``from_args``).

The inline form is one scene as ``key=value`` words: ``"F=1 f=0.3 omega=1 l=0 r=3"``, with an
optional ``name=...`` (default ``inline``, then ``inline-2``, ...).

Scenes read here are registered in ``cross_check.scenes`` (after the built-ins), so every
command finds them by name.  A golden file records its scene with the same keys
(``cross_check.golden.scene_record``): ``from_record`` reads it back through the same checks.
"""
from __future__ import annotations

import difflib
import pathlib
import re
import tomllib

from reference.scene import Scene
from cross_check import scenes

REQUIRED = ("F", "f", "omega", "l", "r")
OPTIONAL = ("restitution", "damping", "wavenumber")
KEYS = ("name",) + REQUIRED + OPTIONAL
#: a scene name: 1 to 80 printable characters, no backslash, no space at either end (``scenes.slug``
#: makes a file name of it: ``:`` and ``/`` are replaced)
NAME = re.compile(r"[^\x00-\x20\\\x7f](?:[^\x00-\x1f\\\x7f]{0,78}[^\x00-\x20\\\x7f])?")
_ALLOWED = f"required: {', '.join(('name',) + REQUIRED)}; optional: {', '.join(OPTIONAL)}"


class SceneFileError(ValueError):
    """A user scene that cannot be read: the message names the file, the scene and the field."""


def _unknown(where, key) -> SceneFileError:
    close = difflib.get_close_matches(str(key), KEYS, n=1)
    hint = f"; did you mean {close[0]!r}?" if close else ""
    return SceneFileError(f"{where}: unknown key {key!r}{hint} ({_ALLOWED})")


def _field_of(message: str, given) -> str | None:
    """The parameter a ``Scene`` error names (``Scene: F must be ...``), else the first given key
    the message mentions."""
    m = re.match(r"\s*Scene: (\w+)\b", message)
    if m and m.group(1) in KEYS:
        return m.group(1)
    return next((k for k in given if re.search(rf"\b{re.escape(k)}\b", message)), None)


def make_scene(table: dict, where: str, name: str | None = None) -> Scene:
    """A ``Scene`` from one table of keys (the name from ``table["name"]`` or ``name``), every
    mistake a ``SceneFileError`` starting with ``where``."""
    if not isinstance(table, dict):
        raise SceneFileError(f"{where}: a scene must be a table of keys ({_ALLOWED}), got {type(table).__name__}")
    if isinstance(table.get("name"), str):
        where = f"{where} ({table['name']!r})"
    for key in table:
        if key not in KEYS:
            raise _unknown(where, key)
    name = table.get("name", name)
    if name is None:
        raise SceneFileError(f"{where}: missing field 'name' ({_ALLOWED})")
    if not isinstance(name, str) or not NAME.fullmatch(name):
        raise SceneFileError(f"{where}: field 'name' must be a string of 1 to 80 printable characters "
                             f"(no backslash, no space at either end), got {name!r}")
    missing = [k for k in REQUIRED if k not in table]
    if missing:
        raise SceneFileError(f"{where}: missing field {missing[0]!r} ({_ALLOWED})")
    params = {k: table[k] for k in REQUIRED + OPTIONAL if k in table}
    for k, value in params.items():
        if isinstance(value, bool) or not isinstance(value, (int, str)):
            raise SceneFileError(f"{where}: field {k!r} must be a number or a string (a decimal or an "
                                 f"expression in pi), got {type(value).__name__} {value!r}")
    try:
        return Scene(name=name, **params)
    except (ValueError, TypeError, ArithmeticError, RecursionError) as exc:
        field = _field_of(str(exc), params)
        what = f"field {field!r}" if field else "a field"
        raise SceneFileError(f"{where}: {what}: {exc}") from None


def read(path) -> list[Scene]:
    """The scenes of a TOML scene file (module docstring); ``SceneFileError`` on any mistake."""
    path = pathlib.Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneFileError(f"{path}: cannot read the scene file: {exc}") from None
    try:
        data = tomllib.loads(text, parse_float=str)
    except tomllib.TOMLDecodeError as exc:
        raise SceneFileError(f"{path}: not TOML: {exc}") from None
    for key in data:
        if key != "scene":
            raise SceneFileError(f"{path}: unknown top-level key {key!r} (a scene file holds [[scene]] tables only)")
    tables = data.get("scene")
    if not isinstance(tables, list) or not tables:
        raise SceneFileError(f"{path}: no scenes: write one [[scene]] table per scene ({_ALLOWED})")
    return [make_scene(t, f"{path}: scene {i + 1}") for i, t in enumerate(tables)]


def parse_inline(text: str, default_name: str = "inline") -> Scene:
    """One scene from ``"F=1 f=0.3 omega=1 l=0 r=3 [name=...] [restitution=...]"``."""
    where = f"--scene {text!r}"
    table = {}
    for word in str(text).split():
        key, eq, value = word.partition("=")
        if not eq or not key or not value:
            raise SceneFileError(f"{where}: {word!r} is not key=value ({_ALLOWED})")
        if key in table:
            raise SceneFileError(f"{where}: field {key!r} given twice")
        table[key] = value
    if not table:
        raise SceneFileError(f"{where}: empty; write key=value words ({_ALLOWED})")
    return make_scene(table, where, name=default_name)


def from_record(record: dict, where: str) -> Scene:
    """The scene of a golden file's ``scene`` record (``null`` values are defaults; ``effects``
    is derived, not read)."""
    table = {k: v for k, v in record.items() if k != "effects" and v is not None}
    return make_scene(table, where)


def collect(files=(), inline=()) -> list[Scene]:
    """The scenes of ``files`` then of the ``inline`` texts, checked together: no name twice, no
    built-in name, no two names with the same file name (``scenes.slug``)."""
    found, where_of = [], {}
    for path in files or ():
        found += [(sc, f"{path}") for sc in read(path)]
    for i, text in enumerate(inline or ()):
        found.append((parse_inline(text, "inline" if i == 0 else f"inline-{i + 1}"), f"--scene {text!r}"))
    for sc, where in found:
        if sc.name in scenes.SCENES:
            raise SceneFileError(f"{where}: scene {sc.name!r}: field 'name': {sc.name!r} is a built-in scene's "
                                 "name; choose another")
        slug = scenes.slug(sc.name)
        if slug in where_of:
            first_name, first_where = where_of[slug]
            same = "the name" if first_name == sc.name else f"the file name of {first_name!r}"
            raise SceneFileError(f"{where}: scene {sc.name!r}: field 'name': duplicate name "
                                 f"({same} is also used in {first_where})")
        where_of[slug] = (sc.name, where)
    return [sc for sc, _ in found]


def register_all(found) -> list[str]:
    """Register the scenes in ``cross_check.scenes``; their names, in order."""
    return [scenes.register(sc) for sc in found]


def add_arguments(parser, what: str = "run on") -> None:
    """``--scenes-file FILE`` and ``--scene "F=1 f=0.3 omega=1 l=0 r=3"`` (both repeatable)."""
    parser.add_argument("--scenes-file", action="append", default=[], metavar="FILE",
                        help=f"{what} the scenes of this TOML file ([[scene]] tables: name, F, f, omega, "
                             "l, r, optional restitution, damping, wavenumber); repeatable")
    parser.add_argument("--scene", action="append", default=[], metavar='"F=1 f=0.3 omega=1 l=0 r=3"',
                        dest="inline_scene",
                        help=f"{what} one scene given inline as key=value words (optional name=...); repeatable")


def from_args(args) -> list[str]:
    """Read, check and register the user scenes of ``add_arguments``' options; their names."""
    return register_all(collect(args.scenes_file, args.inline_scene))
