"""The flexspline cup's diaphragm as an annular plate: the wave generator's coning and the torque's shear.

The wave generator forces the band into w0 cos 2 phi; the wall between the diaphragm (held round in its plane)
and the band's mid-width, a lever L, deforms inextensionally (the cylinder's cos 2 phi mode without hoop or axial
strain): u_r = (z/L) w0 cos 2 phi, v = -(z/L) w0 sin 2 phi / 2, u_z = -r w0 cos 2 phi / (4 L) (from e_z = 0 and
gamma_z theta = 0). At the rigid corner the diaphragm's outer edge (r = b, the wall's mid-surface) takes the
wall's axial displacement and turns with the wall's generator: w(b) = -b w0/(4 L), w'(b) = -w0/L (each times
cos 2 phi); the hub holds its inner edge (r = a): w = w' = 0.

Kirchhoff's plate for the harmonic n = 2 (Clebsch's solution, Timoshenko & Woinowsky-Krieger, Theory of Plates
and Shells, 2nd ed., 1959, sec. 34, "circular plates: unsymmetrical bending"):
w = (A r^2 + B r^4 + C r^-2 + D) cos 2 phi, M_r = -D_p (w'' + nu (w'/r - 4 w/r^2)); the radial bending
stress 6 M_r/t^2 at the hub (r = a) and at the wall (r = b), the larger governs. It is fully reversed: the wave
passes every point twice per input revolution. The torque's shear tau = T/(2 pi r^2 t), largest at the hub,
is the steady mean. The plate has no fillet: the hub's and the wall's corner fillets are not in it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["DiaphragmStresses", "diaphragm_stresses", "diaphragm_geometry"]

WAVE = 2


@dataclass(frozen=True)
class DiaphragmStresses:
    hub_bending_MPa: float        # radial bending stress amplitude at r = a (surface)
    wall_bending_MPa: float       # at r = b
    hub_shear_MPa: float          # the torque's tau at r = a
    edge_rotation_rad: float      # w0 / L
    lever_mm: float
    a_mm: float
    b_mm: float
    t_mm: float

    @property
    def bending_MPa(self) -> float:
        return max(abs(self.hub_bending_MPa), abs(self.wall_bending_MPa))

    def to_dict(self) -> dict:
        return {**self.__dict__, "bending_MPa": self.bending_MPa}


def _basis(r: float) -> np.ndarray:
    """[w, w', w''] of the four n = 2 solutions r^2, r^4, r^-2, 1 at r."""
    return np.array([[r ** 2, r ** 4, r ** -2, 1.0],
                     [2 * r, 4 * r ** 3, -2 * r ** -3, 0.0],
                     [2.0, 12 * r ** 2, 6 * r ** -4, 0.0]])


def _surface_stress(coef: np.ndarray, r: float, t: float, E: float, nu: float) -> float:
    w, dw, ddw = _basis(r) @ coef
    D = E * t ** 3 / (12.0 * (1.0 - nu * nu))
    M = -D * (ddw + nu * (dw / r - WAVE ** 2 * w / r ** 2))
    return float(6.0 * M / t ** 2)


def diaphragm_stresses(a_mm: float, b_mm: float, t_mm: float, lever_mm: float, w0_mm: float, torque_Nmm: float,
                       E_MPa: float, nu: float) -> DiaphragmStresses:
    """The plate's cos 2 phi bending (module docstring) and the torque's shear at the hub."""
    beta = w0_mm / lever_mm
    ba, bb = _basis(a_mm), _basis(b_mm)
    M = np.vstack([ba[0], ba[1], bb[0], bb[1]])
    rhs = np.array([0.0, 0.0, -b_mm * w0_mm / (4.0 * lever_mm), -beta])
    coef = np.linalg.solve(M, rhs)
    return DiaphragmStresses(_surface_stress(coef, a_mm, t_mm, E_MPa, nu), _surface_stress(coef, b_mm, t_mm, E_MPa, nu),
                             torque_Nmm / (2.0 * math.pi * a_mm ** 2 * t_mm), beta, lever_mm, a_mm, b_mm, t_mm)


def diaphragm_geometry(params) -> tuple[float, float, float, float]:
    """(a, b, t, L): hub radius, the wall's mid radius, the diaphragm's thickness (the wall's), the lever from the
    diaphragm's mid-plane to the band's mid-width (geometry/flexspline_cup.py)."""
    from strainwave.geometry.flexspline_cup import BAND_RATIO, BOSS_HEIGHT_WALLS, HUB_RATIO
    fc = params.flexspline_cup
    d1, t = fc.pitch_diameter_mm, fc.wall_thickness_mm
    lever = fc.length_mm - 0.5 * BAND_RATIO * d1 - (BOSS_HEIGHT_WALLS - 0.5) * t
    return HUB_RATIO * d1, 0.5 * (d1 - t), t, lever
