"""The flexspline's tooth-root crack as a part-through semi-elliptical surface crack.

Stress intensity: Newman and Raju's empirical equations for a semi-elliptical surface crack (depth a,
half-length c) in a plate of thickness t and width 2b under remote tension sigma_t and outer-fibre bending
sigma_b (J. C. Newman Jr., I. S. Raju, "An empirical stress-intensity factor equation for the surface
crack", Eng. Fract. Mech. 15 (1981) 185-192; "Stress-intensity factor equations for cracks in
three-dimensional finite bodies", NASA TM-83200, 1981; and the 1984 form with bending, NASA TM-85793,
"Stress-intensity factor equations for cracks in three-dimensional finite bodies subjected to tension and
bending loads"):

    K = (sigma_t + H sigma_b) sqrt(pi a / Q) F,   F = [M1 + M2 (a/t)^2 + M3 (a/t)^4] g f_phi f_w

phi is the ellipse's parametric angle (0 at the free surface, pi/2 at the deepest point), Q = 1 + 1.464
(a/c)^1.65 (c/a for a/c > 1), f_w = sec(pi c/(2b) sqrt(a/t))^1/2; M1, M2, M3, g, f_phi, H below. Valid, as the
authors state: 0 < a/c <= 2, a/t <= 0.8 here (their equations to 1, fitted within +-5 % of their FE), c/b < 0.5.

Crack-face contact rule: where the combined K (wave generator + torque) is negative the faces touch: K = 0
there and that part of the front adds no compliance.

Compliance, as seed 000 eq 4 does for its crack: d lambda = 2/E' int (K/P)^2 dA. The surface crack grows
self-similarly (a/c fixed); a front point at parametric angle phi then advances so that the swept area is
dA = c dphi da (x = c cos phi, y = a sin phi: (x . n) ds = a c dphi), over 0 <= phi <= pi. So

    delta_lambda_f(a) = 2/E' int_0^a c(a') int_0^pi (K(phi, a')/T)^2 [K_total(phi, a') > 0] dphi da'

exact for the self-similar path (linear elasticity: the released energy does not depend on the path).
E' = E/(1 - nu^2): the front of a part-through crack is in plane strain except within a surface layer.

How the loads reach the crack face (the tooth root: the band's outer fibre, smooth band, as study
cup-wave-generator). The crack is the seed's: its plane contains the radial direction and makes beta =
``cracks.flexspline_crack_angle_deg`` (45 deg) with the band's axis. The band carries, through the wall,
- the wave generator's hoop stress sigma_theta = sigma_m + sigma_b (1 - 2y/t) (y from the outer fibre),
  sigma_b = E/(1 - nu^2) (t/2) 3 w0 cos(2 phi_wg)/r_m^2 (analytic/ring_prescribed.py; membrane sigma_m = 0
  for the inextensional shape, or the FEA record's (outer + inner)/2 when given), and the axial stress
  sigma_z = nu sigma_theta of the band of a long shell (kappa_z = 0);
- the torque's shear tau = T/(2 pi r_m^2 t) (seed 000), uniform through the thin wall.
Normal to the crack face (rotation of the plane stress by beta):
    sigma_n = sigma_theta cos^2 beta + sigma_z sin^2 beta + tau sin 2 beta
so the wave generator gives membrane (cos^2 beta + nu sin^2 beta) sigma_m and bending (cos^2 beta + nu sin^2
beta) sigma_b, and the torque a membrane sin(2 beta)/(2 pi r_m^2 t) per N*mm. The in-plane shear of the
rotated state ((sigma_z - sigma_theta) sin 2beta / 2, independent of T) slides the faces: it neither opens
them nor enters d^2 U/dT^2 (a planar crack in one homogeneous material: normal and shear uncouple).
The seed's through-wall crack (K = tau sqrt(pi a), dA = t da: analytic/cracks.py) stays beside it as the
published idealisation.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from strainwave.analytic import cracks, ring_prescribed

__all__ = ["MAX_DEPTH_OVER_T", "MAX_ASPECT", "shape_factor_Q", "newman_raju_F", "newman_raju_H", "stress_intensity",
           "CrackFaceLoads", "tooth_root_loads", "delta_flexibility", "through_wall_flexibility", "ripple_percent",
           "STATES_DEG", "study_loads"]

MAX_DEPTH_OVER_T = 0.8     # Newman-Raju: a/t <= 0.8 (their accuracy statement)
MAX_ASPECT = 2.0           # a/c <= 2
# where the crack is solved: wave-generator angle from the major axis (deg); "closing" lies in the transition
# from open to shut on the default gear (reported, not checked: the contact rule is approximate there)
STATES_DEG = (("major", 0.0), ("between", 45.0), ("closing", 52.0), ("minor", 90.0))


def _check(a_over_c, a_over_t):
    if not (0.0 < a_over_c <= MAX_ASPECT):
        raise ValueError(f"a/c must lie in (0, {MAX_ASPECT:g}], got {a_over_c!r}")
    if not (0.0 <= a_over_t <= MAX_DEPTH_OVER_T):
        raise ValueError(f"a/t must lie in [0, {MAX_DEPTH_OVER_T:g}], got {a_over_t!r}")


def shape_factor_Q(a_over_c: float) -> float:
    """Q = 1 + 1.464 (a/c)^1.65 (a/c <= 1), 1 + 1.464 (c/a)^1.65 (a/c > 1): the square of the elliptic
    integral of the second kind, fitted (Newman-Raju)."""
    r = a_over_c if a_over_c <= 1.0 else 1.0 / a_over_c
    return 1.0 + 1.464 * r ** 1.65


def newman_raju_F(a_over_c: float, a_over_t: float, phi, c_over_b: float = 0.0):
    """Boundary-correction factor F(phi) under tension: [M1 + M2 (a/t)^2 + M3 (a/t)^4] g f_phi f_w."""
    _check(a_over_c, a_over_t)
    phi = np.asarray(phi, dtype=float)
    s, c = np.sin(phi), np.cos(phi)
    if a_over_c <= 1.0:
        r = a_over_c
        M1, M2 = 1.13 - 0.09 * r, -0.54 + 0.89 / (0.2 + r)
        M3 = 0.5 - 1.0 / (0.65 + r) + 14.0 * (1.0 - r) ** 24
        g = 1.0 + (0.1 + 0.35 * a_over_t ** 2) * (1.0 - s) ** 2
        f_phi = (r * r * c * c + s * s) ** 0.25
    else:
        q = 1.0 / a_over_c
        M1, M2, M3 = math.sqrt(q) * (1.0 + 0.04 * q), 0.2 * q ** 4, -0.11 * q ** 4
        g = 1.0 + (0.1 + 0.35 * q * a_over_t ** 2) * (1.0 - s) ** 2
        f_phi = (q * q * s * s + c * c) ** 0.25
    f_w = 1.0 / math.sqrt(math.cos(0.5 * math.pi * c_over_b * math.sqrt(a_over_t))) if c_over_b > 0 else 1.0
    return (M1 + M2 * a_over_t ** 2 + M3 * a_over_t ** 4) * g * f_phi * f_w


def newman_raju_H(a_over_c: float, a_over_t: float, phi):
    """Bending multiplier H(phi) = H1 + (H2 - H1) sin^p phi (Newman-Raju 1984)."""
    _check(a_over_c, a_over_t)
    r, x = a_over_c, a_over_t
    p = 0.2 + r + 0.6 * x
    if r <= 1.0:
        H1 = 1.0 - 0.34 * x - 0.11 * r * x
        G21, G22 = -1.22 - 0.12 * r, 0.55 - 1.05 * r ** 0.75 + 0.47 * r ** 1.5
    else:
        q = 1.0 / r
        H1 = 1.0 - (0.04 + 0.41 * q) * x + (0.55 - 1.93 * q ** 0.75 + 1.38 * q ** 1.5) * x * x
        G21, G22 = -2.11 + 0.77 * q, 0.55 - 0.72 * q ** 0.75 + 0.14 * q ** 1.5
    H2 = 1.0 + G21 * x + G22 * x * x
    return H1 + (H2 - H1) * np.sin(np.asarray(phi, dtype=float)) ** p


def stress_intensity(a_mm: float, c_mm: float, t_mm: float, phi, tension_MPa: float, bending_MPa: float,
                     half_width_mm: float = math.inf, *, contact: bool = True):
    """K_I (MPa sqrt(mm)) along the front; with ``contact`` a negative K is a shut crack: K = 0."""
    r, x = a_mm / c_mm, a_mm / t_mm
    cb = 0.0 if math.isinf(half_width_mm) else c_mm / half_width_mm
    F = newman_raju_F(r, x, phi, cb)
    K = (tension_MPa + newman_raju_H(r, x, phi) * bending_MPa) * math.sqrt(math.pi * a_mm / shape_factor_Q(r)) * F
    return np.maximum(K, 0.0) if contact else K


@dataclass(frozen=True)
class CrackFaceLoads:
    """Stresses normal to the crack face at a tooth root: the wave generator's membrane and outer-fibre bending
    (fixed) and the torque's membrane per unit torque; ``torque_Nmm`` is the torque the state is taken at."""

    membrane_MPa: float
    bending_MPa: float
    per_torque_MPa_per_Nmm: float
    torque_Nmm: float

    def at_torque(self) -> tuple[float, float]:
        """(membrane, bending) of the combined state (wave generator + torque)."""
        return self.membrane_MPa + self.torque_Nmm * self.per_torque_MPa_per_Nmm, self.bending_MPa


