"""``verify``'s report: the checks each scene passes or fails, and ``report.md``.

A scene's checks (``checks``), each failed one listed in the summary and the exit status 1:

* **tasks**: every unit of work ran (an exception is listed with the task);
* **golden self-agreement**: every sample state's golden record passed its check -- the dps 90 / 110
  pair, or under position forcing its proof (``sources`` says which, per scene) -- (a
  hard case that fails it is left out of the golden data with the reason: a listed limitation of
  that construction, not a failure of the scene);
* **golden proofs**: every golden input is proved (``reference.enclosure``: under position forcing
  along validated Taylor flights);
* **agreement**: fast's canonical itinerary equals the reference's on every sample and hard case
  outside the near-grazing band;
* **fast scorecard**: no kind flagged on fast's scorecard against the scene's golden data.

Orbits that Newton finds but Krawczyk does not prove, and kinds flagged on scipy's scorecard, are
reported, not failed: the first are candidates (a non-hyperbolic or grazing orbit has no
isolating box), the second measure scipy.
"""
from __future__ import annotations

from cross_check import scenes
from cross_check.golden import CHECK_DPS, GOLDEN_DPS, GUIDE_DPS, PROVED_DPS
from cross_check.golden_chatter import RESTART_DPS
from cross_check.report import sections
from cross_check.score.card import TEN_DPS
from cross_check.tolerances import tol


def _get(got, what):
    value = got.get(what)
    return None if value is None or isinstance(value, Exception) else value[0]


def _golden_inputs(doc):
    return [(c["name"], label, inp) for c in doc["cases"] for label, inp in c["inputs"].items()]


def checks(got: dict) -> list[str]:
    """The failed checks of one scene (module docstring), each a line saying why."""
    failed = [f"tasks: {what} raised {type(v).__name__}: {str(v)[:200]}"
              for what, v in got.items() if isinstance(v, Exception)]
    g = _get(got, "golden file")
    if g is not None:
        bad = [why for why in g["dropped"] if " / sample-" in why]
        failed += [f"golden self-agreement: {why}" for why in bad]
        unproved = [f"{case} / {label}: {inp['enclosure']['reason']}" for case, label, inp in _golden_inputs(g["document"])
                    if not inp["enclosure"]["proved"]]
        if unproved:
            failed.append(f"golden proofs: {len(unproved)} input(s) not proved, e.g. {unproved[0][:200]}")
    a = _get(got, "agreement")
    if a is not None:
        out = list(a["samples"]["mismatch_outside_band"])
        out += [r["case"] for r in a["hard"] if not r["same"] and r["stable"] and not r["ref_band"]]
        if out:
            failed.append(f"agreement: fast's itinerary differs from the reference's outside the band: {', '.join(out)}")
    card = _get(got, "scorecard fast")
    if card is not None and card["flagged"]:
        failed.append(f"fast scorecard: flagged kinds {', '.join(card['flagged'])}")
    return failed


def proves(got) -> str:
    """One sentence: what a scene's data proves -- its golden inputs proved (``Phi`` and ``Phi'`` in
    Arb balls, under position forcing along validated Taylor flights) with the widest relative
    radius of ``Phi``, the hard cases whose construction carries a certificate, the orbits proved."""
    parts = []
    g, st = _get(got, "golden file"), _get(got, "states")
    if g is not None:
        p, n = _proved_fraction(g["document"])
        radii = [float(inp["enclosure"]["radius"]) for _, _, inp in _golden_inputs(g["document"])
                 if inp["enclosure"]["proved"]]
        parts.append(f"{p}/{n} golden inputs proved" + (f" (widest relative radius of Phi {max(radii):.1e})"
                                                         if radii else ""))
    if st is not None:
        certified = [c.name for c in st["cases"] if "certified:" in c.how]
        if certified:
            parts.append(f"{len(certified)} hard case(s) certified to meet no other event before theirs "
                         "(validated flights backward from the event)")
    orbits = _orbit_rows(got)
    if orbits:
        parts.append(f"{sum(r['proof']['proved'] for r in orbits)}/{len(orbits)} periodic orbits proved (Krawczyk)")
    return "; ".join(parts) + "." if parts else "nothing (its tasks failed: see the summary)."


