"""The report's league section: the league table, read from ``league.md`` on disk.

The report never runs a peer (its own run time stays what it was) and never imports
``cross_check.league`` (the two rooms are independent): ``python -m cross_check league`` writes
``league.md``; when one exists in ``league_dir`` the report includes its table and goal line and
links the page and its work-precision plot, and otherwise says how to make one.
"""
from __future__ import annotations

import os
import pathlib


def league_section(league_dir, report_dir) -> list[str]:
    """Markdown lines: the table of ``league_dir/league.md`` (the lines of the table that starts
    ``| peer |``, and the ``**Goal**`` line) with links, or how to make the league."""
    page = pathlib.Path(league_dir) / "league.md"
    if not page.exists():
        return [f"No league in `{league_dir}/` yet.  Make one: `python -m pip install -e '.[peers]' && "
                "python -m cross_check league --quick` (about 2 minutes; without `--quick` about 15) grades "
                "SUNDIALS CVODE, diffrax, MuJoCo, scipy and heyoka beside fast and the reference; the report "
                "then includes its table here."]
    try:
        text = page.read_text()
    except OSError as exc:
        return [f"The league page `{page}` cannot be read: {exc.strerror or exc}."]
    lines = text.splitlines()
    start = next((i for i, line in enumerate(lines) if line.startswith("| peer |")), None)
    if start is None:
        return [f"The league page `{page}` has no table (an interrupted run?): rerun `python -m cross_check league`."]
    end = start
    while end < len(lines) and lines[end].startswith("|"):
        end += 1
    link = os.path.relpath(page, report_dir)
    head = next((line for line in lines if line.startswith(("Quick run", "Full run"))), "")
    out = [f"From [{link}]({link}) ({head.split(':')[0].lower() or 'a league run'}; `python -m cross_check league`): "
           "each engine at its settings, graded by the scorecard on the golden data.", ""]
    out += lines[start:end] + [""]
    out += [line for line in lines if line.startswith("**Goal**")]
    png = pathlib.Path(league_dir) / "work_precision.png"
    if png.exists():
        out += ["", f"![league work-precision]({os.path.relpath(png, report_dir)})"]
    return out


__all__ = ["league_section"]