def _wall(params) -> tuple[float, float]:
    fc = params.flexspline_cup
    return fc.wall_thickness_mm, 0.5 * (fc.pitch_diameter_mm - fc.wall_thickness_mm)


def tooth_root_loads(params, phi_wg_rad: float, *, hoop_membrane_MPa: float = 0.0,
                     hoop_bending_MPa: float | None = None) -> CrackFaceLoads:
    """The crack-face stresses at a tooth root at wave-generator angle phi (0: major axis), by the map of the
    module docstring. ``hoop_bending_MPa``: the band's outer-fibre hoop bending (default: the ring forced into
    w0 cos 2 phi, E/(1 - nu^2)); ``hoop_membrane_MPa``: its membrane (default 0, the inextensional shape)."""
    t, r_m = _wall(params)
    m, g = params.material, params.gear
    if hoop_bending_MPa is None:
        hoop_bending_MPa = float(ring_prescribed.hoop_bending_stress_MPa(
            phi_wg_rad, g.radial_deformation_mm, t, r_m, m.youngs_modulus_MPa, m.poisson_ratio,
            wave_number=g.wave_number))
    beta = math.radians(params.cracks.flexspline_crack_angle_deg)
    normal = math.cos(beta) ** 2 + m.poisson_ratio * math.sin(beta) ** 2
    per_T = math.sin(2.0 * beta) / (2.0 * math.pi * r_m ** 2 * t)
    return CrackFaceLoads(normal * hoop_membrane_MPa, normal * hoop_bending_MPa, per_T, g.rated_output_torque_Nmm)


