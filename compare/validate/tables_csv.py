"""checks.csv, gci.csv, stress.csv and design.csv beside the report: the report's tables for a spreadsheet.

Read from the results document, as both reports are: a CSV never shows a number results.json does not have.
Written with the standard csv module (quoting, commas in the reasons), each file atomically.
"""
from __future__ import annotations

import csv
import io
from pathlib import Path

from strainwave.io_atomic import atomic_write_text

__all__ = ["CSV_FILES", "write_tables", "check_rows", "gci_rows", "stress_rows", "design_rows"]

CSV_FILES = ("checks.csv", "gci.csv", "stress.csv", "design.csv")

CHECK_FIELDS = ("id", "component", "quantity", "unit", "fea", "fea_uncertainty", "published", "published_rel_error",
                "corrected", "corrected_rel_error", "asserts", "relation", "tolerance_relative", "tolerance_reason",
                "verdict", "passed")


def check_rows(doc: dict) -> list[dict]:
    rows = []
    for c in doc["checks"]:
        rows.append({"id": c["id"], "component": c["component"], "quantity": c["quantity"], "unit": c["unit"],
                     "fea": c["fea"], "fea_uncertainty": c["fea_uncertainty"],
                     "published": c["analytic"].get("published"), "published_rel_error": c["rel_error"].get("published"),
                     "corrected": c["analytic"].get("corrected"), "corrected_rel_error": c["rel_error"].get("corrected"),
                     "asserts": c["asserts"], "relation": c.get("relation", "equal"),
                     "tolerance_relative": c["tolerance"]["relative"], "tolerance_reason": c["tolerance"]["reason"],
                     "verdict": c["verdict"] if c["verdict"] != "not evaluated" else
                     f"not evaluated: {c['reason_not_evaluated']}", "passed": c["passed"]})
    return rows


GCI_FIELDS = ("case", "quantity", "unit", "h1_mm", "h2_mm", "h3_mm", "f1", "f2", "f3", "r21", "r32", "observed_order",
              "formal_order", "extrapolated", "gci_fine", "asymptotic", "flags")


def gci_rows(doc: dict) -> list[dict]:
    rows = []
    for r in doc.get("gci_table", []):
        row = {k: r.get(k) for k in ("case", "quantity", "unit", "r21", "r32", "observed_order", "formal_order",
                                     "extrapolated", "gci_fine", "asymptotic")}
        row.update({f"h{k + 1}_mm": h for k, h in enumerate(r["h_mm"])})
        row.update({f"f{k + 1}": v for k, v in enumerate(r["values"])})
        row["flags"] = "; ".join(r.get("flags", []))
        rows.append(row)
    return rows


STRESS_FIELDS = ("component", "load", "rated_load", "load_unit", "solved_load", "scale", "peak_von_mises_MPa", "x_mm",
                 "y_mm", "z_mm", "peak_on", "peak_displacement_mm", "fatigue_limit_MPa", "safety_factor",
                 "required_safety_factor", "design_passed", "tip_radius_mm", "tip_peak_von_mises_MPa", "corner_radius_mm",
                 "corner_peak_von_mises_MPa", "field_file", "note", "design_verdict")


def stress_rows(doc: dict) -> list[dict]:
    design = doc.get("design") or {}
    factors = {f["component"]: f for f in design.get("factors", [])}
    overall = None if not design else ("PASS" if design.get("passed") else "FAIL")
    rows = []
    for component, s in doc.get("stress_at_rated", {}).items():
        x, y, z = s["peak_location_mm"]
        factor = factors.get(component, {})
        rows.append({"component": component, "load": s["load"]["name"], "rated_load": s["load"]["rated"],
                     "load_unit": s["load"]["unit"], "solved_load": s["load"]["solved"], "scale": s["load"]["scale"],
                     "peak_von_mises_MPa": s["peak_von_mises_MPa"], "x_mm": x, "y_mm": y, "z_mm": z,
                     "peak_on": "; ".join(s["peak_on"]), "peak_displacement_mm": s["peak_displacement_mm"],
                     "fatigue_limit_MPa": s["fatigue_limit_MPa"],
                     # the design factor where the component has one (design.csv's n); else the material-only one
                     "safety_factor": factor.get("safety_factor"),
                     "required_safety_factor": factor.get("required"), "design_passed": factor.get("passed"),
                     "tip_radius_mm": s.get("tip_radius_mm"), "tip_peak_von_mises_MPa": s.get("tip_peak_von_mises_MPa"),
                     "corner_radius_mm": s.get("corner_radius_mm"),
                     "corner_peak_von_mises_MPa": s.get("corner_peak_von_mises_MPa"),
                     "field_file": s["field_file"], "design_verdict": overall,
                     "note": s["note"] if factor else s["note"] + "; not a design factor itself: see design.csv"})
    return rows


DESIGN_FIELDS = ("component", "title", "criterion", "amplitude_MPa", "mean_MPa", "notch_K", "fatigue_limit_MPa",
                 "ultimate_strength_MPa", "yield_strength_MPa", "n", "required_n", "static_n", "verdict", "band_low",
                 "band_high", "material", "amplitude_source", "mean_source", "notch_source", "load", "advice", "admissible")


def design_rows(doc: dict) -> list[dict]:
    """One row per design factor: its inputs (amplitude, mean, notch, strengths), n, [n], static n, verdict."""
    rows = []
    for f in (doc.get("design") or {}).get("factors", []):
        fat = f.get("fatigue")
        if fat:
            rows.append({k: fat.get(k) for k in DESIGN_FIELDS} | {"verdict": f.get("verdict", fat.get("verdict"))})
        else:
            rows.append({"component": f["component"], "title": f.get("title"), "verdict": f.get("verdict"),
                         "n": f.get("safety_factor"), "required_n": f.get("required"), "advice": f.get("reason", "")})
    return rows


def _csv_text(fields: tuple[str, ...], rows: list[dict]) -> str:
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=fields, lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: "" if v is None else repr(v) if isinstance(v, float) else v for k, v in row.items()})
    return buffer.getvalue()


def write_tables(out_dir: Path, doc: dict) -> list[Path]:
    """checks.csv, gci.csv, stress.csv in ``out_dir``; floats at full precision (repr), empty for none."""
    out_dir = Path(out_dir)
    tables = ((CHECK_FIELDS, check_rows(doc)), (GCI_FIELDS, gci_rows(doc)), (STRESS_FIELDS, stress_rows(doc)),
              (DESIGN_FIELDS, design_rows(doc)))
    return [atomic_write_text(out_dir / name, _csv_text(fields, rows)) for name, (fields, rows) in zip(CSV_FILES, tables)]
