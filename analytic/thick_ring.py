"""Ring under two diametral loads with shear, normal-force and curvature corrections.

A separate, named model next to seed 003's thin ring: Roark's Formulas for Stress and
Strain, Table 9.2 case 1 (two equal and opposite diametral loads W), with

    alpha = I/(A R^2)        (thin)   or  e/R              (thick, I -> A e R)
    beta  = F E I/(G A R^2)  (thin)   or  2 F (1+nu) e/R   (thick)
    k1 = 1 - alpha + beta,   k2 = 1 - alpha

    M_A = W R k2 / pi                         (load point)
    D_V = -(W R^3/EI) (pi k1/4 - 2 k2^2/pi)   (loaded diameter, shortening)
    D_H = +(W R^3/EI) (2 k2^2/pi - (1 - alpha - beta)/2)   (free diameter)

D_H is the audit's own energy derivation ("check it"); ``castigliano_deflections``
evaluates the curved-beam strain energy numerically (bending, normal force, their
curvature coupling and shear) and confirms both D_V and D_H (tests/test_analytic_thick_ring.py).
For a rectangular section F = 1.2 (shear form factor).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import integrate


@dataclass(frozen=True)
class RingSection:
    """Rectangular ring section: centroid radius R, radial depth h, axial width b."""

    R_mm: float
    h_mm: float
    b_mm: float

    @property
    def area_mm2(self) -> float:
        return self.h_mm * self.b_mm

    @property
    def I_mm4(self) -> float:
        return self.b_mm * self.h_mm ** 3 / 12.0

    @property
    def r_inner_mm(self) -> float:
        return self.R_mm - 0.5 * self.h_mm

    @property
    def r_outer_mm(self) -> float:
        return self.R_mm + 0.5 * self.h_mm

    @property
    def neutral_radius_mm(self) -> float:
        """r_n = h / ln(r_o/r_i) for a rectangle (Winkler-Bach)."""
        return self.h_mm / math.log(self.r_outer_mm / self.r_inner_mm)

    @property
    def eccentricity_mm(self) -> float:
        """e = R - r_n, the shift of the neutral axis towards the centre of curvature."""
        return self.R_mm - self.neutral_radius_mm


SHEAR_FORM_FACTOR_RECTANGLE = 1.2  # Roark's F for a rectangular section


@dataclass(frozen=True)
class RingFactors:
    """Roark's hoop-stress (alpha) and shear (beta) deformation factors and k1, k2."""

    alpha: float
    beta: float

    @property
    def k1(self) -> float:
        return 1.0 - self.alpha + self.beta

    @property
    def k2(self) -> float:
        return 1.0 - self.alpha


def thin_ring_factors(section: RingSection, poisson_ratio: float,
                      shear_form_factor: float = SHEAR_FORM_FACTOR_RECTANGLE) -> RingFactors:
    """alpha = I/(A R^2), beta = F E I/(G A R^2) = 2F(1+nu) alpha (Roark Table 9.2, thin ring)."""
    alpha = section.I_mm4 / (section.area_mm2 * section.R_mm ** 2)
    return RingFactors(alpha, 2.0 * shear_form_factor * (1.0 + poisson_ratio) * alpha)


def thick_ring_factors(section: RingSection, poisson_ratio: float,
                       shear_form_factor: float = SHEAR_FORM_FACTOR_RECTANGLE) -> RingFactors:
    """alpha = e/R, beta = 2F(1+nu) e/R (Roark Table 9.2, thick ring; use with I -> A e R)."""
    alpha = section.eccentricity_mm / section.R_mm
    return RingFactors(alpha, 2.0 * shear_form_factor * (1.0 + poisson_ratio) * alpha)


def effective_I_mm4(section: RingSection, thick: bool) -> float:
    """I for the thin model, A e R for the thick one (Roark Table 9.2 notes)."""
    if thick:
        return section.area_mm2 * section.eccentricity_mm * section.R_mm
    return section.I_mm4


def moment_at_load_Nmm(W_N: float, R_mm: float, f: RingFactors) -> float:
    """M_A = W R k2/pi, magnitude of the moment under the load (Roark Table 9.2 case 1)."""
    return W_N * R_mm * f.k2 / math.pi


def moment_at_free_point_Nmm(W_N: float, R_mm: float, f: RingFactors) -> float:
    """Moment at 90 deg from the load: W R (1/2 - k2/pi) (statics + M_A; thin limit = seed 003 eq 2 at B)."""
    return W_N * R_mm * (0.5 - f.k2 / math.pi)


def dv_coefficient(f: RingFactors) -> float:
    """pi k1/4 - 2 k2^2/pi: |D_V| E I/(W R^3); thin limit 0.148778 = seed 003 eq 3."""
    return math.pi * f.k1 / 4.0 - 2.0 * f.k2 ** 2 / math.pi


