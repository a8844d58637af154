"""Crack-induced compliances of seed 000 and the general integral they come from (eq 4).

    dlambda = int_0^A [ 2/E' ((K_I/P)^2 + (K_II/P)^2) + (K_III/P)^2 / mu ] dA      (seed 000, eq 4)
    du      = P * dlambda for K proportional to P                                  (seed 000, eq 3, expanded)

``crack_compliance_integral`` evaluates eq 4 by quadrature for any K/P function and
area element; each closed form below is tested against it (tests/test_analytic_cracks.py).
E' = E (plane stress) as in the seed. Units: mm, N, MPa; torsional compliances in
rad/(N*mm), radial ones in mm/N.
"""
from __future__ import annotations

import math
from typing import Callable

from scipy import integrate

from strainwave.analytic.crack_series import hertz_mode_i_constant, m_m, m_p
from strainwave.analytic.variant import Variant

KPerLoad = Callable[[float], tuple[float, float, float]]   # a -> (K_I/P, K_II/P, K_III/P)
AreaElement = Callable[[float], float]                      # a -> dA/da


def crack_compliance_integral(k_per_load_fn: KPerLoad, area_element_fn: AreaElement, a_mm: float,
                              E_MPa: float, mu_MPa: float, a0_mm: float = 0.0) -> float:
    """Additional compliance by seed 000, eq 4, integrated numerically (scipy.integrate.quad).

    Parameters
    ----------
    k_per_load_fn : a -> (K_I/P, K_II/P, K_III/P) in mm^-1/2 per unit load P.
    area_element_fn : a -> dA/da in mm (crack-front length).
    a_mm : final crack depth; integration from ``a0_mm``.
    E_MPa, mu_MPa : E' for modes I, II and mu for mode III, as the seed writes them.
    """
    def integrand(a: float) -> float:
        kI, kII, kIII = k_per_load_fn(a)
        return (2.0 / E_MPa * (kI * kI + kII * kII) + kIII * kIII / mu_MPa) * area_element_fn(a)

    value, _ = integrate.quad(integrand, a0_mm, a_mm, epsabs=0.0, epsrel=1e-11, limit=200)
    return value


def crack_displacement_integral(k_per_load_fn: KPerLoad, area_element_fn: AreaElement, a_mm: float,
                                load: float, E_MPa: float, mu_MPa: float) -> float:
    """du = int 2/E' K_I (K_I/P) + ... dA = P * dlambda (seed 000, eq 3 expanded; the G/P form is half)."""
    return load * crack_compliance_integral(k_per_load_fn, area_element_fn, a_mm, E_MPa, mu_MPa)


# ---- wave generator bearing ring: semi-elliptical surface crack, mode I ----

def bearing_k_per_load(beta: float, semi_axes_mm: tuple[float, float], Q: float) -> KPerLoad:
    """K_I/F_r = 1.95 (beta/2)(3/(2 pi a' b')) sqrt(a/Q) (seed 000, bearing ring K_I)."""
    a1, b1 = semi_axes_mm
    coef = 1.95 * 0.5 * beta * 3.0 / (2.0 * math.pi * a1 * b1)
    return lambda a: (coef * math.sqrt(a / Q), 0.0, 0.0)


def bearing_displacement_mm(radial_force_N: float, ring_thickness_mm: float, beta: float,
                            semi_axes_mm: tuple[float, float], a_mm: float, E_MPa: float, Q: float,
                            variant: Variant = Variant.CORRECTED) -> float:
    """du_H = 0.217 t_i (beta a/(a' b'))^2 F_r^n / (E Q) (seed 000, du_H).

    PUBLISHED: n = 2 and the printed 0.217 (a typo: du_H would not be linear in F_r).
    CORRECTED: n = 1 and 0.216717 = (3*1.95/(4 pi))^2, = F_r * (eq 4 integral with dA = t_i da).
    """
    a1, b1 = semi_axes_mm
    g = ring_thickness_mm * (beta * a_mm / (a1 * b1)) ** 2 / (E_MPa * Q)
    if variant is Variant.PUBLISHED:
        return 0.217 * g * radial_force_N ** 2
    return hertz_mode_i_constant() * g * radial_force_N


def bearing_crack_stiffness(radial_force_N: float, ring_thickness_mm: float, beta: float,
                            semi_axes_mm: tuple[float, float], a_mm: float, E_MPa: float, Q: float,
                            variant: Variant = Variant.CORRECTED) -> float:
    """dK_G = F_r / du_H (seed 000).

    PUBLISHED: E Q / (0.217 F_r t_i (beta a/(a'b'))^2), units 1/mm, load-dependent.
    CORRECTED: E Q / (0.216717 t_i (beta a/(a'b'))^2) in N/mm, independent of the load;
    it acts in series with K_G0 (see torsion.cracked_radial_stiffness_N_per_mm).
    """
    return radial_force_N / bearing_displacement_mm(radial_force_N, ring_thickness_mm, beta, semi_axes_mm,
                                                    a_mm, E_MPa, Q, variant)