def _orbit_rows(got):
    return [row for what in sorted(got) if what.startswith("orbits ") and _get(got, what) is not None
            for row in _get(got, what)]


def _proved_fraction(doc):
    inputs = _golden_inputs(doc)
    proved = sum(inp["enclosure"]["proved"] for _, _, inp in inputs)
    return proved, len(inputs)


def _summary_row(name, got, failed, seconds):
    st, g, a = _get(got, "states"), _get(got, "golden file"), _get(got, "agreement")
    orbits = _orbit_rows(got)
    proved = sum(r["proof"]["proved"] for r in orbits)
    hard = sum(1 for c in st["cases"] if not c.name.startswith("sample")) if st else 0
    cells = [f"`{name}`", f"{len(st['cases'])} ({hard} hard)" if st else "-"]
    if g is not None:
        p, n = _proved_fraction(g["document"])
        cells.append(f"{p}/{n} ({100 * p / max(1, n):.0f}%)")
    else:
        cells.append("-")
    cells.append(f"{a['samples']['map_raw']}" if a else "-")
    cells.append(f"{proved}/{len(orbits)}")
    for adapter in ("fast", "scipy"):
        card = _get(got, f"scorecard {adapter}")
        cells.append("-" if card is None else (", ".join(card["flagged"]) or "none"))
    cells += [f"{seconds:.0f}", "**FAILED**" if failed else "ok"]
    return "| " + " | ".join(cells) + " |"


def _hard_section(st, g):
    lines = ["Hard cases built for this scene (`cross_check/agreement/hardcases.py`):", ""]
    built = [c for c in st["cases"] if not c.name.startswith("sample")]
    lines += [f"- {c.name}: {c.how}" for c in built] or ["- none"]
    if st["notes"]:
        lines += ["", "Not admitted, and why:", ""] + [f"- {k}: {why}" for k, why in st["notes"].items()]
    if g is not None and g["dropped"]:
        lines += ["", "Left out of the golden data (the dps 90 / 110 self-check failed; no doubtful digit is "
                  "written):", ""] + [f"- {why[:300]}" for why in g["dropped"]]
    return lines


#: what an input's written values rest on, by the key its golden record carries (``golden.case_entry``)
_AGREE = f"{tol('golden_proved_agreement').rtol:g}"
SOURCES = (("guide_dps", f"from the midpoints of the input's own proof's balls, each ball within {_AGREE} of its value "
                         f"(the proof guided by a dps-{GUIDE_DPS} run)"),
           ("dps", f"from a dps-{PROVED_DPS} run that the input's proof certifies to {_AGREE}"),
           (None, f"from a dps-{GOLDEN_DPS} run checked at dps {CHECK_DPS}"))


def sources(doc) -> str:
    """One sentence: how many golden inputs of the file ``doc`` have their values from each source
    (``SOURCES``), and how many have chatter times from restart pairs (``golden_chatter``)."""
    inputs = [inp for _, _, inp in _golden_inputs(doc)]
    keys = [next((key for key, _ in SOURCES if key in inp), None) for inp in inputs]
    text = "Golden values: " + "; ".join(f"{keys.count(key)} {what}" for key, what in SOURCES if key in keys)
    restarted = sum("chatter_dps" in inp for inp in inputs)
    if restarted:
        text += (f"; the chatter times of {restarted} of them from restart pairs (dps {RESTART_DPS[0]} checked at "
                 f"{RESTART_DPS[1]}) within their proofs' balls")
    return text + "."


