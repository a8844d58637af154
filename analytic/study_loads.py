"""The loads of the FEA studies that follow from seed formulas, computed here and handed to fea/ as numbers.

fea/ holds no closed form: the registry (``strainwave/registry.py``, ``Study.load_inputs``) names the
function below that gives a study its load, and ``fea.studies.run_study`` passes the numbers to the
study's ``run``. A study whose load is a parameter (the torsion studies' T) needs none.
"""
from __future__ import annotations

from strainwave.analytic import ring, torsion

__all__ = ["bearing_ring_load", "ring_compression_load", "wg_bearing_load"]


def bearing_ring_load(params) -> dict[str, float]:
    """{"force_N": F_r}: the wave generator's radial force on the bearing, F_r = 1.15 k_r T / d1 (seed 000)."""
    g = params.gear
    return {"force_N": torsion.radial_force_N(g.force_coefficient, g.output_torque_Nmm,
                                              params.flexspline_cup.pitch_diameter_mm)}


def ring_compression_load(params) -> dict[str, float]:
    """{"force_N": F, "w0_mm": W0}: the operating deformation W0 = 0.5 m dZ (seed 003, eq 7) and the thin-ring
    force that gives delta_CD = 2 W0 (eqs 3 and 5 inverted) on the rim of eq 1."""
    e, E = params.ewg_drive, params.material.youngs_modulus_MPa
    w0 = ring.radial_deformation_from_teeth_mm(e.module_mm, e.tooth_difference)
    r_m = ring.mid_layer_radius_mm(e.module_mm, e.flexspline_teeth, e.rim_thickness_mm, e.dedendum_coefficient)
    force = ring.force_for_deformation_N(w0, r_m, E, ring.second_moment_mm4(e.face_width_mm, e.rim_thickness_mm))
    return {"force_N": force, "w0_mm": w0}


def wg_bearing_load(params) -> dict:
    """The wave generator bearing on its cam (study wg-bearing): the rated F_r = 1.15 k_r T_rated / d1 (seed 000),
    the cam's radial amplitude w0 = gear.radial_deformation_mm, Stribeck's ball loads (zero clearance) over
    ``wave_generator.ball_count`` balls, each ball's patch half-width b' (Q/F_r)^(1/3) (Hertz, the seed's
    ellipse taken at F_r: the patches spread each ball's load on the race, whose bending does not see their width)
    and the Hertz constant K_n of one ball between its two grooves as built (analytic/wg_contact.py: ball diameter,
    groove radius, race radii; issue 49)."""
    from strainwave.analytic import wg_bearing, wg_contact
    from strainwave.geometry.bearing_ring import check_ring_fits

    g, wg, mat = params.gear, params.wave_generator, params.material
    force = torsion.radial_force_N(g.force_coefficient, g.rated_output_torque_Nmm, params.flexspline_cup.pitch_diameter_mm)
    psi, q = wg_bearing.stribeck_ball_loads(force, wg.ball_count)
    b = wg.contact_semi_axes_mm[1] * (q / force) ** (1.0 / 3.0)
    return {"force_N": force, "w0_mm": g.radial_deformation_mm, "ball_angles_rad": tuple(psi.tolist()),
            "ball_loads_N": tuple(q.tolist()), "patch_half_widths_mm": tuple(b.tolist()), "ball_count": wg.ball_count,
            "hertz_constant": wg_contact.ball_spring_constant(wg.ball_diameter_mm, wg.groove_radius_ratio,
                                                              check_ring_fits(params)[0], mat.youngs_modulus_MPa,
                                                              mat.poisson_ratio)}
