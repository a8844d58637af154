"""The ratcheting torque beside the design verdict (issue 48, item 2): the tooth-mesh FE's value with its GCI, the
closed form's (analytic/drive_curve.ratcheting_torque_Nm) and the Harmonic Drive CSF catalogue's nearest row.

Both models push the flexspline in by the radial part of the flank loads against the wave generator's radial
stiffness until a radial overlap is used up; they differ in what they hold (docs/decisions/069-ratchet48-ratcheting.md):
- FE: the FE contact solve's flank loads at rated, each at its own pressure angle at the CS contact radius; one
  lobe's K_G only (the FE rim sits on a rigid bore); the overlap at the loaded pairs (load-weighted), each pair
  losing delta cos 2 phi of it as the lobe's approach delta shrinks the wave.
- closed form: its own flank loads at the nominal pressure angle; K_G plus the rim bending on the bearing's
  foundation; the full working depth 2 h_a m at the major axis against the largest lift.
The catalogue is shown, not asserted: its drives are not this gear (their teeth are not involutes, their rims
thinner), and no fit is made to it.
"""
from __future__ import annotations

import math

__all__ = ["CSF_RATCHETING_NM", "ratcheting_record", "nearest_csf_ratcheting", "ratcheting_line"]

# Harmonic Drive LLC CSF/CSG catalogue, Table 4, ratcheting torque N m by size and ratio (tooth-mesh-references.md s. 3)
CSF_RATCHETING_NM = {
    8: {30: 11, 50: 12, 100: 14}, 11: {30: 29, 50: 34, 100: 43}, 14: {30: 59, 50: 88, 80: 110, 100: 84},
    17: {30: 100, 50: 150, 80: 200, 100: 160, 120: 120}, 20: {30: 170, 50: 220, 80: 350, 100: 260, 120: 240, 160: 220},
    25: {30: 340, 50: 450, 80: 680, 100: 500, 120: 470, 160: 450},
    32: {30: 720, 50: 980, 80: 1400, 100: 1000, 120: 980, 160: 980},
    40: {50: 1800, 80: 2800, 100: 2100, 120: 1900, 160: 1800}, 45: {50: 2700, 80: 3900, 100: 3100, 120: 2800, 160: 2600},
    50: {50: 3700, 80: 5400, 100: 4100, 120: 3800, 160: 3600}, 58: {50: 5800, 80: 8200, 100: 6400, 120: 5800, 160: 5600}}
INCH_MM = 25.4


def nearest_csf_ratcheting(pitch_diameter_mm: float, ratio: float) -> tuple[int, int, float, float]:
    """(CSF size, ratio, its ratcheting torque N m, that torque scaled by (d / d_size)^3 to this pitch diameter): the
    nearest size and the nearest ratio it offers (size = pitch diameter in tenths of an inch)."""
    size = pitch_diameter_mm / (0.1 * INCH_MM)
    near = min(CSF_RATCHETING_NM, key=lambda s: abs(s - size))
    row = CSF_RATCHETING_NM[near]
    r = min(row, key=lambda k: abs(k - ratio))
    return near, r, float(row[r]), float(row[r]) * (size / near) ** 3


def ratcheting_record(params, book, label: str | None) -> dict | None:
    """The FE's ratcheting torque (GCI), the closed form's and the catalogue's nearest row, all over rated."""
    if not label:
        return None
    q = book.quantity(label, "ratcheting_torque_Nmm")[0]
    if q is None or not math.isfinite(q.value):
        return None
    from strainwave.analytic.drive_curve import ratcheting_torque_Nm
    from strainwave.analytic.mesh_drive import design_from_params
    closed = 1e3 * ratcheting_torque_Nm(design_from_params(params))
    rated = params.gear.rated_output_torque_Nmm
    size, ratio, csf, scaled = nearest_csf_ratcheting(params.flexspline_cup.pitch_diameter_mm, params.gear.gear_ratio)
    return {"fe_torque_Nmm": q.value, "fe_gci_Nmm": q.uncertainty, "closed_form_torque_Nmm": closed,
            "rated_torque_Nmm": rated, "fe_over_rated": q.value / rated, "closed_form_over_rated": closed / rated,
            "fe_over_closed_form": q.value / closed, "csf_size": size, "csf_ratio": ratio, "csf_torque_Nm": csf,
            "csf_scaled_torque_Nm": scaled, "fe_over_csf_scaled": q.value / (1e3 * scaled),
            "note": "the catalogue is shown, not asserted (decision 069-ratchet48)"}


def ratcheting_line(r: dict) -> str:
    gci = "no GCI" if r.get("fe_gci_Nmm") is None else f"GCI +- {r['fe_gci_Nmm'] / 1e3:.3g} N m"
    return (f"Ratcheting torque (tooth-mesh FE: the loaded teeth's radial push against one WG lobe's K_G uses up their "
            f"overlap): {r['fe_torque_Nmm'] / 1e3:.4g} N m ({gci}) = {r['fe_over_rated']:.3g} x rated; closed form "
            f"(analytic/drive_curve.py, + the rim's bending on the bearing, full working depth) "
            f"{r['closed_form_torque_Nmm'] / 1e3:.4g} N m ({r['closed_form_over_rated']:.3g} x); beside them CSF-"
            f"{r['csf_size']} at i = {r['csf_ratio']}: {r['csf_torque_Nm']:g} N m, {r['csf_scaled_torque_Nm']:.4g} N m "
            f"scaled by d^3 (FE over it {r['fe_over_csf_scaled']:.3g}; shown, not asserted: the FE holds the rim on a "
            "rigid bore and only the lobe's K_G yields, so it is an upper bound)")
