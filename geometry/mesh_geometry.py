"""The tooth mesh's geometry from the parameters: the cup's teeth, the circular spline's space and teeth, and
the radii the kinematic engagement (analytic/mesh_engagement.py) and the FE study (fea/tooth_mesh.py) share."""
from __future__ import annotations

from dataclasses import dataclass

from strainwave.geometry.involute import ToothSpec, cup_tooth_spec

__all__ = ["MeshGeometry", "mesh_geometry"]


@dataclass(frozen=True)
class MeshGeometry:
    fs: ToothSpec                  # the cup's external teeth
    cs_space: ToothSpec            # the CS's tooth space, as the external tooth of Z_c that fills it
    cs_tooth: ToothSpec            # the CS's internal teeth (the complement of that space)
    r_neutral_mm: float            # FS rim's neutral line (mid-wall under the teeth)
    r_bore_mm: float
    cs_tip_mm: float               # CS internal tip radius
    w0_mm: float
    backlash_mm: float             # per flank, circumferential, at the CS pitch circle
    face_width_mm: float
    cs_outer_radius_mm: float

    @property
    def z_f(self) -> int:
        return self.fs.teeth

    @property
    def z_c(self) -> int:
        return self.cs_space.teeth


def mesh_geometry(params) -> MeshGeometry:
    fc, cs, g = params.flexspline_cup, params.circular_spline, params.gear
    fs = cup_tooth_spec(params)
    z_c = fc.teeth + g.wave_number
    x = fs.shift_coef
    space = ToothSpec(z_c, fc.module_mm, cs.pressure_angle_deg, cs.addendum_coefficient, 1.35,
                      internal=False, shift_coef=x)
    # the CS's own teeth: the complement of that space. An internal ToothSpec carries its shift in its radii and
    # thins its tooth by it (involute.py since the circular-spline part): tip r_p + (x - h_a) m, root r_p + (x + 1.35) m
    cs_tooth = ToothSpec(z_c, fc.module_mm, cs.pressure_angle_deg, cs.addendum_coefficient, 1.35,
                         internal=True, shift_coef=x)
    cs_tip = space.pitch_radius_mm + (x - cs.addendum_coefficient) * fc.module_mm
    r_bore = 0.5 * fc.pitch_diameter_mm - fc.wall_thickness_mm
    return MeshGeometry(fs, space, cs_tooth, r_bore + 0.5 * fc.wall_thickness_mm, r_bore, cs_tip,
                        g.radial_deformation_mm, cs.backlash_mm, min(cs.face_width_mm, 0.2 * fc.pitch_diameter_mm),
                        0.5 * cs.outer_diameter_mm)
