"""report.html: the validation report as one self-contained HTML page (images inside it as data URIs).

Inline CSS, no network: every picture is embedded, so the page alone (mailed, attached to a ticket) shows
everything; STEP, VTU, the CSV tables and results.json are linked by relative paths inside the output folder.
A table of contents opens the page after the two verdicts (validation, design). The one script is the inline
WebGL viewer of the interactive 3D stress views (``view3d.js``), whose data is embedded in the page; where
WebGL is missing it says so in place of the canvas. ``report.pdf`` is this page printed by headless Chromium
(``report_pdf``).
"""
from __future__ import annotations

import base64
from html import escape
from pathlib import Path

from strainwave.io_atomic import atomic_write_text
from strainwave.compare.validate import report_text as rt
from strainwave.compare.validate.catalogue_table import CATALOGUE_COLUMNS, catalogue_rows, slope_line
from strainwave.compare.validate.report_md import CATALOGUE_INTRO
from strainwave.compare.validate.wg_cup_checks import wg_lines
from strainwave.compare.validate.run_record import PARAM_COLUMNS, param_rows, report_title, run_lines

CSS = """
body{font-family:system-ui,-apple-system,"Segoe UI",sans-serif;margin:2em auto;max-width:1200px;color:#222;
line-height:1.4;padding:0 1em}
h1{margin-bottom:.2em} h2{border-bottom:2px solid #ddd;padding-bottom:.2em;margin-top:2em}
table{border-collapse:collapse;margin:1em 0;font-size:.85em;width:100%}
th,td{border:1px solid #ccc;padding:4px 6px;vertical-align:top;text-align:left}
th{background:#f2f2f2} td.num{text-align:right;white-space:nowrap}
.verdict{font-size:1.3em;padding:.6em 1em;border-radius:6px;margin:1em 0}
.pass{background:#e3f6e3;border:1px solid #6c6} .fail{background:#fde8e8;border:2px solid #c00;color:#a00;
font-weight:bold} .verdict .q{display:block;font-size:.7em;font-weight:normal;color:#444}
nav.toc{columns:2;font-size:.9em;background:#fafafa;border:1px solid #ddd;padding:.5em 1em}
nav.toc a{text-decoration:none} .tip{font-size:.9em;color:#633}
.nowebgl{display:none;border:1px dashed #999;padding:1em;max-width:640px;color:#633}
@media print{canvas.sw-view,.colorbar{display:none} .nowebgl{display:block} figure{break-inside:avoid}
h2{break-after:avoid} body{max-width:none}}
td.PASS{background:#e3f6e3;font-weight:bold} td.FAIL{background:#fde8e8;font-weight:bold}
td.NOT,td.UNDECIDED{background:#fff4d6;font-weight:bold}
figure{display:inline-block;margin:.5em;max-width:48%;vertical-align:top} figure.wide{max-width:98%}
figure img{max-width:100%;border:1px solid #ddd} figcaption{font-size:.8em;color:#555}
.notes{font-size:.8em;color:#444} code{background:#f5f5f5;padding:0 3px}
pre{white-space:pre-wrap;font-size:.8em}
figure.view3d{max-width:100%} canvas.sw-view{border:1px solid #ddd;cursor:grab;width:640px;height:480px;
max-width:100%} .colorbar{display:flex;align-items:center;gap:.5em;font-size:.8em;max-width:640px}
.colorbar .ramp{flex:1;height:12px;border:1px solid #999}
"""