def dh_coefficient(f: RingFactors) -> float:
    """2 k2^2/pi - (1 - alpha - beta)/2: D_H E I/(W R^3); thin limit 0.136620 = seed 003 eq 4.

    Audit's derivation; confirmed here by ``castigliano_deflections`` (note the
    minus on beta inside the bracket: shear lengthens the free diameter).
    """
    return 2.0 * f.k2 ** 2 / math.pi - 0.5 * (1.0 - f.alpha - f.beta)


def deflections_mm(W_N: float, section: RingSection, E_MPa: float, poisson_ratio: float,
                   thick: bool = True) -> tuple[float, float]:
    """(shortening of the loaded diameter, lengthening of the free diameter) by Roark Table 9.2 case 1."""
    f = thick_ring_factors(section, poisson_ratio) if thick else thin_ring_factors(section, poisson_ratio)
    scale = W_N * section.R_mm ** 3 / (E_MPa * effective_I_mm4(section, thick))
    return scale * dv_coefficient(f), scale * dh_coefficient(f)


def winkler_bach_stress_MPa(M_Nmm: float, N_N: float, r_mm: float, section: RingSection) -> float:
    """Curved-beam (Winkler-Bach) hoop stress at radius r: N/A + M (r - r_n)/(A e r).

    M is positive when it puts the outer fibre in tension. At the inner fibre this is
    the audit's sigma_i = M (r_n - r_i)/(A e r_i) up to the sign convention.
    """
    A, e, rn = section.area_mm2, section.eccentricity_mm, section.neutral_radius_mm
    return N_N / A + M_Nmm * (r_mm - rn) / (A * e * r_mm)


def curvature_stress_factors(section: RingSection) -> tuple[float, float]:
    """(inner, outer) ratio of the Winkler-Bach bending stress to the straight-beam M c/I."""
    c = 0.5 * section.h_mm
    straight = c / section.I_mm4
    inner = abs(winkler_bach_stress_MPa(1.0, 0.0, section.r_inner_mm, section)) / straight
    outer = abs(winkler_bach_stress_MPa(1.0, 0.0, section.r_outer_mm, section)) / straight
    return inner, outer


def castigliano_deflections(section: RingSection, E_MPa: float, G_MPa: float, thick: bool = True,
                            shear_form_factor: float = SHEAR_FORM_FACTOR_RECTANGLE) -> dict:
    """Numerical Castigliano for a ring under diametral loads W (per unit W), by quadrature.

    Strain energy of a curved beam (Winkler kinematics, derived in the module's test notes):
        dU/dphi = R [M^2/(2 E I*) + N^2/(2 E A) + M N/(E A R) + F V^2/(2 G A)],
    I* = A e R (thick) or I (thin); M positive = outer fibre in tension, N positive = tension.
    Quarter ring from the free point B (phi = 0) to the load point D (phi = pi/2);
    load vector (W, Q, M0): W the diametral pair, Q a dummy outward pair at the free
    points, M0 the redundant moment at B. The compliance matrix is integrated with
    scipy.integrate.quad, M0 is condensed out (dU/dM0 = 0).

    Returns dict with ``dv`` (approach of the load points), ``dh`` (separation of the
    free points), ``m_load`` (|M| under the load) and ``m_free`` (|M| at B), all per unit W.
    """
    R, A = section.R_mm, section.area_mm2
    Istar = effective_I_mm4(section, thick)

    def fields(phi):
        s, c = math.sin(phi), math.cos(phi)
        # Internal forces on the arc [0, phi] from the load resultant at B: F_B = (Q/2, W/2).
        m = np.array([-0.5 * R * (1.0 - c), -0.5 * R * s, -1.0])   # d(M)/d(W, Q, M0)
        n = np.array([-0.5 * c, 0.5 * s, 0.0])
        v = np.array([-0.5 * s, -0.5 * c, 0.0])
        return m, n, v

    def entry(i, j):
        def integrand(phi):
            m, n, v = fields(phi)
            return R * (m[i] * m[j] / (E_MPa * Istar) + n[i] * n[j] / (E_MPa * A)
                        + (m[i] * n[j] + m[j] * n[i]) / (E_MPa * A * R)
                        + shear_form_factor * v[i] * v[j] / (G_MPa * A))
        return 4.0 * integrate.quad(integrand, 0.0, 0.5 * math.pi, epsabs=0.0, epsrel=1e-12)[0]

    C = np.array([[entry(i, j) for j in range(3)] for i in range(3)])
    m0 = -C[2, 0] / C[2, 2]                       # redundant moment per unit W
    dv = C[0, 0] + C[0, 2] * m0
    dh = C[1, 0] + C[1, 2] * m0
    m_load = abs(-m0 - 0.5 * R)                   # M at phi = pi/2
    m_free = abs(-m0)
    return {"dv": dv, "dh": dh, "m_load": m_load, "m_free": m_free}
