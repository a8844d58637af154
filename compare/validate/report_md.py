"""report.md: the validation report as Markdown (summary verdict first), from the results document."""
from __future__ import annotations

from pathlib import Path

from strainwave.io_atomic import atomic_write_text
from strainwave.compare.validate import report_text as rt
from strainwave.compare.validate.wg_cup_checks import wg_lines
from strainwave.compare.validate.run_record import PARAM_COLUMNS, param_rows, report_title, run_lines
from strainwave.compare.validate.catalogue_table import CATALOGUE_COLUMNS, catalogue_rows, slope_line

CATALOGUE_INTRO = ("Each size is a drive built by one set of design rules (d1 = 2.54 mm x size; wall, length, "
                   "k_r and K_G0 in proportion to seed 000's example), the unit without its output shaft. A comparison, "
                   "not a check.")


def _table(columns, rows) -> list[str]:
    def cell(text: str) -> str:
        return str(text).replace("|", "\\|").replace("\n", " ")

    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    lines += ["| " + " | ".join(cell(c) for c in row) + " |" for row in rows]
    return lines


def _md_headlines(doc: dict) -> list[str]:
    """Title, the two verdicts, the run, the parameter diff and the design verdict."""
    lines = [f"# {report_title(doc)}", "", f"**{rt.VALIDATION_QUESTION}** {rt.headline(doc)}", "",
             f"**{rt.DESIGN_QUESTION}** {rt.design_headline(doc)}", "", rt.run_line(doc), ""]
    lines += [f"- {line}" for line in run_lines(doc)] + ([""] if run_lines(doc) else [])
    if param_rows(doc):
        lines += ["### Parameters that differ from the embedded default", ""]
        lines += _table(PARAM_COLUMNS, param_rows(doc)) + [""]
    table = doc.get("designer_table")
    if table and table["rows"]:
        lines += ["## Designer headline", ""] + _table(table["columns"], table["rows"]) + [""]
    elif doc.get("designer"):
        lines += ["```", *doc["designer"], "```", ""]
    design = doc.get("design")
    if design:
        lines += ["## Design verdict: safety factors at the rated load", "",
                  f"Each component's factor against [n] = {design['required_safety_factor']:g} "
                  f"({design['required_source']}). {rt.DESIGN_BAND_NOTE}", ""]
        lines += _table(rt.DESIGN_COLUMNS, [rt.design_row(f) for f in design["factors"]]) + [""]
        lines += [f"- {t}" for t in rt.design_notes(design)] + [""]
        lines += [f"- {t}" for t in (rt.singular_line(c, s) for c, s in doc.get("stress_at_rated", {}).items()) if t]
        lines += [""]
    return lines


def _md_failing_and_rated(doc: dict) -> list[str]:
    """Failing checks, the stress at the rated load, the flexspline on its wave generator."""
    lines = []
    failing = [c for c in doc["checks"] if not c["passed"]]
    if failing:
        lines += ["## Failing checks", ""]
        lines += [f"- `{c['id']}`: {rt.failing_line(c)}" for c in failing] + [""]
    rated = doc.get("stress_at_rated", {})
    if rated:
        lines += ["## Stress at the rated load", ""]
        lines += _table(rt.RATED_COLUMNS, [rt.rated_row(c, s) for c, s in rated.items()]) + [""]
    wg_rows = wg_lines(doc.get("cup_wave_generator") or {})
    if wg_rows:
        lines += ["## Flexspline on the wave generator (stress and fatigue safety)", ""]
        lines += _table(("item", "value"), wg_rows) + [""]
    return lines