def _table(columns, rows, *, result_col: int | None = None, table_id: str = "") -> str:
    head = "".join(f"<th>{escape(c)}</th>" for c in columns)
    body = []
    for row in rows:
        cells = []
        for i, cell in enumerate(row):
            cls = f' class="{escape(str(cell).split()[0])}"' if i == result_col else ""
            cells.append(f"<td{cls}>{escape(str(cell))}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    ident = f' id="{escape(table_id, quote=True)}"' if table_id else ""
    return f"<table{ident}><thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>"


def _source(image: dict, root: Path | None) -> str:
    """The image as a data URI read from ``root`` (a self-contained page), or its relative path without one."""
    if root is None:
        return image["path"]
    return "data:image/png;base64," + base64.b64encode((Path(root) / image["path"]).read_bytes()).decode("ascii")


def _figure(image: dict, root: Path | None = None) -> str:
    source = escape(_source(image, root), quote=True)
    caption = escape(image["caption"])
    # stress pictures carry their numbers in the image: shown at full width, their titles stay legible
    wide = ' class="wide"' if image["kind"] in ("stress", "crack-opening") else ""
    return (f'<figure{wide}><img src="{source}" alt="{caption}" loading="eager">'
            f"<figcaption>{caption}</figcaption></figure>")


def _view(component: str, view: dict, payload: str, ramp: str) -> str:
    source = f"view-data-{component}"
    low, high = view["range_MPa"]
    # "</" never occurs in the JSON (base64 and numbers), so it cannot end the script element early
    return (f'<figure class="view3d" id="view-{component}"><canvas class="sw-view" width="640" height="480" '
            f'data-source="{source}" aria-label="{escape(view["caption"], quote=True)}"></canvas>'
            f'<p class="nowebgl">This interactive view needs WebGL, which this viewer does not offer (or the page '
            f'is printed): the picture above shows the same field.</p>'
            f'<div class="colorbar"><span>{low:.3g}</span><span class="ramp" style="background:{ramp}"></span>'
            f"<span>{high:.4g} MPa (von Mises)</span></div><figcaption>{escape(view['caption'])}</figcaption></figure>"
            f'<script type="application/json" id="{source}">{payload}</script>')


def _verdicts(doc: dict) -> list[str]:
    """The two verdicts, each with its question: a failing design is red, never under a green box."""
    passed, design = doc["passed"], rt.design_passed(doc)
    return [f'<div class="verdict {"pass" if passed else "fail"}" id="verdict"><span class="q">'
            f"{escape(rt.VALIDATION_QUESTION)}</span>{escape(rt.headline(doc))}</div>",
            f'<div class="verdict {"pass" if design else "fail"}" id="design-verdict"><span class="q">'
            f"{escape(rt.DESIGN_QUESTION)}</span>{escape(rt.design_headline(doc))}</div>"]


def _run_section(doc: dict) -> list[str]:
    """The run's identity, its parameters that differ from the default, and the designer headline's table."""
    parts = ['<ul id="run">' + "".join(f"<li>{escape(line)}</li>" for line in run_lines(doc)) + "</ul>"]
    if param_rows(doc):
        parts.append("<h3>Parameters that differ from the embedded default</h3>")
        parts.append(_table(PARAM_COLUMNS, param_rows(doc), table_id="params-diff"))
    table = doc.get("designer_table")
    if table and table["rows"]:
        parts.append('<h2 id="designer-headline">Designer headline</h2>')
        parts.append(_table(table["columns"], table["rows"], table_id="designer-table"))
    if doc.get("designer"):
        parts.append('<details><summary>The headline in full</summary><pre id="designer">'
                     + escape("\n".join(doc["designer"])) + "</pre></details>")
    return parts


def _toc(entries: list[tuple[str, str]]) -> str:
    return '<nav class="toc" id="contents"><b>Contents</b><ol>' + "".join(
        f'<li><a href="#{escape(i, quote=True)}">{escape(t)}</a></li>' for i, t in entries) + "</ol></nav>"


def _design_section(doc: dict) -> list[str]:
    design = doc.get("design")
    if not design:
        return []
    parts = ['<h2 id="design">Design verdict: safety factors at the rated load</h2>',
             f"<p>Each component's factor against [n] = {design['required_safety_factor']:g} "
             f"({escape(design['required_source'])}). {escape(rt.DESIGN_BAND_NOTE)}</p>",
             _table(rt.DESIGN_COLUMNS, [rt.design_row(f) for f in design["factors"]], result_col=5,
                    table_id="design-table"),
             '<ul class="design-notes">' + "".join(f"<li>{escape(t)}</li>" for t in rt.design_notes(design)) + "</ul>"]
    tips = [t for t in (rt.singular_line(c, s) for c, s in doc.get("stress_at_rated", {}).items()) if t]
    if tips:
        parts.append('<ul class="tip">' + "".join(f"<li>{escape(t)}</li>" for t in tips) + "</ul>")
    return parts


def _component_section(doc: dict, component: str, title: str, root, views, ramp) -> list[str]:
    rated = doc.get("stress_at_rated", {})
    checks = [c for c in doc["checks"] if c["component"] == component]
    parts = [f'<h2 id="{component}">{escape(title)}</h2>']
    inputs = doc.get("inputs", {}).get(component)
    if inputs:
        parts.append(f'<h3 id="inputs-{component}">Inputs and model</h3><div class="inputs">')
        parts += [_figure(i, root) for i in doc["images"] if i["component"] == component and i["kind"] == "preview"]
        parts.append(_table(("input", "value"), rt.input_lines(inputs)))
        parts.append(_table(rt.INPUT_MESH_COLUMNS, rt.input_mesh_rows(inputs)))
        parts.append(f'<p class="notes">{escape(inputs["mesh_note"])}</p></div>')
    if component in rated:
        parts.append(f"<p><b>Stress at the rated load</b> {escape(rt.rated_sentence(rated[component]))}</p>")
        tip = rt.singular_line(component, rated[component])
        if tip:
            parts.append(f'<p class="tip">{escape(tip)}</p>')
    parts.append(f'<h3 id="checks-{component}">Checks</h3>')
    parts.append(_table(rt.CHECK_COLUMNS, [rt.check_row(c) for c in checks], result_col=7))
    parts.append('<ul class="notes">' + "".join(
        f"<li><code>{escape(c['id'])}</code>: {escape(rt.check_notes(c))}</li>" for c in checks) + "</ul>")
    sweep = doc["crack_sweeps"].get(component)
    if sweep:
        parts.append(f"<h3>Crack-depth sweep ({escape(sweep['quantity'])}, {escape(sweep['unit'])})</h3>")
        parts.append(_table(rt.SWEEP_COLUMNS, rt.sweep_rows(sweep)))
        parts.append(f"<p>{escape(rt.sweep_fit_line(sweep))}</p>")
    figures = [_figure(i, root) for i in doc["images"] if i["component"] == component and i["kind"] != "preview"]
    if figures:
        parts.append("<div>" + "".join(figures) + "</div>")
    if component in views:
        parts.append(f'<h3 id="view3d-{component}">Interactive 3D view of the stress field</h3>')
        parts.append(_view(component, doc["views"][component], views[component], ramp))
    return parts


def _appendix(doc: dict) -> list[str]:
    meta = doc["metadata"]
    parts = ['<h2 id="gci">Discretization error (GCI table)</h2>', f'<p class="notes">{escape(rt.GCI_INTRO)}</p>',
             _table(rt.GCI_COLUMNS, [rt.gci_cells(r) for r in doc.get("gci_table", [])], table_id="gci-table"),
             '<h2 id="audit">Seed audit</h2><p>Every inconsistency found in the seeds, with the FEA evidence where '
             "the FEA can settle it.</p>", _table(rt.AUDIT_COLUMNS, [rt.audit_row(a) for a in doc["audit"]])]
    nafems = doc.get("nafems")
    if nafems:
        parts += ['<h2 id="nafems">Appendix: NAFEMS benchmarks</h2>', f'<p class="notes">{escape(rt.NAFEMS_INTRO)}</p>',
                  _table(rt.NAFEMS_COLUMNS, [rt.nafems_row(r) for r in nafems["cases"]], result_col=9,
                         table_id="nafems-table"),
                  "<ul>" + "".join(f"<li>{escape(n)}</li>" for n in nafems["notes"]) + "</ul>"]
    if doc.get("catalogue"):
        cat = doc["catalogue"]
        parts.append('<h2 id="catalogue">Catalogue drives (Harmonic Drive CHA K3)</h2>')
        parts.append(f"<p>{escape(CATALOGUE_INTRO)}</p>" + _table(CATALOGUE_COLUMNS, catalogue_rows(cat)))
        parts.append(f'<p>{escape(slope_line(cat))}</p><p class="notes">{escape(cat["left_out"])}</p>')
        if cat.get("gear_line"):
            parts.append(f"<p>{escape(cat['gear_line'])}</p>")
    parts += ['<h2 id="cases">FEA cases and timings</h2>', _table(rt.CASE_COLUMNS, [rt.case_row(c) for c in meta["cases"]]),
              "<p>Time per stage: " + escape(", ".join(f"{k} {v:.1f} s" for k, v in meta["timings_s"].items()))
              + "</p>"]
    if doc.get("missing_images"):
        parts.append('<h2 id="missing">Images that could not be made</h2><ul>' + "".join(
            f"<li>{escape(m['what'])}: {escape(m['reason'])}</li>" for m in doc["missing_images"]) + "</ul>")
    files = doc["files"]
    links = [(Path(p).name, p) for p in files["step"] + files["fields"]] + [
        (n, n) for n in ("results.json", *files.get("tables", ()), files.get("report_pdf", ""), "report.md") if n]
    parts.append('<h2 id="files">Files</h2><p>Beside this page in its folder (relative links):</p><ul>' + "".join(
        f'<li><a href="{escape(p, quote=True)}">{escape(n)}</a></li>' for n, p in links)
        + ("" if files["step"] else f"<li>STEP: {escape(rt.no_step_line(doc))}</li>")
        + ("" if files.get("report_pdf") else f'<li id="no-pdf">{escape(rt.NO_PDF)}</li>') + "</ul>")
    parts.append('<h2 id="versions">Versions</h2>' + _table(("package", "version"), list(meta["versions"].items())))
    return parts


def render_html(doc: dict, views: dict[str, str] | None = None, root: Path | None = None) -> str:
    """The page; ``views`` = {component: the 3D view's JSON payload} (kept out of results.json); ``root``: the
    output folder the images are read from and embedded (None: linked by relative path)."""
    views = {c: p for c, p in (views or {}).items() if c in doc.get("views", {})}
    ramp = ""
    if views:
        from strainwave.compare.validate.view3d import colorbar_css
        ramp = colorbar_css()
    toc = [("designer-headline", "Designer headline")] if (doc.get("designer_table") or {}).get("rows") else []
    toc += [("design", "Design verdict: safety factors")] if doc.get("design") else []
    failing = [c for c in doc["checks"] if not c["passed"]]
    toc += [("failing", "Failing checks")] if failing else []
    toc += [("rated", "Stress at the rated load")] if doc.get("stress_at_rated") else []
    toc += list(rt.components()) + [("gci", "Discretization error (GCI table)"), ("audit", "Seed audit")]
    toc += [("nafems", "Appendix: NAFEMS benchmarks")] if doc.get("nafems") else []
    toc += [("catalogue", "Catalogue drives (Harmonic Drive CHA K3)")] if doc.get("catalogue") else []
    toc += [("cases", "FEA cases and timings"), ("files", "Files"), ("versions", "Versions")]
    parts = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
             '<meta name="viewport" content="width=device-width, initial-scale=1">',
             f"<title>{escape(report_title(doc))}</title>", f"<style>{CSS}</style></head><body>",
             f"<h1>{escape(report_title(doc))}</h1>", *_verdicts(doc), f"<p>{escape(rt.run_line(doc))}</p>"]
    parts += _run_section(doc)
    parts.append(_toc(toc))
    parts += _design_section(doc)
    if failing:
        parts.append('<h2 id="failing">Failing checks</h2><ul>')
        parts += [f"<li><code>{escape(c['id'])}</code>: {escape(rt.failing_line(c))}</li>" for c in failing]
        parts.append("</ul>")
    rated = doc.get("stress_at_rated", {})
    if rated:
        parts.append('<h2 id="rated">Stress at the rated load</h2>')
        parts.append(_table(rt.RATED_COLUMNS, [rt.rated_row(c, s) for c, s in rated.items()]))
    wg_rows = wg_lines(doc.get("cup_wave_generator") or {})
    if wg_rows:
        parts.append('<h2 id="wave-generator">Flexspline on the wave generator (stress and fatigue safety)</h2>')
        parts.append(_table(("item", "value"), wg_rows))
    for component, title in rt.components():
        parts += _component_section(doc, component, title, root, views, ramp)
    parts += _appendix(doc)
    if views:
        from strainwave.compare.validate.view3d import viewer_script
        parts.append(f"<script>{viewer_script()}</script>")
    parts.append("</body></html>")
    return "\n".join(parts)


def write_html(path: Path, doc: dict, views: dict[str, str] | None = None) -> Path:
    """The self-contained page: images read from ``path``'s folder and embedded."""
    return atomic_write_text(path, render_html(doc, views, root=Path(path).parent))
