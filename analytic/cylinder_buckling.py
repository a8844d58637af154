"""Torsional buckling of a thin circular cylinder of moderate length (the flexspline's buckling torque).

Donnell's shallow-shell equation in Batdorf's modified form (Batdorf, NACA Report 874, 1947),

    D del^4 w + (E t / R^2) del^-4 w_xxxx + 2 tau t w_xy = 0,

with both ends simply supported (w = w_xx = 0), solved by Galerkin's method on Batdorf's own functions
w = sum_m sin(m pi x/L) (a_m sin(n y/R) + b_m cos(n y/R)) (the helical mode is the sin/cos coupling), for
the integer number n of circumferential waves that gives the least load. In k_s = tau t L^2 / (pi^2 D) and
Z = L^2 sqrt(1 - nu^2) / (R t) the equations are independent of the material:

    d_p a_p = s sum_m C_pm b_m,   d_p b_p = -s sum_m C_pm a_m,   s = 4 pi^4 beta k_s,
    d_m = pi^4 (m^2 + beta^2)^2 + 12 Z^2 m^4 / (m^2 + beta^2)^2,  C_pm = 2 p m / (pi (p^2 - m^2)) (m + p odd),

beta = n L / (pi R). Its large-Z asymptote is the published closed form, k_s = 0.85 Z^(3/4) (Batdorf; NASA
SP-8007, 1968, "moderate-length cylinders"), i.e. tau_cr = 0.747 E (t/R)^(5/4) (R/L)^(1/2) at nu = 0.3
(Timoshenko & Gere, Theory of Elastic Stability, 2nd ed., 1961, sec. 11.12, Donnell's formula). Its small-Z
limit is the long flat strip's k_s = 5.35 (Southwell and Skan). Both are this module's tests.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["CylinderBuckling", "batdorf_k", "asymptote_k", "torsional_buckling", "cup_tube", "TERMS"]

TERMS = 24                 # axial half-waves in the Galerkin sum (k_s converged to < 1e-4 at Z <= 1e4)
ASYMPTOTE = 0.85           # k_s = 0.85 Z^(3/4), simply supported (Batdorf; SP-8007)


def _coupling(terms: int) -> np.ndarray:
    p = np.arange(1, terms + 1)[:, None]
    m = np.arange(1, terms + 1)[None, :]
    odd = (p + m) % 2 == 1
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(odd, 2.0 * p * m / (math.pi * (p * p - m * m)), 0.0)


def batdorf_k(Z: float, beta: float, terms: int = TERMS) -> float:
    """k_s of the mode with circumferential parameter beta = n L/(pi R): the least s with
    D a = s^2 C^T D^-1 C a (eliminating b), s = 4 pi^4 beta k_s."""
    from scipy.linalg import eigh
    m = np.arange(1, terms + 1, dtype=float)
    q = m * m + beta * beta
    d = math.pi ** 4 * q * q + 12.0 * Z * Z * m ** 4 / (q * q)
    C = _coupling(terms)
    M = C.T @ (C / d[:, None])
    mu = eigh(M, np.diag(d), eigvals_only=True)     # mu = 1/s^2: the largest gives the least load
    return math.sqrt(1.0 / mu[-1]) / (4.0 * math.pi ** 4 * beta)


def asymptote_k(Z: float) -> float:
    return ASYMPTOTE * Z ** 0.75


@dataclass(frozen=True)
class CylinderBuckling:
    """The torsional buckling of a tube (mid radius R, wall t, length L) with simply supported ends."""
    Z: float
    n_waves: int               # circumferential waves of the least mode
    k_s: float                 # Batdorf's Galerkin solution at that n
    k_s_asymptote: float       # 0.85 Z^(3/4)
    tau_cr_MPa: float
    tau_cr_asymptote_MPa: float
    torque_Nmm: float          # tau_cr 2 pi R^2 t
    torque_asymptote_Nmm: float

    def to_dict(self) -> dict:
        return dict(self.__dict__)


def torsional_buckling(R_mm: float, t_mm: float, L_mm: float, E_MPa: float, nu: float) -> CylinderBuckling:
    """The least k_s over the integer wave numbers n >= 2 (n = 1 is a beam's sway, not a shell mode)."""
    Z = L_mm * L_mm * math.sqrt(1.0 - nu * nu) / (R_mm * t_mm)
    best = None
    for n in range(2, 200):
        k = batdorf_k(Z, n * L_mm / (math.pi * R_mm))
        if best is not None and k > best[1]:
            break                       # k(n) is unimodal: past the least
        best = (n, k)
    n, k = best
    scale = math.pi ** 2 * E_MPa * t_mm * t_mm / (12.0 * (1.0 - nu * nu) * L_mm * L_mm)
    ka = asymptote_k(Z)
    arm = 2.0 * math.pi * R_mm * R_mm * t_mm
    return CylinderBuckling(Z, n, k, ka, k * scale, ka * scale, k * scale * arm, ka * scale * arm)


def cup_tube(params) -> tuple[float, float, float]:
    """(R, t, L) of the flexspline cup's wall as the buckling tube: mid radius of bore to root circle, wall, and the
    length from the diaphragm's mid-plane to the rim (the FE's tube, fea/wg_band.tube_geometry)."""
    from strainwave.geometry.flexspline_cup import BOSS_HEIGHT_WALLS
    fc = params.flexspline_cup
    t = fc.wall_thickness_mm
    return 0.5 * (fc.pitch_diameter_mm - t), t, fc.length_mm - (BOSS_HEIGHT_WALLS - 0.5) * t
