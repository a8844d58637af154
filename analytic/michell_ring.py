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


# ---- the ring under ball patches on the race, its bore held radially (the cam), shear-free ----

def race_pressure_fourier(n: np.ndarray, r_o_mm: float, width_mm: float, ball_angles_rad, ball_loads_N,
                          half_widths_mm) -> np.ndarray:
    """p_n of the race pressure sum_i 2 Q_i/(pi h_i B) sqrt(1 - (s/h_i)^2) (Hertz line patches, s = r_o (theta -
    psi_i)) = p_0 + sum p_n cos n theta, for loads symmetric about theta = 0; 2 J1(k)/k is a patch's own factor."""
    from scipy.special import j1

    n = np.asarray(n, float)[:, None]
    psi, q, h = (np.asarray(v, float)[None, :] for v in (ball_angles_rad, ball_loads_N, half_widths_mm))
    k = n * h / r_o_mm
    shape = np.where(k > 0, 2.0 * j1(np.where(k > 0, k, 1.0)) / np.where(k > 0, k, 1.0), 1.0)
    p = np.sum(q * np.cos(n * psi) * shape, axis=1) / (np.pi * r_o_mm * width_mm)
    return np.where(n[:, 0] == 0, 0.5 * p, p)


def _harmonic_n(n: np.ndarray, p: np.ndarray, k: float, a: float, b: float):
    """Scaled Airy amplitudes (alpha, beta, gamma, delta) of harmonics n >= 2: bore u_r = sigma_rt = 0, race
    sigma_rr = -p_n, sigma_rt = 0. Each basis is bounded by 1 on [a, b] (module docstring's table, rescaled)."""
    rho = a / b
    m = len(n)
    M = np.zeros((m, 4, 4))
    # race (s_b = 1, s_a = rho): sigma_rr, sigma_rt
    M[:, 0] = np.stack([-np.ones(m), -(n - 2), -rho ** (n + 2), -(n + 2) * rho ** n], axis=1)
    M[:, 1] = np.stack([np.ones(m), n, -rho ** (n + 2), -n * rho ** n], axis=1)
    # bore (s_b = rho, s_a = 1): 2 mu u_r / a, sigma_rt
    M[:, 2] = np.stack([-rho ** (n - 2) / (n - 1), (k - n - 1) * rho ** n / (n + 1), np.ones(m) / (n + 1),
                        (k + n - 1) / (n - 1)], axis=1)
    M[:, 3] = np.stack([rho ** (n - 2), n * rho ** n, -np.ones(m), -n], axis=1)
    rhs = np.zeros((m, 4))
    rhs[:, 0] = -p
    return np.linalg.solve(M, rhs[..., None])[..., 0]


def _hoop_n(coef: np.ndarray, n: np.ndarray, r: np.ndarray, a: float, b: float) -> np.ndarray:
    """sum over n >= 2 of sigma_tt at radii r, theta = 0."""
    sb, sa = r[None, :] / b, a / r[None, :]
    nn = n[:, None]
    al, be, ga, de = (coef[:, i][:, None] for i in range(4))
    return np.sum(al * sb ** (nn - 2) + (nn + 2) * be * sb ** nn + ga * sa ** (nn + 2) + (nn - 2) * de * sa ** nn,
                  axis=0)


def _hoop_0_1(p0: float, p1: float, k: float, a: float, b: float, r: np.ndarray) -> np.ndarray:
    """The n = 0 (Lame) and n = 1 (Michell's r^3, r^-1 and the single-valued r ln r - (k+1)/(k-1) r theta sin
    theta pair, plus a rigid translation) harmonics' hoop stress at r, theta = 0."""
    A0 = -p0 / (1.0 + 0.5 * (k - 1.0) * a ** 2 / b ** 2)         # C0 = (k - 1) A0 a^2/2 from u_r(a) = 0
    hoop0 = A0 - 0.5 * (k - 1.0) * A0 * a ** 2 / r ** 2
    c = (k + 3.0) / (k - 1.0)
    x = lambda rr: np.array([2 * rr, -2 * rr ** -3, -c / rr, 0.0])          # noqa: E731 sigma_rr
    s = lambda rr: np.array([2 * rr, -2 * rr ** -3, 1 / rr, 0.0])           # noqa: E731 sigma_rt
    u = np.array([(k - 2) * a ** 2, a ** -2, -2 * k / (k - 1) * np.log(a), 1.0])   # 2 mu u_r(a), T scaled
    A, B, C, _ = np.linalg.solve(np.array([x(b), s(b), u, s(a)]), np.array([-p1, 0.0, 0.0, 0.0]))
    return hoop0 + 6 * A * r + 2 * B * r ** -3 + C / r


def held_bore_hoop_stress_MPa(nu: float, r_i_mm: float, r_o_mm: float, width_mm: float, ball_angles_rad,
                              ball_loads_N, half_widths_mm, r_mm, plane: Plane = Plane.STRESS,
                              harmonics: int = 20000) -> np.ndarray:
    """Hoop stress at radii ``r_mm`` on theta = 0 of the ring whose bore is held radially and free tangentially
    (the cam) under Hertz line patches on the race (``race_pressure_fourier``): Michell's series, n = 0 .. harmonics,
    each harmonic exact. Independent of E (a displacement-free load on a fixed support)."""
    k = kappa(nu, plane)
    a, b = r_i_mm, r_o_mm
    r = np.atleast_1d(np.asarray(r_mm, float))
    p = race_pressure_fourier(np.arange(harmonics + 1), b, width_mm, ball_angles_rad, ball_loads_N, half_widths_mm)
    out = _hoop_0_1(p[0], p[1], k, a, b, r)
    n = np.arange(2, harmonics + 1, dtype=float)
    for chunk in np.array_split(np.arange(n.size), max(1, n.size // 2000)):
        coef = _harmonic_n(n[chunk], p[2:][chunk], k, a, b)
        out = out + _hoop_n(coef, n[chunk], r, a, b)
    return out
