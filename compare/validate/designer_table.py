"""The designer headline as a short table: one row per answer a designer asks for, its value in catalogue units
beside the model's, and its basis in a few words. The full sentences stay in results.json's ``designer``."""
from __future__ import annotations

__all__ = ["DESIGNER_COLUMNS", "designer_table", "catalogue_stiffness"]

DESIGNER_COLUMNS = ("question", "answer", "basis")


def catalogue_stiffness(k_Nmm_per_rad: float) -> str:
    """A torsional stiffness in N mm/rad with the catalogue's N m/rad beside it."""
    return f"{k_Nmm_per_rad:.4g} N mm/rad ({k_Nmm_per_rad / 1e3:.4g} N m/rad)"


def _tooth_rows(s3: dict) -> list[list[str]]:
    from strainwave.analytic.tooth_number import supported_minimum
    zm = s3["tooth_number_min_with_fea_factors"]
    a = zm["assumptions"]
    seed_design = (a["rim_thickness_ratio"], a["dedendum_coefficient"], a["psi_sigma"], a["permissible_safety"],
                   a["fatigue_limit_MPa"]) == (0.012, 1.35, 0.12, 1.4, 625.0)
    rows = []
    for dz in (2, 4):
        r = zm[f"dZ{dz}"]
        z, basis = supported_minimum(dz, r["Z_R_min"], a["permissible_safety"], seed_design)
        rows.append([f"smallest rigid-ring tooth number Z_R,min, dZ = {dz}", str(z),
                     f"seed 003 eq 14, fitted tooth factors (seed's constants: {r['seed_constant_Z_R_min']}); "
                     + basis.split(";")[0]])
    return rows


def _crack_rows(h: dict) -> list[list[str]]:
    rows = [["torsional stiffness K_HD, uncracked", catalogue_stiffness(h["K_HD_uncracked_Nmm_per_rad"]),
             "seed 000 with the FEA-confirmed (corrected) forms"],
            [f"K_HD lost to cracks a = {h['seed_depth_mm']:g} mm in all three components",
             f"{100 * h['drop_all_three']:.2g} %", f"seed 000 claims {h['seed_claim_percent']:g} %"]]
    for c in h["components"]:
        depth = "not reached within the wall" if c["depth_for_target_mm"] is None else \
            f"a = {c['depth_for_target_mm']:.3g} mm"
        rows.append([f"crack depth costing {100 * h['target_drop']:g} % of K_HD: {c['component']}", depth,
                     f"{c['form']}; at a = {c['depth_mm']:g} mm: -{100 * c['drop_at_seed_depth']:.2g} %"])
    return rows


def designer_table(summary: dict) -> dict:
    """{columns, rows} of the headline answers, from the analytic summary (seed 003's and seed 000's)."""
    rows = (_tooth_rows(summary["seed003"]) if "seed003" in summary else []) + \
        (_crack_rows(summary["crack_headline"]) if "crack_headline" in summary else [])
    return {"columns": list(DESIGNER_COLUMNS), "rows": rows}
