"""The exact plane-elasticity solution of a ring whose bore is pushed to w0 cos 2phi (Michell, n = 2).

The wave generator's cam forces the bearing's inner ring (bore r_i, race r_o) radially to u_r(r_i) = w0 cos 2phi
with no shear (frictionless cam); the race is free. Michell's Airy function for the n = 2 harmonic,

    phi = (A r^2 + B r^4 + C r^-2 + D) cos 2theta,

gives (Barber, Elasticity, 3rd ed., table 8.1)

    sigma_rr = -(2A + 6C r^-4 + 4D r^-2) cos 2theta
    sigma_tt =  (2A + 12B r^2 + 6C r^-4) cos 2theta
    sigma_rt =  (2A + 6B r^2 - 6C r^-4 - 2D r^-2) sin 2theta
    2 mu u_r = (-2A r + (kappa - 3) B r^3 + 2C r^-3 + (kappa + 1) D r^-1) cos 2theta

with kappa = 3 - 4 nu (plane strain) or (3 - nu)/(1 + nu) (plane stress). The four constants follow from
u_r(r_i) = w0, sigma_rt(r_i) = 0, sigma_rr(r_o) = sigma_rt(r_o) = 0: no series, no thin-ring or curved-beam
assumption. A ring of finite width lies between the two: plane stress (free faces, a narrow ring) and plane
strain (faces held, a wide one).
"""
from __future__ import annotations

from enum import Enum

import numpy as np

__all__ = ["Plane", "kappa", "cam_ring_constants", "cam_ring_hoop_stress_MPa", "cam_ring_stresses_MPa",
           "cam_ring_displacement_mm"]


class Plane(str, Enum):
    STRESS = "plane stress"
    STRAIN = "plane strain"


def kappa(nu: float, plane: Plane) -> float:
    """Kolosov's constant: 3 - 4 nu (plane strain), (3 - nu)/(1 + nu) (plane stress)."""
    return 3.0 - 4.0 * nu if Plane(plane) is Plane.STRAIN else (3.0 - nu) / (1.0 + nu)


def cam_ring_constants(E_MPa: float, nu: float, r_i_mm: float, r_o_mm: float, w0_mm: float,
                       plane: Plane = Plane.STRESS) -> np.ndarray:
    """(A, B, C, D) of the Airy function (module docstring) for the bore at w0 cos 2phi and the race free."""
    if not 0.0 < r_i_mm < r_o_mm:
        raise ValueError(f"ring radii must satisfy 0 < r_i < r_o, got {r_i_mm}, {r_o_mm}")
    k, mu = kappa(nu, plane), E_MPa / (2.0 * (1.0 + nu))
    a, b = r_i_mm, r_o_mm
    rows = np.array([
        [-2.0 * a, (k - 3.0) * a ** 3, 2.0 * a ** -3, (k + 1.0) / a],    # 2 mu u_r(r_i) = 2 mu w0
        [2.0, 6.0 * a ** 2, -6.0 * a ** -4, -2.0 * a ** -2],              # sigma_rt(r_i) = 0
        [-2.0, 0.0, -6.0 * b ** -4, -4.0 * b ** -2],                      # sigma_rr(r_o) = 0
        [2.0, 6.0 * b ** 2, -6.0 * b ** -4, -2.0 * b ** -2],              # sigma_rt(r_o) = 0
    ])
    rhs = np.array([2.0 * mu * w0_mm, 0.0, 0.0, 0.0])
    return np.linalg.solve(rows, rhs)


def cam_ring_stresses_MPa(E_MPa: float, nu: float, r_i_mm: float, r_o_mm: float, w0_mm: float, r_mm, phi_rad,
                          plane: Plane = Plane.STRESS) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(sigma_rr, sigma_tt, sigma_rt) at (r, phi), phi from the major axis (where the bore is pushed out)."""
    A, B, C, D = cam_ring_constants(E_MPa, nu, r_i_mm, r_o_mm, w0_mm, plane)
    r, c, s = np.asarray(r_mm, float), np.cos(2.0 * np.asarray(phi_rad, float)), np.sin(2.0 * np.asarray(phi_rad, float))
    srr = -(2.0 * A + 6.0 * C * r ** -4 + 4.0 * D * r ** -2) * c
    stt = (2.0 * A + 12.0 * B * r ** 2 + 6.0 * C * r ** -4) * c
    srt = (2.0 * A + 6.0 * B * r ** 2 - 6.0 * C * r ** -4 - 2.0 * D * r ** -2) * s
    return srr, stt, srt


def cam_ring_hoop_stress_MPa(E_MPa: float, nu: float, r_i_mm: float, r_o_mm: float, w0_mm: float,
                             phi_rad: float = 0.0, r_mm: float | None = None, plane: Plane = Plane.STRESS) -> float:
    """The hoop stress at radius ``r_mm`` (default the race r_o) and angle ``phi_rad`` from the major axis."""
    r = r_o_mm if r_mm is None else r_mm
    return float(cam_ring_stresses_MPa(E_MPa, nu, r_i_mm, r_o_mm, w0_mm, r, phi_rad, plane)[1])


def cam_ring_displacement_mm(E_MPa: float, nu: float, r_i_mm: float, r_o_mm: float, w0_mm: float, r_mm, phi_rad,
                              plane: Plane = Plane.STRESS) -> tuple[np.ndarray, np.ndarray]:
    """(u_r, u_theta) at (r, phi): 2 mu u_theta = (2A r + (kappa + 3) B r^3 + 2C r^-3 + (1 - kappa) D r^-1) sin 2theta."""
    A, B, C, D = cam_ring_constants(E_MPa, nu, r_i_mm, r_o_mm, w0_mm, plane)
    k, two_mu = kappa(nu, plane), E_MPa / (1.0 + nu)
    r, c, s = np.asarray(r_mm, float), np.cos(2.0 * np.asarray(phi_rad, float)), np.sin(2.0 * np.asarray(phi_rad, float))
    u_r = (-2.0 * A * r + (k - 3.0) * B * r ** 3 + 2.0 * C * r ** -3 + (k + 1.0) * D / r) * c / two_mu
    u_t = (2.0 * A * r + (k + 3.0) * B * r ** 3 + 2.0 * C * r ** -3 + (1.0 - k) * D / r) * s / two_mu
    return u_r, u_t