def delta_flexibility(a_mm: float, a_over_c: float, t_mm: float, loads: CrackFaceLoads, E_prime_MPa: float, *,
                      half_width_mm: float = math.inf, n_depth: int = 64, n_phi: int = 96) -> float:
    """delta lambda_f (rad/(N*mm)) of the surface crack: the integral of the module docstring, Gauss-Legendre in a'
    and phi (symmetric about pi/2, so twice 0..pi/2), the shut parts (combined K < 0) left out."""
    if not (a_mm > 0.0 and E_prime_MPa > 0.0):
        raise ValueError(f"a and E' must be > 0, got {a_mm!r}, {E_prime_MPa!r}")
    _check(a_over_c, a_mm / t_mm)
    xa, wa = np.polynomial.legendre.leggauss(n_depth)
    xp, wp = np.polynomial.legendre.leggauss(n_phi)
    depths, w_depth = 0.5 * a_mm * (xa + 1.0), 0.5 * a_mm * wa
    phis, w_phi = 0.25 * math.pi * (xp + 1.0), 0.25 * math.pi * wp
    sigma_m, sigma_b = loads.at_torque()
    total = 0.0
    for d, wd in zip(depths, w_depth):
        c = d / a_over_c
        k_T = stress_intensity(d, c, t_mm, phis, loads.per_torque_MPa_per_Nmm, 0.0, half_width_mm, contact=False)
        k_tot = stress_intensity(d, c, t_mm, phis, sigma_m, sigma_b, half_width_mm, contact=False)
        total += wd * c * 2.0 * float(np.sum(w_phi * k_T ** 2 * (k_tot > 0.0)))
    return 2.0 / E_prime_MPa * total


def through_wall_flexibility(params, a_mm: float) -> float:
    """The seed's through-wall idealisation beside it: K = tau sqrt(pi a), one tip, dA = t da, E' = E
    (seed 000 eq 4 corrected, K_u = K_d = 1: analytic/cracks.py)."""
    t, r_m = _wall(params)
    return cracks.flexspline_crack_flexibility(r_m, t, 1.0, 1.0, a_mm, params.material.youngs_modulus_MPa)


def ripple_percent(delta_open: float, delta_shut: float, lambda_total: float) -> float:
    """Peak-to-peak torsional-stiffness ripple in % of K_HD = 1/lambda_total as the crack passes from the
    open to the shut axis (twice per input revolution: the ripple's fundamental is at twice the input)."""
    return 100.0 * lambda_total * (1.0 / (lambda_total + delta_shut) - 1.0 / (lambda_total + delta_open))


def study_loads(params) -> dict:
    """The keywords of study cup-surface-crack's run: the torque's crack-face stress per N*mm and, per state,
    the crack face's membrane (wave generator + rated torque) and bending, MPa (fea/ receives numbers)."""
    states = []
    for name, deg in STATES_DEG:
        loads = tooth_root_loads(params, math.radians(deg))
        states.append((name, *loads.at_torque()))
    return {"per_torque_MPa_per_Nmm": tooth_root_loads(params, 0.0).per_torque_MPa_per_Nmm,
            "states": tuple(states)}
