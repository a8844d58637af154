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
from strainwave.fea.mesh_contact import MeshSystem
from strainwave.analytic.mesh_kinematics import MeshGeometry, sliced_clearances
from strainwave.analytic.wg_bearing import BallBearing, hertz_remainder_twist_rad, linearised_foundation

__all__ = ["MeshDesign", "design_from_params", "mesh_system", "pair_compliance_mm_per_N", "bearing_foundation",
           "bearing_twist_rad"]


@dataclass(frozen=True)
class MeshDesign:
    """The tooth mesh and the springs behind it."""

    geometry: MeshGeometry
    E_MPa: float
    friction_coefficient: float
    bearing_outer_ring_mm: float        # the WG bearing's outer ring bends with the rim (second beam layer)
    foundation_N_per_mm2: float         # the WG bearing's radial foundation modulus per unit rim length
    K_G_N_per_mm: float                 # one wave-generator lobe's radial stiffness (cam and inner ring)
    # the balls (Hertz): the foundation above holds their tangent stiffness at the ball load Q_ref of the torque
    # T_ref; bearing_twist_rad adds the rest of their nonlinear approach in series. None: a linear foundation only
    bearing: BallBearing | None = None
    bearing_reference: tuple[float, float] | None = None     # (Q_ref N, T_ref N mm)

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


def bearing_foundation(geom: MeshGeometry, bearing: BallBearing, outer_ring_mm: float, E_MPa: float,
                       torque_Nmm: float, lumped_N_per_mm2: float | None) -> tuple[float, tuple[float, float]]:
    """(foundation modulus for the linear mesh model, (Q_ref, T_ref)): the balls' tangent stiffness at the load
    ``torque_Nmm`` puts on the most loaded ball (radial load per lobe T tan(alpha) / (2 r_p)), in series with an
    optional lumped foundation."""
    r = geom.pitch_radius_mm
    R = torque_Nmm * math.tan(math.radians(geom.pressure_angle_deg)) / (2.0 * r)
    EI = E_MPa * geom.face_width_mm * (geom.rim_thickness_mm ** 3 + outer_ring_mm ** 3) / 12.0
    k, Q = linearised_foundation(bearing, R, EI, lumped_N_per_mm2)
    return k, (Q, torque_Nmm)


def bearing_twist_rad(design: MeshDesign, torque_Nmm) -> np.ndarray:
    """The balls' nonlinear twist in series with the linear mesh model (zero without a bearing)."""
    T = np.asarray(torque_Nmm, float)
    if design.bearing is None or design.bearing_reference is None:
        return np.zeros_like(T)
    Q_ref, T_ref = design.bearing_reference
    g = design.geometry
    return hertz_remainder_twist_rad(T, bearing=design.bearing, Q_at_reference_N=Q_ref, reference_torque_Nmm=T_ref,
                                     pitch_radius_mm=g.pitch_radius_mm, alpha_deg=g.pressure_angle_deg)


def design_from_params(params) -> MeshDesign:
    """The shipped gear's mesh: cup, circular spline and wave generator as the parameter file gives them."""
    cup, cs, g, wg = params.flexspline_cup, params.circular_spline, params.gear, params.wave_generator
    from strainwave.analytic.catalogue_rules import MeshRules
    rules = MeshRules()
    geom = MeshGeometry(cup.teeth, cup.module_mm, g.radial_deformation_mm, cs.pressure_angle_deg,
                        cs.addendum_coefficient, cs.backlash_mm, cup.wall_thickness_mm, cs.face_width_mm,
                        g.wave_number, cup.length_mm, rules.face_slices)
    E = params.material.youngs_modulus_MPa
    # the ball set sits under the cup's bore and the outer ring: its pitch circle one ball radius further in
    bore = cup.pitch_diameter_mm - 2.0 * (1.25 * cup.module_mm + cup.wall_thickness_mm)
    balls = BallBearing(wg.ball_diameter_mm, wg.ball_count,
                        bore - 2.0 * wg.outer_ring_thickness_mm - wg.ball_diameter_mm)
    lumped = rules.lumped_foundation_N_per_mm2(E, cs.face_width_mm, cup.pitch_diameter_mm)
    k, ref = bearing_foundation(geom, balls, wg.outer_ring_thickness_mm, E, g.rated_output_torque_Nmm, lumped)
    return MeshDesign(geom, E, cs.flank_friction_coefficient, wg.outer_ring_thickness_mm, k,
                      wg.uncracked_radial_stiffness_N_per_mm, balls, ref)


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