# ---- flexspline: tooth-root crack at angle beta under torsion, modes I and II ----

def flexspline_k_per_load(r_m_mm: float, wall_mm: float, K_u: float, K_d: float, angle_deg: float) -> KPerLoad:
    """K_I/T = K_u K_d sin(2 beta) sqrt(pi a)/(2 pi r_m^2 delta), K_II/T with cos(2 beta) (seed 000)."""
    tau_per_T = K_u * K_d / (2.0 * math.pi * r_m_mm ** 2 * wall_mm)
    s, c = math.sin(math.radians(2.0 * angle_deg)), math.cos(math.radians(2.0 * angle_deg))
    return lambda a: (tau_per_T * s * math.sqrt(math.pi * a), tau_per_T * c * math.sqrt(math.pi * a), 0.0)


def flexspline_crack_flexibility(r_m_mm: float, wall_mm: float, K_u: float, K_d: float, a_mm: float,
                                 E_MPa: float, variant: Variant = Variant.CORRECTED) -> float:
    """dlambda_f (seed 000, flexspline).

    PUBLISHED: K_u K_d a^2 / (2 pi E r_m^4 delta).
    CORRECTED: (K_u K_d)^2 a^2 / (4 pi E r_m^4 delta), the eq-4 integral with dA = delta da
    for any crack angle (sin^2 + cos^2 = 1). PUBLISHED / CORRECTED = 2/(K_u K_d).
    """
    if variant is Variant.PUBLISHED:
        return K_u * K_d * a_mm ** 2 / (2.0 * math.pi * E_MPa * r_m_mm ** 4 * wall_mm)
    return (K_u * K_d) ** 2 * a_mm ** 2 / (4.0 * math.pi * E_MPa * r_m_mm ** 4 * wall_mm)


def flexspline_through_crack_flexibility(r_m_mm: float, wall_mm: float, a_mm: float, E_MPa: float,
                                         tips: int = 2) -> float:
    """dlambda_f of a THROUGH-WALL crack of half-length a (the seed's Griffith K = tau sqrt(pi a)), both tips.

    Seed 000's K_I^2 + K_II^2 = tau^2 pi a at any angle, tau = T/(2 pi r_m^2 delta); a through crack of
    half-length a grows at both tips, dA = 2 delta da, so eq 4 gives tips * a^2 / (4 pi E r_m^4 delta):
    a^2 / (2 pi E r_m^4 delta) for the through crack, twice the seed's own one-tip integral (dA = delta da,
    ``flexspline_crack_flexibility`` CORRECTED) and equal to its PUBLISHED a^2/(2 pi ...) with K_u K_d = 1.
    E' = E (plane stress, as the seed); a thick-wall crack lies between that and plane strain (1 - nu^2).
    """
    if tips not in (1, 2):
        raise ValueError(f"a crack has one or two tips, not {tips}")
    return tips * a_mm ** 2 / (4.0 * math.pi * E_MPa * r_m_mm ** 4 * wall_mm)


# ---- output shaft: circumferential crack, mode III (torque) and mode I (axial force) ----

def shaft_k_per_torque(d_s_mm: float, a_final_mm: float | None, variant: Variant = Variant.CORRECTED) -> KPerLoad:
    """K_III/T = M_M 16 sqrt(pi a)/(pi d_e^3) (seed 000).

    With ``a_final_mm`` given, d_e and M_M are frozen at the final depth (what the
    seed's closed forms assume); with None they follow the growing crack, d_e = d_s - 2a.
    """
    def k(a: float) -> tuple[float, float, float]:
        d_e = d_s_mm - 2.0 * (a if a_final_mm is None else a_final_mm)
        return 0.0, 0.0, m_m(d_e / d_s_mm, variant) * 16.0 * math.sqrt(math.pi * a) / (math.pi * d_e ** 3)
    return k


def shaft_k_per_axial_force(d_s_mm: float, a_final_mm: float | None, variant: Variant = Variant.PUBLISHED) -> KPerLoad:
    """K_I/P = M_P 4 sqrt(pi a)/(pi d_e^2) (seed 000)."""
    def k(a: float) -> tuple[float, float, float]:
        d_e = d_s_mm - 2.0 * (a if a_final_mm is None else a_final_mm)
        return m_p(d_e / d_s_mm, variant) * 4.0 * math.sqrt(math.pi * a) / (math.pi * d_e ** 2), 0.0, 0.0
    return k


