"""report.html: the validation report as one HTML page with relative links (opens from its folder).

Inline CSS, no network: images, STEP, VTU and results.json are linked by relative paths inside the output
folder, so the folder can be moved or zipped and still opens in any browser. The one script is the inline
WebGL viewer of the interactive 3D stress views (``view3d.js``), whose data is embedded in the page.
"""
from __future__ import annotations

from html import escape
from pathlib import Path

from ...io_atomic import atomic_write_text
from . import report_text as rt
from strainwave.compare.validate.catalogue_table import CATALOGUE_COLUMNS, catalogue_rows, slope_line
from strainwave.compare.validate.report_md import CATALOGUE_INTRO
from strainwave.compare.validate.wg_cup_checks import wg_lines

CSS = """
body{font-family:system-ui,-apple-system,"Segoe UI",sans-serif;margin:2em auto;max-width:1200px;color:#222;
line-height:1.4;padding:0 1em}
h1{margin-bottom:.2em} h2{border-bottom:2px solid #ddd;padding-bottom:.2em;margin-top:2em}
table{border-collapse:collapse;margin:1em 0;font-size:.85em;width:100%}
th,td{border:1px solid #ccc;padding:4px 6px;vertical-align:top;text-align:left}
th{background:#f2f2f2} td.num{text-align:right;white-space:nowrap}
.verdict{font-size:1.3em;padding:.6em 1em;border-radius:6px;margin:1em 0}
.pass{background:#e3f6e3;border:1px solid #6c6} .fail{background:#fde8e8;border:1px solid #d66}
td.PASS{background:#e3f6e3;font-weight:bold} td.FAIL{background:#fde8e8;font-weight:bold}
td.NOT{background:#fff4d6;font-weight:bold}
figure{display:inline-block;margin:.5em;max-width:48%;vertical-align:top} figure.wide{max-width:98%}
figure img{max-width:100%;border:1px solid #ddd} figcaption{font-size:.8em;color:#555}
.notes{font-size:.8em;color:#444} code{background:#f5f5f5;padding:0 3px}
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


def _figure(image: dict) -> str:
    path = escape(image["path"], quote=True)
    caption = escape(image["caption"])
    # stress pictures carry their numbers in the image: shown at full width, their titles stay legible
    wide = ' class="wide"' if image["kind"] == "stress" else ""
    return (f'<figure{wide}><a href="{path}"><img src="{path}" alt="{caption}" loading="eager"></a>'
            f"<figcaption>{caption}</figcaption></figure>")


def _view(component: str, view: dict, payload: str, ramp: str) -> str:
    source = f"view-data-{component}"
    low, high = view["range_MPa"]
    # "</" never occurs in the JSON (base64 and numbers), so it cannot end the script element early
    return (f'<figure class="view3d" id="view-{component}"><canvas class="sw-view" width="640" height="480" '
            f'data-source="{source}" aria-label="{escape(view["caption"], quote=True)}"></canvas>'
            f'<div class="colorbar"><span>{low:.3g}</span><span class="ramp" style="background:{ramp}"></span>'
            f"<span>{high:.4g} MPa (von Mises)</span></div><figcaption>{escape(view['caption'])}</figcaption></figure>"
            f'<script type="application/json" id="{source}">{payload}</script>')


def render_html(doc: dict, views: dict[str, str] | None = None) -> str:
    """The page; ``views`` = {component: the 3D view's JSON payload} (kept out of results.json)."""
    views = {c: p for c, p in (views or {}).items() if c in doc.get("views", {})}
    ramp = ""
    if views:
        from .view3d import colorbar_css
        ramp = colorbar_css()
    passed = doc["passed"]
    parts = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
             '<meta name="viewport" content="width=device-width, initial-scale=1">',
             "<title>strainwave validation report</title>", f"<style>{CSS}</style></head><body>",
             "<h1>strainwave validation report</h1>",
             f'<div class="verdict {"pass" if passed else "fail"}" id="verdict">{escape(rt.headline(doc))}</div>',
             f"<p>{escape(rt.run_line(doc))}</p>"]
    if doc.get("designer"):
        parts.append('<pre id="designer">' + escape("\n".join(doc["designer"])) + "</pre>")
    failing = [c for c in doc["checks"] if not c["passed"]]
    if failing:
        parts.append("<h2>Failing checks</h2><ul>")
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
    for component, title in rt.COMPONENTS:
        checks = [c for c in doc["checks"] if c["component"] == component]
        parts.append(f'<h2 id="{component}">{escape(title)}</h2>')
        inputs = doc.get("inputs", {}).get(component)
        if inputs:
            parts.append(f'<h3 id="inputs-{component}">Inputs and model</h3><div class="inputs">')
            parts += [_figure(i) for i in doc["images"] if i["component"] == component and i["kind"] == "preview"]
            parts.append(_table(("input", "value"), rt.input_lines(inputs)))
            parts.append(_table(rt.INPUT_MESH_COLUMNS, rt.input_mesh_rows(inputs)))
            parts.append(f'<p class="notes">{escape(inputs["mesh_note"])}</p></div>')
        if component in rated:
            parts.append(f"<p><b>Stress at the rated load</b> {escape(rt.rated_sentence(rated[component]))}</p>")
        parts.append(f'<h3 id="checks-{component}">Checks</h3>')
        parts.append(_table(rt.CHECK_COLUMNS, [rt.check_row(c) for c in checks], result_col=7))
        parts.append('<ul class="notes">' + "".join(
            f"<li><code>{escape(c['id'])}</code>: {escape(rt.check_notes(c))}</li>" for c in checks) + "</ul>")
        sweep = doc["crack_sweeps"].get(component)
        if sweep:
            parts.append(f"<h3>Crack-depth sweep ({escape(sweep['quantity'])}, {escape(sweep['unit'])})</h3>")
            parts.append(_table(rt.SWEEP_COLUMNS, rt.sweep_rows(sweep)))
            parts.append(f"<p>{escape(rt.sweep_fit_line(sweep))}</p>")
        figures = [_figure(i) for i in doc["images"] if i["component"] == component and i["kind"] != "preview"]
        if figures:
            parts.append("<div>" + "".join(figures) + "</div>")
        if component in views:
            parts.append(f'<h3 id="view3d-{component}">Interactive 3D view of the stress field</h3>')
            parts.append(_view(component, doc["views"][component], views[component], ramp))
    parts.append('<h2 id="gci">Discretization error (GCI table)</h2>')
    parts.append(f'<p class="notes">{escape(rt.GCI_INTRO)}</p>')
    parts.append(_table(rt.GCI_COLUMNS, [rt.gci_cells(r) for r in doc.get("gci_table", [])], table_id="gci-table"))
    nafems = doc.get("nafems")
    if nafems:
        parts.append('<h2 id="nafems">Appendix: NAFEMS benchmarks</h2>')
        parts.append(f'<p class="notes">{escape(rt.NAFEMS_INTRO)}</p>')
        parts.append(_table(rt.NAFEMS_COLUMNS, [rt.nafems_row(r) for r in nafems["cases"]], result_col=9,
                            table_id="nafems-table"))
        parts.append("<ul>" + "".join(f"<li>{escape(n)}</li>" for n in nafems["notes"]) + "</ul>")
    parts.append('<h2 id="audit">Seed audit</h2><p>Every inconsistency found in the seeds, with the FEA evidence '
                 "where the FEA can settle it.</p>")
    parts.append(_table(rt.AUDIT_COLUMNS, [rt.audit_row(a) for a in doc["audit"]]))
    if doc.get("catalogue"):
        cat = doc["catalogue"]
        parts.append('<h2 id="catalogue">Catalogue drives (Harmonic Drive CHA K3)</h2>')
        parts.append(f"<p>{escape(CATALOGUE_INTRO)}</p>" + _table(CATALOGUE_COLUMNS, catalogue_rows(cat)))
        parts.append(f'<p>{escape(slope_line(cat))}</p><p class="notes">{escape(cat["left_out"])}</p>')
    meta = doc["metadata"]
    parts.append('<h2 id="cases">FEA cases and timings</h2>')
    parts.append(_table(rt.CASE_COLUMNS, [rt.case_row(c) for c in meta["cases"]]))
    parts.append("<p>Time per stage: " + escape(", ".join(f"{k} {v:.1f} s" for k, v in meta["timings_s"].items()))
                 + "</p>")
    if doc.get("missing_images"):
        parts.append("<h2>Images that could not be made</h2><ul>" + "".join(
            f"<li>{escape(m['what'])}: {escape(m['reason'])}</li>" for m in doc["missing_images"]) + "</ul>")
    links = [(Path(p).name, p) for p in doc["files"]["step"] + doc["files"]["fields"]] + [("results.json",
                                                                                         "results.json")]
    parts.append('<h2 id="files">Files</h2><ul>' + "".join(
        f'<li><a href="{escape(p, quote=True)}">{escape(n)}</a></li>' for n, p in links) + "</ul>")
    parts.append("<h2>Versions</h2>" + _table(("package", "version"), list(meta["versions"].items())))
    if views:
        from .view3d import viewer_script
        parts.append(f"<script>{viewer_script()}</script>")
    parts.append("</body></html>")
    return "\n".join(parts)


def write_html(path: Path, doc: dict, views: dict[str, str] | None = None) -> Path:
    return atomic_write_text(path, render_html(doc, views))
