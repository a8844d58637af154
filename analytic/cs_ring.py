"""The circular spline's body under the two mesh zones' loads: an inextensible thin ring (Timoshenko's Fourier
series), held against rotation by its bolts (a uniform shear reaction), loaded at the two major axes by the
tangential F_t = T / (2 r_p) and the radial F_r = F_t tan(alpha) of each zone (decision 069, item 3).

Per harmonic n >= 2 (even: the two zones are opposite), bending only: a tangential pair twists the ring's teeth by
v(0) / R = 2 F_t R^2 / (pi E I) sum 1 / (n^2 (n^2 - 1)^2); a radial pair opens it by u(0) = 2 F_r R^3 / (pi E I)
sum 1 / (n^2 - 1)^2 (two opposite point loads P open a ring's diameter by (pi/4 - 2/pi) P R^3 / EI), which the rack
flank closes by a twist u tan(alpha) / r_p. A ring free in its plane is the soft bound: a housing clamping the
body's face restrains the ovalisation (not modelled).
"""
from __future__ import annotations

import math

__all__ = ["ring_mesh_twist_rad_per_Nmm", "cs_body_twist_rad_per_Nmm", "S_TANGENTIAL", "S_RADIAL"]

_EVEN = range(2, 2000, 2)
S_TANGENTIAL = sum(1.0 / (n * n * (n * n - 1.0) ** 2) for n in _EVEN)
S_RADIAL = sum(1.0 / (n * n - 1.0) ** 2 for n in _EVEN)


def ring_mesh_twist_rad_per_Nmm(R_mm: float, EI_Nmm2: float, r_p_mm: float, alpha_deg: float) -> tuple[float, float]:
    """(tangential, radial) output twist per N mm of a ring of mid-radius ``R_mm`` loaded at two opposite mesh
    zones at the pitch radius ``r_p_mm``."""
    a = math.radians(alpha_deg)
    F_t = 1.0 / (2.0 * r_p_mm)
    F_r = F_t * math.tan(a)
    v0 = 2.0 * F_t * R_mm ** 3 / (math.pi * EI_Nmm2) * S_TANGENTIAL
    u0 = 2.0 * F_r * R_mm ** 3 / (math.pi * EI_Nmm2) * S_RADIAL
    return v0 / R_mm, u0 * math.tan(a) / r_p_mm


def cs_body_twist_rad_per_Nmm(design, outer_diameter_mm: float) -> float:
    """The circular spline body's twist per N mm (tangential + radial) for a drive of ``analytic.mesh_drive``:
    the body from the internal teeth's root (r_p + 1.25 m) to ``outer_diameter_mm`` / 2, the face width wide."""
    g = design.geometry
    root = g.pitch_radius_mm + 1.25 * g.module_mm
    h = 0.5 * outer_diameter_mm - root
    if not h > 0.0:
        raise ValueError(f"the circular spline's outer diameter {outer_diameter_mm:g} mm is inside its root")
    EI = design.E_MPa * g.face_width_mm * h ** 3 / 12.0
    return sum(ring_mesh_twist_rad_per_Nmm(root + 0.5 * h, EI, g.pitch_radius_mm, g.pressure_angle_deg))
