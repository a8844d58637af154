"""The cup's wall twisted by the teeth in mesh: torque entering at the two mesh zones, not as a uniform shear.

The chain's cup compliance takes the torque into the tube as a uniform shear flow. In the drive it enters at
the teeth in contact near the two major axes, at the open end, on a wall held radially by the wave generator
(the cam's active set of ``wg_band``) and free tangentially (the bearing rolls). This module applies the same
torque as a tangential shear on the band's outer surface distributed as the tooth loads are (weight w(phi),
period pi: two lobes) and reads the work-conjugate flexibility lambda = W / T^2, W = int w v dA over the whole
wall (the twist the teeth see, load-weighted), T = int w r dA. Uniform w gives the existing shear case.

The quarter model (``wg_band``) holds a load symmetric about phi = 0 under the antisymmetric conditions (u_r = u_z
= 0 on the planes); a zone that is not symmetric about the major axis is split w = w_s + w_a, w_a odd about
phi = 0 (and, by the period pi, about phi = pi/2), which the symmetric conditions (u_theta = 0 on the planes)
hold. The two parts do no work on each other, so W = 4 (w_s . u_s + w_a . u_a) on the quarter, T = 4 int w_s r.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from strainwave.fea import wg_band as wb
from strainwave.fea.assembly import Lame

__all__ = ["ZoneLoad", "tube_of_design", "weighted_band_loads", "tooth_zone", "uniform_zone", "zone_flexibilities"]


@dataclass(frozen=True)
class ZoneLoad:
    """A tangential load distribution over the circumference, period pi (two lobes): weight(phi) >= 0."""

    name: str
    weight: Callable[[np.ndarray], np.ndarray]


def uniform_zone() -> ZoneLoad:
    return ZoneLoad("uniform", lambda phi: np.ones_like(phi))


def tooth_zone(angles_rad: np.ndarray, tangential_N: np.ndarray, pitch_rad: float) -> ZoneLoad:
    """The teeth's tangential loads (every tooth round the whole circle) as a shear per radian: each tooth's load
    spread by a hat one pitch either side (area 1), so the shear is the linear interpolation of load per pitch
    between teeth; folded to period pi, the two lobes averaged (one lobe's total is half of the teeth's)."""
    a = np.mod(np.asarray(angles_rad, float) + 0.5 * math.pi, math.pi) - 0.5 * math.pi     # into [-pi/2, pi/2)
    F = np.asarray(tangential_N, float)

    def weight(phi: np.ndarray) -> np.ndarray:
        x = np.mod(np.asarray(phi, float) + 0.5 * math.pi, math.pi) - 0.5 * math.pi
        d = np.abs(x[..., None] - a)
        d = np.minimum(d, math.pi - d)
        return 0.5 * np.sum(F * np.clip(1.0 - d / pitch_rad, 0.0, None), axis=-1) / pitch_rad
    return ZoneLoad("teeth", weight)


def tube_of_design(design) -> wb.TubeGeometry:
    """The quarter wall of a ``MeshDesign``: bore to tooth root (root 1.25 m under the pitch circle), the held end
    at the diaphragm's mid-plane as the cup study places it, the load band the face width at the open end."""
    from strainwave.geometry.flexspline_cup import BOSS_HEIGHT_WALLS
    g = design.geometry
    r_o = g.pitch_radius_mm - 1.25 * g.module_mm
    t = g.rim_thickness_mm
    return wb.TubeGeometry(r_o - t, r_o, (BOSS_HEIGHT_WALLS - 0.5) * t, g.cup_length_mm, g.face_width_mm)


def weighted_band_loads(tube: wb.Tube, weight: Callable[[np.ndarray], np.ndarray]) -> tuple[np.ndarray, float]:
    """(load vector of the tangential shear weight(phi) on the band's outer surface of the quarter, its moment
    int weight r dA over the quarter), by the facet rule of ``band_outer_loads``."""
    cb, x, r, dA = wb.band_outer_quadrature(tube, 8)
    q = weight(np.arctan2(x[1], x[0])) * dA
    e_theta = np.stack([-x[1], x[0]]) / r
    N = np.stack([cb.basis[a][0].value for a in range(len(cb.basis))]) * q
    dofs = cb.element_dofs.ravel()
    load = np.zeros(tube.dofs)
    for k in (0, 1):
        load += np.bincount(3 * dofs + k, np.sum(N * e_theta[k], axis=2).ravel(), minlength=tube.dofs)
    return load, float(np.sum(r * q))


def zone_flexibilities(design, n_theta: int, zones: dict[str, ZoneLoad], *, contact: bool = True,
                       poisson: float = 0.3) -> dict[str, float]:
    """name -> the wall's flexibility (rad/(N mm)) under each zone's load, on one mesh of ``n_theta`` elements
    around the quarter; the wall on the wave generator's cam (linear insertion's active set; ``contact`` False:
    every band bore point held radially, the prescribed-shape limit)."""
    tube = wb.tube_mesh(tube_of_design(design), n_theta)
    lame = Lame.from_young(design.E_MPa, poisson)
    K0 = wb.assemble(tube, np.zeros(tube.dofs), lame, False)[0]
    systems = {sym: wb.bore_system(tube, K0, symmetric=sym) for sym in (True, False)}
    try:
        active = wb.insert(tube, lame, design.geometry.w0_mm, contact=contact, nonlinear=False, K0=K0,
                           system=systems[True]).active
        out = {}
        for name, zone in zones.items():
            # the part symmetric about phi = 0 under the antisymmetric conditions, the odd part under the symmetric
            parts = {False: lambda p, z=zone: 0.5 * (z.weight(p) + z.weight(-p)),
                     True: lambda p, z=zone: 0.5 * (z.weight(p) - z.weight(-p))}
            work, torque_q = 0.0, 0.0
            for sym, wfun in parts.items():
                load, moment = weighted_band_loads(tube, wfun)
                if not np.any(load):
                    continue
                u = wb.held_solve(tube, systems[sym], load, active, 0.0)
                work += float(load @ u)
                torque_q += moment if not sym else 0.0
            out[name] = work / (4.0 * torque_q ** 2)
        out["bore_points_held"] = float(active.sum()) / active.size
        return out
    finally:
        for s in systems.values():
            s.close()
