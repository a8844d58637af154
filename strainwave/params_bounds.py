"""The physically meaningful range of every numeric parameter, stated once, with its reason.

The closed forms raise lengths to the 6th power and divide by loads; the mesher and the CAD kernel
work in absolute tolerances (OCC's 1e-7 mm confusion distance). A value the schema accepts must
therefore be one that every stage can compute with: outside these ranges a run would overflow,
underflow to zero, or ask gmsh/OCC for features below their tolerance. The ranges are wide (a
watch-sized drive to a ship's) and each names why it ends where it does.
"""
from __future__ import annotations

from dataclasses import dataclass

from strainwave.errors import InputError


@dataclass(frozen=True)
class Bound:
    lo: float
    hi: float
    why: str

    def __post_init__(self):
        if not (self.lo <= self.hi):
            raise ValueError(f"Bound: lo {self.lo!r} must be <= hi {self.hi!r}")   # a schema bug, not input


# Reasons shared by several keys.
_LENGTH = "from a 1 mm micro drive to a 10 m ring; beyond it the closed forms' 6th powers lose meaning"
_FEATURE = ("smallest feature CAD and the mesher resolve reliably (OCC's tolerance is 1e-7 mm, a slot "
            "is depth/5); largest a drive's wall could hold")
_TORQUE = "1 uN*m to 10 MN*m: below it float round-off dominates the crack flexibilities, above it no gear exists"
_TEETH = "catalogue strain wave gears have up to a few hundred teeth; CAD work grows with the tooth count"
_FACTOR = "a dimensionless design factor of order one"

