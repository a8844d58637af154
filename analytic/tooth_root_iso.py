"""ISO 6336-3 (method B) tooth-root stress of one flank load on the flexspline's tooth: the closed form beside the
tooth-mesh FE's filleted sector (fea/tooth_root_fe.py), on the SAME tooth, fillet, load and load radius.

sigma_F = F_n cos(alpha_Fen) 6 h_Fe / (b s_Fn^2) * Y_S * Y_B    (ISO's F_t/(b m) Y_F Y_S with F_n = F_t / cos alpha_n)

- critical section: the two points where the fillet's tangent makes 30 deg with the tooth's centre line (ISO's
  method B for external teeth), on the cup's circular fillet (geometry/involute._fitted_fillet): s_Fn its chord;
- the load: the flank normal at the contact radius r (ISO takes the outer point of single contact; here the FE's
  own load radius, so both hold one problem): alpha_Fen = alpha_r - psi(r), the involute's pressure angle there
  minus the tooth's polar half-angle; h_Fe the lever from where that line crosses the centre line to the section;
- Y_S = (1.2 + 0.13 L) q_s^(1 / (1.21 + 2.3 / L)), L = s_Fn / h_Fe, q_s = s_Fn / (2 rho_F) (ISO 6336-3 eq. for
  Y_S, valid 1 <= q_s < 8); Y_B = 1.6 ln(2.242 h_t / s_R) for 0.5 < s_R / h_t < 1.2, else 1 (the thin rim).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["IsoRootStress", "iso_root_stress"]


@dataclass(frozen=True)
class IsoRootStress:
    stress_MPa: float
    nominal_MPa: float           # F cos(alpha_Fen) 6 h_Fe / (b s_Fn^2): Y_F's part
    s_Fn_mm: float
    h_Fe_mm: float
    alpha_Fen_deg: float
    rho_F_mm: float
    Y_S: float
    Y_B: float
    q_s: float


def iso_root_stress(spec, fillet_rho_mm: float, fillet_dphi_rad: float, contact_radius_mm: float, force_N: float,
                    face_width_mm: float, bore_radius_mm: float) -> IsoRootStress:
    """ISO 6336-3 method B root stress of an external tooth (``spec``: geometry/involute.ToothSpec) with a circular
    root fillet of radius ``fillet_rho_mm`` centred ``fillet_dphi_rad`` off the tooth's centre line."""
    from strainwave.geometry.involute import half_angle_rad
    if spec.internal:
        raise ValueError("iso_root_stress: external teeth only")
    rho = fillet_rho_mm
    rc = spec.root_radius_mm + rho
    cx, cy = rc * math.cos(fillet_dphi_rad), rc * math.sin(fillet_dphi_rad)
    beta = math.radians(240.0)        # the fillet normal whose tangent is 30 deg off the centre line (x axis)
    px, py = cx + rho * math.cos(beta), cy + rho * math.sin(beta)
    s_fn = 2.0 * py
    r = contact_radius_mm
    psi = float(half_angle_rad(spec, r))
    alpha_r = math.acos(min(1.0, spec.base_radius_mm / r))
    a_fen = alpha_r - psi
    x_load = r * math.cos(psi) - r * math.sin(psi) * math.tan(a_fen)
    h_fe = x_load - px
    nominal = force_N * math.cos(a_fen) * 6.0 * h_fe / (face_width_mm * s_fn ** 2)
    L, q_s = s_fn / h_fe, s_fn / (2.0 * rho)
    y_s = (1.2 + 0.13 * L) * q_s ** (1.0 / (1.21 + 2.3 / L))
    s_r, h_t = spec.root_radius_mm - bore_radius_mm, spec.tip_radius_mm - spec.root_radius_mm
    y_b = 1.6 * math.log(2.242 * h_t / s_r) if 0.5 < s_r / h_t < 1.2 else 1.0
    return IsoRootStress(nominal * y_s * y_b, nominal, s_fn, h_fe, math.degrees(a_fen), rho, y_s, y_b, q_s)