def _golden_section(g):
    p, n = _proved_fraction(g["document"])
    lines = [f"Golden data: `golden/` -- {len(g['document']['cases'])} states, {n} inputs, {p} proved "
             f"({100 * p / max(1, n):.1f}%)."]
    radii = [float(inp["enclosure"]["radius"]) for _, _, inp in _golden_inputs(g["document"]) if inp["enclosure"]["proved"]]
    if radii:
        lines[0] += f"  Widest proved relative radius of Phi: {max(radii):.1e}."
    if n:
        lines[0] += "  " + sources(g["document"])
    unproved = [(c, lab, inp["enclosure"]["reason"]) for c, lab, inp in _golden_inputs(g["document"])
                if not inp["enclosure"]["proved"]]
    if unproved:
        lines += ["", "Not proved:", ""] + [f"- {c} / {lab}: {why[:240]}" for c, lab, why in unproved]
    return lines


def _multipliers(proof):
    out = []
    for m in proof.get("multipliers", []):
        if isinstance(m, dict):
            out.append(f"{float(m['re'][0]):.4g} +- {float(m['im'][0]):.4g}i")
        else:
            out.append(f"{float(m[0]):.4g}")
    return ", ".join(out)


def _cell(text, width=160):
    """``text`` cut to ``width`` characters for a table cell, its ``|`` escaped (a reason such as
    ``|C (P(z) - z)|`` split its row into more columns than the header)."""
    return text[:width].replace("|", "\\|")


def _orbit_section(orbits):
    if not orbits:
        return ["No periodic point found from the seed grid."]
    lines = ["| period | point (x, v) at t = 0 | type (fast) | reaches v = 0 | sticks | proved | proved type | "
             "multipliers | box radius or reason |", "|---|---|---|---|---|---|---|---|---|"]
    for r in orbits:
        pr = r["proof"]
        where = (f"x in [{r['segment'][0]:.6g}, {r['segment'][1]:.6g}], v = {r['v']:.6g}" if r["what"] == "segment"
                 else f"({r['x']:.6g}, {r['v']:.6g})")
        kind = "sticking" if r["sticks"] else r["kind"]
        lines.append(f"| {r['period']} | {where} | {kind} | {'yes' if r['dissip'] else 'no'} | "
                     f"{'yes' if r['sticks'] else 'no'} | {'**yes**' if pr['proved'] else 'no'} | "
                     f"{pr.get('kind', '-')} | {_multipliers(pr) or '-'} | "
                     f"{pr['radius']:.1e} |" if pr["proved"] else
                     f"| {r['period']} | {where} | {kind} | {'yes' if r['dissip'] else 'no'} | "
                     f"{'yes' if r['sticks'] else 'no'} | no | - | - | {_cell(pr['reason'])} |")
    return lines


def _scorecard_lines(card):
    if card is None:
        return ["(failed: see the summary)"]
    rows = [f"{k}: {s['grade']} ({s['cases']} cases, worst graded digits "
            f"{'-' if s['worst_graded_digits'] is None else format(s['worst_graded_digits'], '.1f')})"
            for k, s in card["kinds"].items()]
    return ["; ".join(rows) or "no cases"]


def _ten_periods(got, name):
    """fast's digits after ten periods on the scene's sample states (its scorecard's), summarized."""
    import json

    card = _get(got, "scorecard fast")
    ten = [] if card is None else json.loads(card["json"]).get("scenes", {}).get(name, {}).get("ten", [])
    return sections.Summary.of([float("nan") if d is None else d for d in ten])


def cpu_line(got) -> str:
    """The scene's CPU seconds by kind of task (golden chunks, orbit periods and scorecards summed)."""
    spent = {}
    for what, value in got.items():
        if not isinstance(value, Exception):
            key = what.split(" ")[0]
            spent[key] = spent.get(key, 0.0) + value[1]
    ranked = sorted(spent.items(), key=lambda kv: -kv[1])
    return "CPU seconds by task: " + ", ".join(f"{k} {v:.1f}" for k, v in ranked) + "."


