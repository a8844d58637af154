"""The circular spline's body with its bolted face, in series with the drive (issue 48 item 5, decision 070).

``fea.cs_housing_fe`` measures the body's twist under the two mesh zones (tangential + radial, per unit output
torque) with its mounting face clamped to a rigid housing, on three lattices (GCI). The whole face clamped is the
stiff bound of any one-face mounting (decision 070: nothing here sources a bolt pattern); the free ring of
``analytic.cs_ring`` (and the same FE with ``Restraint.FREE``) is the soft bound. At a fixed ratio the catalogue
rules make every body similar (all lengths ~ d), so the twist scales as (E_ref / E)(d_ref / d)^3: the FE runs
once per ratio at the rules' reference size and is kept for the process.
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from functools import lru_cache

from strainwave.fea.result import Quantity

__all__ = ["CsBodyTerm", "cs_body_term", "body_case_of_design", "body_case_of_params", "cs_body_term_of_case", "LEVELS"]

LEVELS = (3, 2, 1)          # fea.cs_housing_fe lattice levels, finest first (5 / k deg around the quarter)


@dataclass(frozen=True)
class CsBodyTerm:
    """The body's twist per N mm at the reference pitch diameter and modulus, with its three-lattice record."""

    restraint: str
    reference_d_mm: float
    reference_E_MPa: float
    twist: Quantity              # tangential + radial, rad/(N mm)
    tangential: Quantity
    radial: Quantity
    cpu_s: float

    def at(self, d_mm: float, E_MPa: float | None = None) -> float:
        """The term at pitch diameter ``d_mm`` (similar bodies: ~ 1 / (E d^3))."""
        e = 1.0 if E_MPa is None else self.reference_E_MPa / E_MPa
        return self.twist.value * e * (self.reference_d_mm / d_mm) ** 3

    def to_dict(self) -> dict:
        def q(x: Quantity) -> dict:
            c = x.convergence
            return {"value": x.value, "gci_fine": c.gci_fine, "observed_order": c.observed_order,
                    "h_mm": list(c.h_mm), "values": list(c.values)}
        return {"restraint": self.restraint, "reference_d_mm": self.reference_d_mm, "twist_rad_per_Nmm": q(self.twist),
                "tangential_rad_per_Nmm": q(self.tangential), "radial_rad_per_Nmm": q(self.radial),
                "cpu_s": self.cpu_s}


def body_case_of_design(design, outer_diameter_mm: float, restraint: str):
    """The body of a drive of ``analytic.mesh_drive`` (catalogue rules): root r_p + 1.25 m (the rack's dedendum,
    as analytic.cs_ring) to ``outer_diameter_mm`` / 2, the face width wide, the teeth's loads at r_p."""
    from strainwave.fea.cs_housing_fe import BodyCase, Restraint
    g = design.geometry
    return BodyCase(g.pitch_radius_mm + 1.25 * g.module_mm, 0.5 * outer_diameter_mm, g.face_width_mm,
                    g.pitch_radius_mm, g.pressure_angle_deg, design.E_MPa, Restraint(restraint))


def body_case_of_params(params, restraint: str):
    """This gear's own circular spline: the CAD's root circle of the internal teeth to its outer diameter, its
    face width, the loads at its pitch radius."""
    from strainwave.fea.cs_housing_fe import BodyCase, Restraint
    from strainwave.geometry.involute import circular_spline_tooth_spec
    spec, cs = circular_spline_tooth_spec(params), params.circular_spline
    return BodyCase(spec.root_radius_mm, 0.5 * cs.outer_diameter_mm, cs.face_width_mm, spec.pitch_radius_mm,
                    cs.pressure_angle_deg, params.material.youngs_modulus_MPa, Restraint(restraint))


@lru_cache(maxsize=16)
def _solved(case) -> CsBodyTerm:
    from strainwave.fea.cs_housing_fe import cs_housing_twist_rad_per_Nmm
    from strainwave.fea.refinement import converged_quantity
    t0 = time.process_time()
    runs = [cs_housing_twist_rad_per_Nmm(case, k)[0] for k in LEVELS]
    h = [(case.ro_mm - case.ri_mm) / k for k in LEVELS]
    unit = "rad/(N*mm)"
    q = {name: converged_quantity(f"cs_body_{name}_twist_rad_per_Nmm", unit, h, [r[name] for r in runs])
         for name in ("tangential", "radial")}
    total = converged_quantity("cs_body_twist_rad_per_Nmm", unit, h, [sum(r.values()) for r in runs])
    return CsBodyTerm(case.restraint.value, 2.0 * case.r_p_mm, case.E_MPa, total, q["tangential"], q["radial"],
                      time.process_time() - t0)


def cs_body_term(design, outer_diameter_mm: float, restraint: str = "face") -> CsBodyTerm:
    """The body's term for ``design`` (a drive at the reference size), solved once per distinct body."""
    return _solved(body_case_of_design(design, outer_diameter_mm, restraint))


def cs_body_term_of_case(case) -> CsBodyTerm:
    """The term of any ``fea.cs_housing_fe.BodyCase`` (this gear's own body), solved once per process."""
    return _solved(case)
