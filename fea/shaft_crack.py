"""Shaft crack sweep: delta lambda(a) on three meshes per depth, and the energy release rate from it.

Compliance method (Irwin-Kies): for a torque T, G = (T^2 / 2) d lambda / dA with A the crack area
(an annulus pi (r_o^2 - (r_o - a)^2) times the arc fraction). Seed 000's eq 4 integrates
K_III^2 / mu over A, i.e. T^2 d lambda/dA = K_III^2 / mu, so G = K_III^2 / (2 mu) for mode III. The
handbook K_III it uses (M_M series) is for a circumferentially cracked SOLID bar; the FEA shaft is hollow
(d_i / d = 0.64 by default), so agreement is not expected near the bore - the comparison shows by how much.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Sequence

from .result import StudyResult
from .shaft_torsion import run


@dataclass(frozen=True)
class EnergyReleaseRate:
    a_mm: float                      # mid depth of the two sweep points
    G_fea_N_per_mm: float            # (T^2/2) (delta lambda_2 - delta lambda_1) / (A_2 - A_1)
    G_fea_uncertainty_N_per_mm: float  # from the GCI bands of both delta lambdas
    G_K_III_published_N_per_mm: float  # K_III^2 / (2 mu), seed 000 as printed (solid bar)
    G_K_III_corrected_N_per_mm: float  # K_III^2 / (2 mu), corrected M_M series (solid bar)

    def to_dict(self) -> dict:
        return dict(self.__dict__)


def crack_area_mm2(params, depth_mm: float) -> float:
    r_o = params.output_shaft.outer_diameter_mm / 2
    return math.pi * (r_o ** 2 - (r_o - depth_mm) ** 2) * params.crack_geometry.shaft_arc_deg / 360.0


def crack_sweep(params, depths_mm: Sequence[float], *, mesh_size_mm: float | None = None, order: int = 2,
                progress: Callable[[str], None] = lambda m: None, quick: bool = False) -> list[StudyResult]:
    """shaft-torsion with each crack depth. Each depth solves its own seam meshes closed and opened (the
    uncracked flexibility of every run then comes from the mesh its crack is embedded in); the cache
    only shares the uncracked part's geometry."""
    cache: dict = {}
    out = []
    for k, a in enumerate(sorted(depths_mm)):
        progress(f"shaft crack sweep {k + 1}/{len(depths_mm)}: a = {a:g} mm")
        out.append(run(params, mesh_size_mm=mesh_size_mm, order=order, crack_depth_mm=a, progress=progress,
                       quick=quick, _uncracked_cache=cache))
    return out


def energy_release_rates(params, sweep: Sequence[StudyResult]) -> list[EnergyReleaseRate]:
    """G between consecutive sweep depths (a = 0 with delta lambda = 0 included) vs K_III^2/(2 mu)."""
    from strainwave.analytic.cracks import shaft_K_III
    from strainwave.analytic.variant import Variant

    T = params.gear.output_torque_Nmm
    d_s = params.output_shaft.outer_diameter_mm
    mu = params.material.implied_shear_modulus_MPa      # the FEA's modulus, so only K_III differs
    pts = [(0.0, 0.0, 0.0)] + sorted(
        (r.meta["crack_depth_mm"], r["delta_flexibility_rad_per_Nmm"].value,
         r["delta_flexibility_rad_per_Nmm"].uncertainty or 0.0) for r in sweep)
    out = []
    for (a1, l1, e1), (a2, l2, e2) in zip(pts, pts[1:]):
        dA = crack_area_mm2(params, a2) - crack_area_mm2(params, a1)
        a_mid = 0.5 * (a1 + a2)
        g = 0.5 * T ** 2 * (l2 - l1) / dA
        dg = 0.5 * T ** 2 * math.hypot(e1, e2) / dA
        k_pub = shaft_K_III(T, d_s, a_mid, Variant.PUBLISHED)
        k_cor = shaft_K_III(T, d_s, a_mid, Variant.CORRECTED)
        out.append(EnergyReleaseRate(a_mid, g, dg, k_pub ** 2 / (2 * mu), k_cor ** 2 / (2 * mu)))
    return out


def fitted_exponent(sweep: Sequence[StudyResult]) -> float:
    """Slope of log delta lambda vs log a (the seed's published a^3 vs corrected a^2 scaling)."""
    import numpy as np
    a = np.array([r.meta["crack_depth_mm"] for r in sweep])
    d = np.array([r["delta_flexibility_rad_per_Nmm"].value for r in sweep])
    keep = d > 0
    return float(np.polyfit(np.log(a[keep]), np.log(d[keep]), 1)[0])