def scene_section(rec, got, failed, slug) -> list[str]:
    """A scene's section of the report."""
    name = rec["name"]
    params = ", ".join(f"{k} = {rec[k]}" for k in ("F", "f", "omega", "l", "r", "restitution", "damping",
                                                    "wavenumber") if rec.get(k) is not None)
    lines = [f"## `{name}`", "", f"{params}; effects: {', '.join(rec['effects'])}.", "", cpu_line(got), ""]
    if failed:
        lines += ["Failed checks:", ""] + [f"- {f}" for f in failed] + [""]
    st, g, a = _get(got, "states"), _get(got, "golden file"), _get(got, "agreement")
    if st is not None:
        lines += _hard_section(st, g) + [""]
    lines += [f"What the data proves: {proves(got)}", ""]
    if g is not None:
        lines += _golden_section(g) + [""]
    if a is not None:
        lines += ["Fast against the reference (its golden data, from the sources above; ten periods: fast's "
                  f"scorecard, against the reference at {TEN_DPS} digits), samples:", ""]
        lines += sections.agreement_table({name: {**a["samples"], "map10": _ten_periods(got, name)}}) + [""]
        if a["hard"]:
            lines += ["Hard cases (fast and scipy see the float64 rounding of the decimal state):", ""]
            lines += sections.hard_table(a["hard"]) + [""]
    lines += ["Periodic orbits (Newton from a seed grid, `dynamics.periodic`; Krawczyk proofs, "
              "`reference.enclosure`):", ""] + _orbit_section(_orbit_rows(got)) + [""]
    if _get(got, "portrait") is not None:
        lines += [f"![portrait of {name}](scenes/{slug}/portrait.png)", ""]
    for adapter in ("fast", "scipy"):
        lines += [f"Scorecard `{adapter}` on this scene's golden data "
                  f"([scenes/{slug}/scorecard-{adapter}.md](scenes/{slug}/scorecard-{adapter}.md)): "]
        lines += _scorecard_lines(_get(got, f"scorecard {adapter}")) + [""]
    return lines


def render(records, results, depth) -> tuple[str, list]:
    """``report.md`` and the failed checks ``[(scene, check)]``."""
    failed_all, rows, body = [], [], []
    for rec in records:
        name = rec["name"]
        got = results["scenes"][name]
        failed = checks(got)
        failed_all += [(name, f) for f in failed]
        seconds = sum(v[1] for v in got.values() if not isinstance(v, Exception))
        rows.append(_summary_row(name, got, failed, seconds))
        body += scene_section(rec, got, failed, scenes.slug(name))
    head = ["# Verify: your scenes", "",
            f"{len(records)} scene(s), {depth.name} run ({depth.n_sample} sample states, orbit periods "
            f"{', '.join(map(str, depth.periods))}, scores over {' and '.join(map(str, depth.score_periods))} "
            f"period(s)), on {results['workers']} Dask worker(s) in {results['seconds']:.0f} s.", "",
            "| scene | states | golden inputs proved | fast vs ref digits (median / worst) | orbits proved / found | "
            "fast flagged kinds | scipy flagged kinds | CPU seconds | verdict |",
            "|---|---|---|---|---|---|---|---|---|"] + rows + [""]
    head += ["What the data proves:", ""] + [f"- `{rec['name']}`: {proves(results['scenes'][rec['name']])}"
                                              for rec in records] + [""]
    if failed_all:
        head += ["Failed checks:", ""] + [f"- `{n}`: {f}" for n, f in failed_all] + [""]
    else:
        head += ["Every check holds: golden self-agreement, a proof per golden input, fast's itinerary equal "
                 "to the reference's outside the near-grazing band, no kind flagged on fast's scorecard.", ""]
    head += ["Digits: significant correct digits, `-log10(|a - ref| / max(1, |ref|))`, capped at 17.  "
             "Golden data in `golden/` (40 digits, a proof per input; each scene's section says what its "
             "values rest on): "
             "`python -m cross_check score ADAPTER --golden-dir golden`, "
             "`python -m cross_check prove --golden --golden-dir golden`, `pytest --golden-dir golden`.", ""]
    return "\n".join(head + body) + "\n", failed_all


__all__ = ["checks", "proves", "sources", "render", "scene_section"]
