"""Decision 069, item 3: the circular spline's body and the WG outer ring under the two mesh zones' loads, by the
inextensible thin ring's Fourier series (Timoshenko; the diametral check: a ring pulled by two opposite point loads
P opens by (pi/4 - 2/pi) P R^3 / EI). Per zone: tangential F_t = T / (2 r_p), radial F_r = F_t tan(alpha).

Circular spline: a ring held against rotation by its bolts (a uniform shear reaction), its teeth loaded at the two
major axes. Twist per unit torque, at the teeth:
- tangential pair (even harmonics n >= 2): v(0) = 2 F_t R^3 / (pi E I) sum 1 / (n^2 (n^2 - 1)^2); twist v(0) / R;
- radial pair (the mesh pushed apart): u(0) = 2 F_r R^3 / (pi E I) sum 1 / (n^2 - 1)^2; the rack's flank gap
  opens by u tan(alpha), closed by a twist u tan(alpha) / r_p.
WG outer ring: the same radial pair on the ring alone (no balls: an upper bound), and the ring on the ball bed (the
chain's own Hetenyi term already holds it): the n = 2 ring stiffness 9 E I / R^4 beside the bed's k.
Geometry: the rules' drive (analytic/catalogue_rules.MeshRules, fatigue rim); the circular spline's outer diameter
1.25 d and face width 0.1875 d (the shipped gear's 200 / 160 and 30 / 160). Run: .venv/bin/python
benchmarks/catalogue_ring_bodies.py [SIZE]
"""
from __future__ import annotations

import json
import math
import sys

from strainwave.analytic.catalogue_rules import MeshRules
from strainwave.analytic.cs_ring import S_RADIAL, ring_mesh_twist_rad_per_Nmm

CS_OUTER_OVER_D = 200.0 / 160.0        # shipped circular spline: outer diameter / d1


def ring_twist_per_torque(R_mm, EI_Nmm2, r_p_mm, alpha_rad):
    return ring_mesh_twist_rad_per_Nmm(R_mm, EI_Nmm2, r_p_mm, math.degrees(alpha_rad))


def main(size: float) -> None:
    rules = MeshRules()
    d = rules.pitch_diameter_mm(size)
    E = rules.E_MPa
    assert abs(4.0 * S_RADIAL / math.pi - (math.pi / 4.0 - 2.0 / math.pi)) < 1e-6     # the diametral check
    for ratio in (30.0, 50.0, 100.0):
        design = rules.design(size, ratio)
        g = design.geometry
        r_p, m, b, a = g.pitch_radius_mm, g.module_mm, g.face_width_mm, math.radians(g.pressure_angle_deg)
        root_cs = r_p + 1.25 * m                                  # internal teeth: the root lies outward
        h_cs = 0.5 * CS_OUTER_OVER_D * d - root_cs
        R_cs = root_cs + 0.5 * h_cs
        cs_t, cs_r = ring_twist_per_torque(R_cs, E * b * h_cs ** 3 / 12.0, r_p, a)
        t_ring = design.bearing_outer_ring_mm
        R_ring = g.neutral_radius_mm - 0.5 * g.rim_thickness_mm - 0.5 * t_ring
        EI_ring = E * b * t_ring ** 3 / 12.0
        _, ring_free = ring_twist_per_torque(R_ring, EI_ring, r_p, a)
        k_ring_n2 = 9.0 * EI_ring / R_ring ** 4
        print(json.dumps({"size": size, "ratio": ratio, "d_mm": d, "cs_h_mm": h_cs, "cs_R_mm": R_cs,
                          "cs_h_over_R": h_cs / R_cs, "cs_tangential_rad_per_Nmm": cs_t,
                          "cs_radial_rad_per_Nmm": cs_r, "cs_total_rad_per_Nmm": cs_t + cs_r,
                          "wg_ring_free_rad_per_Nmm": ring_free, "wg_ring_n2_N_per_mm2": k_ring_n2,
                          "ball_bed_N_per_mm2": design.foundation_N_per_mm2,
                          "rim_mm": g.rim_thickness_mm}))


if __name__ == "__main__":
    main(float(sys.argv[1]) if len(sys.argv) > 1 else 25.0)
