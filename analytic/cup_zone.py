"""The cup's extra twist when the torque enters at the two mesh zones (decision 067, cat48b).

The chain's cup term (analytic.torsion.cup_series_flexibility) takes the torque into the tube as a uniform
shear flow. In the drive the teeth in contact near the two major axes put it in, on the open end of a wall that
the wave generator holds radially only where the cam touches. ``fea.cup_zone_load`` measures the wall's
work-conjugate flexibility under the tooth loads (this drive's own, from its mesh model at the rated torque) and
under the uniform shear on the same mesh; the difference is the term added in series. It is measured on three
meshes (GCI) at a reference size for each ratio; at a fixed ratio the rules make every drive similar (all
lengths ~ d, the tooth-load shape independent of d), so it scales as (d_ref / d)^3 (tests/test_cup_zone.py).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from strainwave.fea.result import Quantity

__all__ = ["teeth_tangential_loads", "CupZoneTerm", "cup_zone_term"]


def teeth_tangential_loads(design, torque_Nmm: float) -> tuple[np.ndarray, np.ndarray]:
    """(angle of each loaded flank pair's tooth, its tangential load F cos(alpha) N) of the mesh model at
    ``torque_Nmm`` (wave-generator angle 0; first loading)."""
    from strainwave.analytic.mesh_drive import mesh_system
    from strainwave.analytic.mesh_kinematics import teeth_on_neutral_line
    from strainwave.fea.mesh_contact import solve_torque_path
    g = design.geometry
    system, tooth = mesh_system(design, 0.0)
    F = solve_torque_path(system, np.linspace(0.0, torque_Nmm, 11)).forces_N[-1]
    on = F > 0.0
    angles = teeth_on_neutral_line(g, 0.0).angle_rad[tooth]
    # a reverse flank (negative lever) pushes the other way round
    return angles[on], (np.sign(system.lever_mm) * F * math.cos(math.radians(g.pressure_angle_deg)))[on]


@dataclass(frozen=True)
class CupZoneTerm:
    """The extra cup flexibility of one ratio at the reference pitch diameter, with its three-mesh record."""

    ratio: float
    reference_d_mm: float
    extra: Quantity              # teeth-zone minus uniform flexibility, rad/(N mm), GCI of the difference
    uniform: Quantity            # the uniform shear on the same meshes (the tube alone, no diaphragm)
    teeth: Quantity
    cpu_s: float

    def at(self, d_mm: float) -> float:
        """The term at pitch diameter ``d_mm`` (similitude at a fixed ratio: ~ 1 / d^3)."""
        return self.extra.value * (self.reference_d_mm / d_mm) ** 3

    def to_dict(self) -> dict:
        def q(x: Quantity) -> dict:
            c = x.convergence
            return {"value": x.value, "unit": x.unit, "gci_fine": c.gci_fine, "observed_order": c.observed_order,
                    "h_mm": list(c.h_mm), "values": list(c.values)}
        return {"ratio": self.ratio, "reference_d_mm": self.reference_d_mm, "extra_rad_per_Nmm": q(self.extra),
                "uniform_rad_per_Nmm": q(self.uniform), "teeth_rad_per_Nmm": q(self.teeth), "cpu_s": self.cpu_s}


def cup_zone_term(design, torque_Nmm: float, elements: tuple[int, int, int], ratio: float) -> CupZoneTerm:
    """The term of ``design`` (a drive at the reference size) on meshes of ``elements`` around the quarter
    (finest first)."""
    import time
    from strainwave.fea import cup_zone_load as cz
    from strainwave.fea.refinement import converged_quantity
    t0 = time.process_time()
    g = design.geometry
    angles, Ft = teeth_tangential_loads(design, torque_Nmm)
    zones = {"uniform": cz.uniform_zone(), "teeth": cz.tooth_zone(angles, Ft, 2.0 * math.pi / g.teeth_flexspline)}
    geo = cz.tube_of_design(design)
    h = [0.5 * math.pi * geo.r_m_mm / n for n in elements]
    runs = [cz.zone_flexibilities(design, n, zones) for n in elements]
    unit = "rad/(N*mm)"
    quantity = {k: converged_quantity(f"cup_zone_{k}_flexibility_rad_per_Nmm", unit, h, [r[k] for r in runs])
                for k in ("uniform", "teeth")}
    extra = converged_quantity("cup_zone_extra_flexibility_rad_per_Nmm", unit, h,
                               [r["teeth"] - r["uniform"] for r in runs])
    return CupZoneTerm(ratio, 2.0 * g.pitch_radius_mm, extra, quantity["uniform"], quantity["teeth"],
                       time.process_time() - t0)
