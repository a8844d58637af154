"""The report's catalogue comparison: Harmonic Drive's CHA K3 beside the seed models for every size.

A comparison, not a check: the seed's models leave out tooth engagement and clearance, so the ratio says
how much of a real drive's compliance they hold; this gear's chain with the teeth in mesh is one line beside. The FEA-chain column comes from ``make bench``
(benchmarks/bench_catalogue.py), which meshes every size; validate stays cheap with the closed forms.
"""
from __future__ import annotations

import warnings

from strainwave.analytic import catalogue
from strainwave.params import load_params

__all__ = ["catalogue_document", "CATALOGUE_COLUMNS", "catalogue_rows", "slope_line"]

CATALOGUE_COLUMNS = ("size", "ratio", "d1 (mm)", "catalogue K3 (N m/rad)", "published K (N m/rad)",
                     "published / K3", "corrected K (N m/rad)", "corrected / K3")
LEFT_OUT = ("The published and corrected columns are seed 000's forms: the flexspline tube and the wave "
            "generator's radial stiffness only, without the teeth in mesh (tooth bending, clearance), which "
            "strainwave's drive chain adds (below and `strainwave catalogue`); they are shown to say how much of "
            "a real drive's compliance the seeds' model holds.")


def catalogue_document(rules: catalogue.DesignRules = catalogue.DesignRules(), gear_line: str = "") -> dict:
    """Rows per catalogue size and ratio, the log-log slope of K against size per ratio, and ``gear_line``:
    this gear's drive chain with the teeth in mesh against the table (``mesh_chain_checks.gear_line``)."""
    rows = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")         # catalogue sizes sit outside seed 000's example ranges
        for row in catalogue.read_catalogue():
            cmp = catalogue.compare_row(row, load_params(overrides=catalogue.overrides_for(row, rules)))
            rows.append({"size": row.size, "ratio": row.ratio_label, "d1_mm": cmp.d1_mm,
                         "K3_Nm_per_rad": row.K3_Nm_per_rad, "K_published_Nm_per_rad": cmp.K_published_Nm_per_rad,
                         "K_corrected_Nm_per_rad": cmp.K_corrected_Nm_per_rad})
    slopes = {}
    for label in catalogue.RATIO_OF_LABEL:
        sel = [r for r in rows if r["ratio"] == label]
        sizes = [r["size"] for r in sel]
        slopes[label] = {"catalogue": catalogue.log_slope(sizes, [r["K3_Nm_per_rad"] for r in sel]),
                         "corrected": catalogue.log_slope(sizes, [r["K_corrected_Nm_per_rad"] for r in sel])}
    return {"rows": rows, "slopes": slopes, "rules": dict(rules.__dict__), "left_out": LEFT_OUT,
            "gear_line": gear_line}


def catalogue_rows(doc: dict) -> list[tuple[str, ...]]:
    """The table cells of ``catalogue_document``'s rows."""
    return [(str(r["size"]), r["ratio"], f"{r['d1_mm']:.1f}", f"{r['K3_Nm_per_rad']:.3g}",
             f"{r['K_published_Nm_per_rad']:.3g}", f"{r['K_published_Nm_per_rad'] / r['K3_Nm_per_rad']:.2f}",
             f"{r['K_corrected_Nm_per_rad']:.3g}", f"{r['K_corrected_Nm_per_rad'] / r['K3_Nm_per_rad']:.2f}")
            for r in doc["rows"]]


def slope_line(doc: dict) -> str:
    return "Slope of log K against log size: " + "; ".join(
        f"ratio {k}: catalogue {v['catalogue']:.2f}, model {v['corrected']:.2f}" for k, v in doc["slopes"].items())