BOUNDS: dict[str, Bound] = {
    "material.youngs_modulus_MPa": Bound(100.0, 2e6, "polymers (~1e3 MPa) to diamond (1.2e6 MPa)"),
    "material.shear_modulus_MPa": Bound(40.0, 1e6, "polymers to diamond"),
    "material.poisson_ratio": Bound(0.001, 0.499, "(0, 0.5): 0.5 is incompressible, where the FEA locks"),
    "material.fatigue_limit_MPa": Bound(1.0, 1e4, "polymers to the strongest steels"),
    "material.ultimate_strength_MPa": Bound(1.0, 1e4, "polymers to the strongest steels"),
    "gear.wave_number": Bound(1, 16, "strain wave gears are single- to triple-wave"),
    "gear.gear_ratio": Bound(2.0, 1e4, "a strain wave gear reduces (ratio >= 2); catalogue stages 30..320"),
    "gear.radial_deformation_mm": Bound(1e-3, 100.0, _FEATURE),
    "gear.force_coefficient": Bound(1e-3, 10.0, _FACTOR),
    "gear.output_torque_Nmm": Bound(1e-3, 1e10, _TORQUE),
    "gear.rated_output_torque_Nmm": Bound(1e-3, 1e10, _TORQUE),
    "flexspline_cup.pitch_diameter_mm": Bound(1.0, 1e4, _LENGTH),
    "flexspline_cup.wall_thickness_mm": Bound(0.01, 1e3, _FEATURE),
    "flexspline_cup.length_mm": Bound(1.0, 1e4, _LENGTH),
    "flexspline_cup.teeth": Bound(4, 2000, _TEETH),
    "flexspline_cup.module_mm": Bound(0.01, 100.0, "ISO module series run 0.05..50 mm"),
    "flexspline_cup.root_crack_depth_mm": Bound(1e-3, 1e3, _FEATURE),
    "output_shaft.outer_diameter_mm": Bound(1.0, 1e4, _LENGTH),
    "output_shaft.inner_diameter_mm": Bound(0.0, 1e4, "0 is a solid shaft; " + _LENGTH),
    "output_shaft.length_mm": Bound(1.0, 1e4, _LENGTH),
    "output_shaft.crack_depth_mm": Bound(1e-3, 1e3, _FEATURE),
    "wave_generator.bearing_inner_ring_thickness_mm": Bound(0.1, 1e3, _FEATURE),
    "wave_generator.contact_semi_axes_mm": Bound(1e-3, 1e3, _FEATURE),
    "wave_generator.beta": Bound(0.01, 1.0, "a circumferential stress factor (seed 000: 0.4278..0.5)"),
    "wave_generator.uncracked_radial_stiffness_N_per_mm": Bound(1.0, 1e12, "a bearing's radial stiffness"),
    "wave_generator.bearing_crack_depth_mm": Bound(1e-3, 1e3, _FEATURE),
    "wave_generator.ball_count": Bound(3, 200, "a ball bearing carries a few to ~100 balls; Stribeck needs >= 3"),
    "wave_generator.ball_diameter_mm": Bound(0.1, 1e3, _FEATURE),
    "wave_generator.outer_ring_thickness_mm": Bound(0.1, 1e3, _FEATURE),
    "circular_spline.pressure_angle_deg": Bound(5.0, 40.0, "involute racks from 14.5 deg to 30 deg; below 5 the flank is radial"),
    "circular_spline.addendum_coefficient": Bound(0.1, 1.5, "a tooth of some height, below the full-depth 1.25 m reach"),
    "circular_spline.flank_friction_coefficient": Bound(0.0, 0.5, "frictionless to dry steel"),
    "wave_generator.groove_radius_ratio": Bound(0.501, 0.99, "a groove wider than the ball that still conforms"),
    "wave_generator.bearing_width_mm": Bound(0.1, 1e3, _FEATURE),
    "wave_generator.input_speed_rpm": Bound(1e-3, 1e5, "a hand-turned drive to a 100 000 rpm spindle"),
    "material.yield_strength_MPa": Bound(1.0, 1e4, "polymers to the strongest steels"),
    "bearing_material.fatigue_limit_MPa": Bound(1.0, 1e4, "polymers to the strongest steels"),
    "bearing_material.yield_strength_MPa": Bound(1.0, 1e4, "polymers to the strongest steels"),
    "bearing_material.ultimate_strength_MPa": Bound(1.0, 1e4, "polymers to the strongest steels"),
    "bearing_material.static_contact_limit_MPa": Bound(1.0, 2e4, "ISO 76's 4000..4600 MPa for steel, wider for others"),
    "circular_spline.backlash_mm": Bound(0.0, 1e2, "zero (a tight mesh) to a tooth pitch's worth"),
    "circular_spline.outer_diameter_mm": Bound(1.0, 1e4, _LENGTH),
    "circular_spline.face_width_mm": Bound(0.1, 1e3, _FEATURE),
    "cracks.surface_crack_shape_factor": Bound(1.0, 10.0, "Q = 1 + 1.464 (a/c)^1.65 is 1..2.5 for a/c <= 1"),
    "cracks.stress_nonuniformity": Bound(0.1, 10.0, _FACTOR),
    "cracks.dynamic_load_factor": Bound(0.1, 10.0, _FACTOR),
    "cracks.flexspline_crack_angle_deg": Bound(0.1, 89.9, "an inclined crack, strictly between 0 and 90 deg"),
    "ewg_drive.tooth_difference": Bound(1, 16, "seed 003 works dZ = 2 and 4"),
    "ewg_drive.flexspline_teeth": Bound(2, 2000, _TEETH),
    "ewg_drive.module_mm": Bound(0.01, 100.0, "ISO module series run 0.05..50 mm"),
    "ewg_drive.rim_thickness_ratio": Bound(1e-3, 0.5, "rim / reference diameter: a rim, not a disc"),
    "ewg_drive.face_width_mm": Bound(0.1, 1e4, _LENGTH),
    "ewg_drive.dedendum_coefficient": Bound(0.1, 5.0, "h*_f is about 1.25..1.4 for standard racks"),
    "ewg_drive.pressure_angle_deg": Bound(1.0, 44.9, "involute racks use 14.5..30 deg"),
    "ewg_drive.root_fillet_coefficient": Bound(0.01, 0.5, "ISO 53 racks use 0.25..0.39"),
    "ewg_drive.tooth_influence": Bound(1.0, 10.0, "K_delta: teeth raise the rim's bending stress, never lower it"),
    "ewg_drive.stress_concentration": Bound(1.0, 10.0, "K_sigma: a concentration factor is >= 1"),
    "ewg_drive.mean_stress_influence": Bound(0.0, 0.99, "psi_sigma in [0, 1)"),
    "ewg_drive.permissible_safety": Bound(0.1, 100.0, _FACTOR),
    "crack_geometry.slot_width_mm": Bound(1e-4, 10.0, _FEATURE),
    "crack_geometry.shaft_axial_position_ratio": Bound(0.01, 0.99, "a crack inside the shaft, not at its end"),
    "crack_geometry.shaft_arc_deg": Bound(1.0, 360.0, "an arc of at least 1 deg up to the full circle"),
    "crack_geometry.flexspline_tooth_index": Bound(0, 1999, "a tooth of the cup (teeth <= 2000)"),
    "crack_geometry.flexspline_axial_position_ratio": Bound(0.01, 0.99, "a crack inside the cup, not at its end"),
}


def check_bounds(section: str, record: object) -> None:
    """Refuse any numeric field of ``record`` (a params section) outside its stated range."""
    for name, value in vars(record).items():
        bound = BOUNDS.get(f"{section}.{name}")
        if bound is None:
            continue
        for v in value if isinstance(value, tuple) else (value,):
            if not bound.lo <= v <= bound.hi:
                raise InputError(f"{section}.{name}", v, f"must lie in [{bound.lo:g}, {bound.hi:g}] ({bound.why})")
