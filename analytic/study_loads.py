"""The loads of the FEA studies that follow from seed formulas, computed here and handed to fea/ as numbers.

fea/ holds no closed form: the registry (``strainwave/registry.py``, ``Study.load_inputs``) names the
function below that gives a study its load, and ``fea.studies.run_study`` passes the numbers to the
study's ``run``. A study whose load is a parameter (the torsion studies' T) needs none.
"""
from __future__ import annotations

from . import ring, torsion

__all__ = ["bearing_ring_load", "ring_compression_load"]


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
