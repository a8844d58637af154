"""A drive's teeth in mesh as a ``MeshSystem``: its geometry, its springs, and the system at a WG angle.

``MeshDesign`` is everything the closed-form mesh model needs (lengths mm, moduli MPa). It is built from a
parameter set (``design_from_params``) or, for a catalogue drive, from the design rules of
``analytic/catalogue_rules.py``. ``mesh_system`` assembles the clearances (mesh_kinematics) and the
flexibility (mesh_compliance) at one wave-generator angle.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from strainwave.analytic import mesh_compliance as mc
from strainwave.analytic.mesh_contact import MeshSystem
from strainwave.analytic.mesh_kinematics import MeshGeometry, sliced_clearances

__all__ = ["MeshDesign", "design_from_params", "mesh_system", "pair_compliance_mm_per_N"]


@dataclass(frozen=True)
class MeshDesign:
    """The tooth mesh and the springs behind it."""

    geometry: MeshGeometry
    E_MPa: float
    friction_coefficient: float
    bearing_outer_ring_mm: float        # the WG bearing's outer ring bends with the rim (second beam layer)
    foundation_N_per_mm2: float         # the WG bearing's radial foundation modulus per unit rim length
    K_G_N_per_mm: float                 # one wave-generator lobe's radial stiffness (cam and inner ring)

    @property
    def rim_I_mm4(self) -> float:
        """Rim and outer ring as two unbonded layers bending about their own mid-surfaces."""
        g = self.geometry
        return g.face_width_mm * (g.rim_thickness_mm ** 3 + self.bearing_outer_ring_mm ** 3) / 12.0

    def with_friction(self, mu: float) -> "MeshDesign":
        return replace(self, friction_coefficient=mu)


def pair_compliance_mm_per_N(design: MeshDesign) -> float:
    """One flank pair's own compliance: ISO 6336-1's c' (flexspline z1 = Z_f against internal teeth) plus the
    tooth's tilt on its thin rim."""
    g = design.geometry
    c = mc.iso6336_single_pair_stiffness_N_per_mm_um(g.teeth_flexspline, None, alpha_deg=g.pressure_angle_deg)
    b = g.face_width_mm / g.face_slices
    tilt = mc.thin_rim_tilt_compliance_mm_per_N(g.pitch_radius_mm - g.neutral_radius_mm, math.pi * g.module_mm,
                                                g.rim_thickness_mm, b, design.E_MPa, g.pressure_angle_deg)
    return mc.tooth_pair_compliance_mm_per_N(c, b) + tilt


def design_from_params(params) -> MeshDesign:
    """The shipped gear's mesh: cup, circular spline and wave generator as the parameter file gives them."""
    cup, cs, g, wg = params.flexspline_cup, params.circular_spline, params.gear, params.wave_generator
    from strainwave.analytic.catalogue_rules import MeshRules
    rules = MeshRules()
    geom = MeshGeometry(cup.teeth, cup.module_mm, g.radial_deformation_mm, cs.pressure_angle_deg,
                        cs.addendum_coefficient, cs.backlash_mm, cup.wall_thickness_mm, cs.face_width_mm,
                        g.wave_number, cup.length_mm, rules.face_slices)
    E = params.material.youngs_modulus_MPa
    return MeshDesign(geom, E, cs.flank_friction_coefficient, wg.outer_ring_thickness_mm,
                      rules.foundation_N_per_mm2(E, cs.face_width_mm, cup.pitch_diameter_mm),
                      wg.uncracked_radial_stiffness_N_per_mm)


def mesh_system(design: MeshDesign, psi_rad: float = 0.0,
                compliance: np.ndarray | None = None) -> tuple[MeshSystem, np.ndarray]:
    """The flank pairs (one per tooth, flank and face slice) in mesh at wave-generator angle ``psi_rad`` and the
    tooth each belongs to.

    ``compliance`` replaces the closed-form flexibility (the FE study passes its own, same pair order)."""
    g = design.geometry
    gap, sign, tooth, _, angles = sliced_clearances(g, psi_rad)
    alpha = math.radians(g.pressure_angle_deg)
    r = g.pitch_radius_mm
    if compliance is None:
        compliance = mc.mesh_compliance_matrix(
            angles, tooth, psi_rad=psi_rad, wave_number=g.wave_number, radius_mm=g.neutral_radius_mm,
            alpha_deg=g.pressure_angle_deg, pair_compliance_mm_per_N=pair_compliance_mm_per_N(design),
            E_MPa=design.E_MPa, rim_I_mm4=design.rim_I_mm4, foundation_N_per_mm2=design.foundation_N_per_mm2,
            K_G_N_per_mm=design.K_G_N_per_mm, tooth_height_mm=r - g.neutral_radius_mm, flank_sign=sign)
    system = MeshSystem(gap, compliance, sign * r * math.cos(alpha), np.full(len(gap), r * math.sin(alpha)),
                        design.friction_coefficient, r)
    return system, tooth