def penny_area_element(a: float) -> float:
    """dA = 2 pi a da: a circular (penny) crack, as seed 000 uses for the shaft."""
    return 2.0 * math.pi * a


def circumferential_area_element(d_s_mm: float, a_final_mm: float | None = None) -> AreaElement:
    """dA = pi d_e da: an annular crack of depth a in a bar of diameter d_s (d_e frozen or growing)."""
    return lambda a: math.pi * (d_s_mm - 2.0 * (a if a_final_mm is None else a_final_mm))


def shaft_crack_flexibility(d_s_mm: float, a_mm: float, mu_MPa: float, variant: Variant = Variant.CORRECTED,
                            series: Variant | None = None) -> float:
    """dlambda_so for pure torsion (seed 000, output shaft).

    PUBLISHED: 512 M_M^2 a^3 / (3 mu d_e^6) (penny-crack area dA = 2 pi a da).
    CORRECTED: 128 M_M^2 a^2 / (mu d_e^5) (circumferential crack, dA = pi d_e da).
    PUBLISHED / CORRECTED = 4a/(3 d_e). ``series`` picks the M_M coefficients
    (defaults to the same variant).
    """
    d_e = d_s_mm - 2.0 * a_mm
    mm_ = m_m(d_e / d_s_mm, series or variant)
    if variant is Variant.PUBLISHED:
        return 512.0 * mm_ ** 2 * a_mm ** 3 / (3.0 * mu_MPa * d_e ** 6)
    return 128.0 * mm_ ** 2 * a_mm ** 2 / (mu_MPa * d_e ** 5)


def shaft_mixed_axial_term(d_s_mm: float, a_mm: float, E_MPa: float, variant: Variant = Variant.PUBLISHED) -> float:
    """16 M_P^2 a^2 / (pi E d_e^4), the K_I term seed 000 adds to dlambda_so. Units 1/N, not rad/(N*mm).

    It equals the eq-4 integral of (K_I/P)^2 with dA = da (no crack-front length), and
    is an axial compliance: d^2 K_I^2/dT^2 = 0, so it cannot be added to a torsional one.
    Kept only to report the published value; flagged dimensionally wrong in the audit.
    """
    d_e = d_s_mm - 2.0 * a_mm
    return 16.0 * m_p(d_e / d_s_mm, variant) ** 2 * a_mm ** 2 / (math.pi * E_MPa * d_e ** 4)


def shaft_crack_flexibility_growing(d_s_mm: float, a_mm: float, mu_MPa: float,
                                    variant: Variant = Variant.CORRECTED) -> float:
    """Eq 4 with d_e and M_M following the growing circumferential crack (no frozen-geometry shortcut)."""
    return crack_compliance_integral(shaft_k_per_torque(d_s_mm, None, variant),
                                     circumferential_area_element(d_s_mm, None), a_mm, 1.0, mu_MPa)


# ---- stress intensity factors at a load (the K/P functions times the load) ----

def bearing_K_I(radial_force_N: float, beta: float, semi_axes_mm: tuple[float, float], a_mm: float,
                Q: float) -> float:
    """K_I = 1.95 sigma sqrt(a/Q), sigma = beta sigma_max/2, sigma_max = 3F_r/(2 pi a'b') (seed 000), MPa sqrt(mm)."""
    return radial_force_N * bearing_k_per_load(beta, semi_axes_mm, Q)(a_mm)[0]


def flexspline_K(torque_Nmm: float, r_m_mm: float, wall_mm: float, K_u: float, K_d: float, angle_deg: float,
                 a_mm: float) -> tuple[float, float]:
    """(K_I, K_II) = K_u K_d tau sqrt(pi a) (sin 2beta, cos 2beta), tau = T/(2 pi r_m^2 delta) (seed 000)."""
    kI, kII, _ = flexspline_k_per_load(r_m_mm, wall_mm, K_u, K_d, angle_deg)(a_mm)
    return torque_Nmm * kI, torque_Nmm * kII


def shaft_K_III(torque_Nmm: float, d_s_mm: float, a_mm: float, variant: Variant = Variant.CORRECTED) -> float:
    """K_III = M_M 16 T sqrt(pi a)/(pi d_e^3), d_e = d_s - 2a (seed 000, output shaft)."""
    return torque_Nmm * shaft_k_per_torque(d_s_mm, a_mm, variant)(a_mm)[2]


def shaft_K_I(axial_force_N: float, d_s_mm: float, a_mm: float, variant: Variant = Variant.CORRECTED) -> float:
    """K_I = M_P 4 P sqrt(pi a)/(pi d_e^2) (seed 000, output shaft)."""
    return axial_force_N * shaft_k_per_axial_force(d_s_mm, a_mm, variant)(a_mm)[0]