def _md_components(doc: dict) -> list[str]:
    """One section per component: inputs, checks, crack sweep, images."""
    lines = []
    images = doc["images"]
    rated = doc.get("stress_at_rated", {})
    for component, title in rt.components():
        checks = [c for c in doc["checks"] if c["component"] == component]
        lines += [f"## {title}", ""]
        inputs = doc.get("inputs", {}).get(component)
        if inputs:
            lines += ["### Inputs and model", ""]
            for image in (i for i in images if i["component"] == component and i["kind"] == "preview"):
                lines += [f"![{image['caption']}]({image['path']})", ""]
            lines += _table(("input", "value"), rt.input_lines(inputs)) + [""]
            lines += _table(rt.INPUT_MESH_COLUMNS, rt.input_mesh_rows(inputs)) + ["", inputs["mesh_note"], ""]
        if component in rated:
            lines += [f"**Stress at the rated load** {rt.rated_sentence(rated[component])}", ""]
        lines += ["### Checks", ""]
        lines += _table(rt.CHECK_COLUMNS, [rt.check_row(c) for c in checks]) + [""]
        lines += [f"- `{c['id']}`: {rt.check_notes(c)}" for c in checks] + [""]
        sweep = doc["crack_sweeps"].get(component)
        if sweep:
            lines += [f"### Crack-depth sweep ({sweep['quantity']}, {sweep['unit']})", ""]
            lines += _table(rt.SWEEP_COLUMNS, rt.sweep_rows(sweep)) + ["", rt.sweep_fit_line(sweep), ""]
        for image in (i for i in images if i["component"] == component and i["kind"] != "preview"):
            lines += [f"![{image['caption']}]({image['path']})", "", f"*{image['caption']}*", ""]
        if component in doc.get("views", {}):
            lines += ["An interactive 3D view of this stress field is in report.html.", ""]
    return lines


def _md_appendices(doc: dict) -> list[str]:
    """The GCI table, NAFEMS, the seed audit, the catalogue drives, cases and timings."""
    lines = []
    lines += ["## Discretization error (GCI table)", "", rt.GCI_INTRO, ""]
    lines += _table(rt.GCI_COLUMNS, [rt.gci_cells(r) for r in doc.get("gci_table", [])]) + [""]
    nafems = doc.get("nafems")
    if nafems:
        lines += ["## Appendix: NAFEMS benchmarks", "", rt.NAFEMS_INTRO, ""]
        lines += _table(rt.NAFEMS_COLUMNS, [rt.nafems_row(r) for r in nafems["cases"]]) + [""]
        lines += [f"- {note}" for note in nafems["notes"]] + [""]
    lines += ["## Seed audit", "", "Every inconsistency found in the seeds, with the FEA evidence where the FEA can "
              "settle it.", ""]
    lines += _table(rt.AUDIT_COLUMNS, [rt.audit_row(a) for a in doc["audit"]]) + [""]
    if doc.get("catalogue"):
        cat = doc["catalogue"]
        lines += ["## Catalogue drives (Harmonic Drive CHA K3)", "", CATALOGUE_INTRO, ""]
        lines += _table(CATALOGUE_COLUMNS, catalogue_rows(cat)) + ["", slope_line(cat), "", cat["left_out"], ""]
        lines += [cat["gear_line"], ""] if cat.get("gear_line") else []
    meta = doc["metadata"]
    lines += ["## FEA cases and timings", ""]
    lines += _table(rt.CASE_COLUMNS, [rt.case_row(c) for c in meta["cases"]]) + [""]
    lines += ["Time per stage: " + ", ".join(f"{k} {v:.1f} s" for k, v in meta["timings_s"].items()), ""]
    if doc.get("missing_images"):
        lines += ["## Images that could not be made", ""]
        lines += [f"- {m['what']}: {m['reason']}" for m in doc["missing_images"]] + [""]
    return lines


def _md_files(doc: dict) -> list[str]:
    """The files written beside the report, and the versions."""
    meta = doc["metadata"]
    lines = []
    lines += ["## Files", ""]
    lines += [f"- STEP: [{Path(p).name}]({p})" for p in doc["files"]["step"]] or [f"- STEP: {rt.no_step_line(doc)}"]
    lines += [f"- VTU: [{Path(p).name}]({p})" for p in doc["files"]["fields"]]
    lines += ["- [results.json](results.json)"] + [f"- [{n}]({n})" for n in doc["files"].get("tables", ())]
    lines += [f"- [{doc['files']['report_pdf']}]({doc['files']['report_pdf']})"] if doc["files"].get("report_pdf") \
        else [f"- {rt.NO_PDF}"]
    lines += [""]
    lines += ["## Versions", ""] + [f"- {k}: {v}" for k, v in meta["versions"].items()] + [""]
    return lines




def render_markdown(doc: dict) -> str:
    lines = _md_headlines(doc) + _md_failing_and_rated(doc) + _md_components(doc) + _md_appendices(doc)
    return "\n".join(lines + _md_files(doc))


def write_markdown(path: Path, doc: dict) -> Path:
    return atomic_write_text(path, render_markdown(doc))
