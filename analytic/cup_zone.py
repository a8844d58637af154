"""The cup's extra twist when the torque enters at the two mesh zones (decision 067, cat48b), net of the plane
rim the reduced mesh model already holds (decision 075-catzone48).

The chain's cup term (analytic.torsion.cup_series_flexibility) takes the torque into the tube as a uniform
shear flow. In the drive the teeth in contact near the two major axes put it in, on the open end of a wall that
the wave generator holds radially only where the cam touches. ``fea.cup_zone_load`` measures the wall's
work-conjugate flexibility under the tooth loads (this drive's own, from its mesh model at the rated torque) and
under the uniform shear on the same mesh; the difference (the gross term) holds the plane rim's response, which the
mesh model's rim beam already counts (decision 075: 0.66-0.91 of it), so the term added in series is the gross less
the plane annulus under the same loads (``fea.drive_assembled.zone_members``, the validate chain's own net; decision
073-assembled48). It is measured on three
meshes (GCI) at a reference size for each ratio; at a fixed ratio the rules make every drive similar (all
lengths ~ d, the tooth-load shape independent of d), so it scales as (d_ref / d)^3 (tests/test_cup_zone.py).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from strainwave.fea.result import Quantity

__all__ = ["teeth_tangential_loads", "teeth_rated_loads", "CupZoneTerm", "cup_zone_term"]


def teeth_tangential_loads(design, torque_Nmm: float) -> tuple[np.ndarray, np.ndarray]:
    """(angle of each loaded flank pair's tooth, its tangential load F cos(alpha) N) of the mesh model at
    ``torque_Nmm`` (wave-generator angle 0; first loading); a reverse flank (negative lever) pushes the other way."""
    phi, lever, F = teeth_rated_loads(design, torque_Nmm)
    return phi, np.sign(lever) * F * math.cos(math.radians(design.geometry.pressure_angle_deg))


def teeth_rated_loads(design, torque_Nmm: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(tooth angle, signed lever mm, normal force N) of each flank pair the mesh model loads at ``torque_Nmm``
    (wave-generator angle 0; first loading)."""
    from strainwave.analytic.mesh_drive import mesh_system
    from strainwave.analytic.mesh_kinematics import teeth_on_neutral_line
    from strainwave.fea.mesh_contact import solve_torque_path
    system, tooth = mesh_system(design, 0.0)
    F = solve_torque_path(system, np.linspace(0.0, torque_Nmm, 11)).forces_N[-1]
    on = F > 0.0
    return teeth_on_neutral_line(design.geometry, 0.0).angle_rad[tooth][on], system.lever_mm[on], F[on]


@dataclass(frozen=True)
class CupZoneTerm:
    """The extra cup flexibility of one ratio at the reference pitch diameter, with its three-mesh record."""

    ratio: float
    reference_d_mm: float
    extra: Quantity              # the net term added in series: gross minus the plane annulus, rad/(N mm), with GCI
    uniform: Quantity            # the uniform shear on the same meshes (the tube alone, no diaphragm)
    teeth: Quantity              # the wall under the teeth's loads
    cpu_s: float
    gross: Quantity | None = None    # teeth minus uniform (decision 067's term, before 075), recorded beside

    def at(self, d_mm: float) -> float:
        """The term at pitch diameter ``d_mm`` (similitude at a fixed ratio: ~ 1 / d^3)."""
        return self.extra.value * (self.reference_d_mm / d_mm) ** 3

    def to_dict(self) -> dict:
        def q(x: Quantity) -> dict:
            c = x.convergence
            return {"value": x.value, "unit": x.unit, "gci_fine": c.gci_fine, "observed_order": c.observed_order,
                    "h_mm": list(c.h_mm), "values": list(c.values)}
        return {"ratio": self.ratio, "reference_d_mm": self.reference_d_mm, "extra_rad_per_Nmm": q(self.extra),
                "uniform_rad_per_Nmm": q(self.uniform), "teeth_rad_per_Nmm": q(self.teeth), "cpu_s": self.cpu_s,
                **({"gross_rad_per_Nmm": q(self.gross)} if self.gross is not None else {})}


def cup_zone_term(design, torque_Nmm: float, elements: tuple[int, int, int], ratio: float) -> CupZoneTerm:
    """The term of ``design`` (a drive at the reference size) on wall meshes of ``elements`` around the quarter
    (finest first): the wall's extra under the mesh model's rated loads net of the plane annulus (decision 075)."""
    import time
    from strainwave.fea import cup_zone_load as cz
    from strainwave.fea import drive_assembled as da
    from strainwave.fea.assembly import Lame
    from strainwave.fea.refinement import converged_quantity
    t0 = time.process_time()
    g = design.geometry
    phi, lever, F = teeth_rated_loads(design, torque_Nmm)
    geo = cz.tube_of_design(design)
    lame = Lame.from_young(design.E_MPa, 0.3)
    g2 = da.annulus_modes(geo.r_i_mm, geo.r_o_mm, g.face_width_mm, 0.5 * geo.wall_mm, lame, da.HARMONICS)
    runs = [da.zone_terms(geo, n, lame, g.w0_mm, phi, lever, F, g.face_width_mm, g2) for n in elements]
    h = [0.5 * math.pi * geo.r_m_mm / n for n in elements]
    unit = "rad/(N*mm)"
    q = {k: converged_quantity(f"cup_zone_{k}_flexibility_rad_per_Nmm", unit, h, v) for k, v in {
        "uniform": [r["uniform"] for r in runs], "teeth": [r["uniform"] + r["gross"] for r in runs],
        "gross": [r["gross"] for r in runs], "extra": [r["net"] for r in runs]}.items()}
    return CupZoneTerm(ratio, 2.0 * g.pitch_radius_mm, q["extra"], q["uniform"], q["teeth"],
                       time.process_time() - t0, q["gross"])
