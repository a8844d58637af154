"""Higher-fidelity ring-compression physics for the concealed-data generator (never used by the diagnosis).

- ``elastica_curve``: geometrically exact inextensible elastica of a ring under diametral point loads
  (quarter ring, shooting on the redundant moment), dimensionless, tabulated once per benchmark run.
- ``fibre_ring_deflection``: elastic-perfectly-plastic fibre-section ring (small rotations): every section
  carries fibres with plastic-strain memory, the redundant moment is found from compatibility at each
  load step, delta_CD by the unit-load method. Spread of plasticity gives a gradual knee.
- ``curved_beam_factor``: Castigliano on the full curved-beam energy with Cowper's shear coefficient
  (strainwave.analytic.thick_ring.castigliano_deflections), relative to thin-ring theory.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

THIN_DV = (math.pi ** 2 - 8.0) / (4.0 * math.pi)   # seed 003, eq 3


def _quarter(P: float, m_c: float):
    """theta' = -1 + m_c - (P/2) x on s in [0, pi/2] (lengths / R, moments * R/EI, P = F R^2/EI).

    theta is the tangent angle (0 at the load point C, -pi/2 at the free point A when symmetric);
    the load F/2 on the quarter acts downward at C, so the bending moment grows with the lever arm x.
    """
    def rhs(s, z):
        th, x, y = z
        return [-1.0 + m_c - 0.5 * P * x, math.cos(th), math.sin(th)]
    sol = solve_ivp(rhs, (0.0, 0.5 * math.pi), [0.0, 0.0, 0.0], rtol=1e-10, atol=1e-12)
    return sol.y[:, -1]


def elastica_point(P: float) -> float:
    """delta_CD / R of the elastica ring at load parameter P = F R^2/(E I)."""
    if P == 0.0:
        return 0.0
    f = lambda m: _quarter(P, m)[0] + 0.5 * math.pi
    lo, hi = -P - 0.1, P + 0.1      # the redundant moment is about P/pi (seed 003 eq 2 at C)
    m_c = brentq(f, lo, hi, xtol=1e-13)
    th, x, y = _quarter(P, m_c)
    return 2.0 * (1.0 + y)    # vertical drop C->A is -y; undeformed 1


def elastica_curve(max_delta_over_R: float = 0.6, n: int = 40) -> tuple[np.ndarray, np.ndarray]:
    """Table (P, delta_CD/R) from 0 to about ``max_delta_over_R``."""
    P_max = max_delta_over_R / (THIN_DV * 1.0)
    P = np.linspace(0.0, P_max, n)
    return P, np.array([elastica_point(p) for p in P])


def elastica_deflection(F: np.ndarray, R_mm: float, EI_Nmm2: float, table) -> np.ndarray:
    """delta_CD (mm) for forces F (N) by interpolating the dimensionless table (reversible elasticity)."""
    P_tab, d_tab = table
    P = np.abs(F) * R_mm ** 2 / EI_Nmm2
    if P.max() > P_tab[-1]:
        raise ValueError("load beyond the tabulated elastica range")
    return np.sign(F) * np.interp(P, P_tab, d_tab) * R_mm


def fibre_ring_deflection(F_path: np.ndarray, R_mm: float, h_mm: float, b_mm: float, E_MPa: float,
                          yield_MPa: float, n_sections: int = 24, n_fibres: int = 24) -> np.ndarray:
    """delta_CD (mm) along a force path (N) for an elastic-perfectly-plastic fibre-section ring."""
    psi = (np.arange(n_sections) + 0.5) * (0.5 * math.pi / n_sections)   # from the load point C
    w = np.full(n_sections, 0.5 * math.pi / n_sections)
    z = (np.arange(n_fibres) + 0.5) / n_fibres * h_mm - 0.5 * h_mm
    dA = h_mm * b_mm / n_fibres
    eps_p = np.zeros((n_sections, n_fibres))
    I = b_mm * h_mm ** 3 / 12.0
    m_p = 0.25 * b_mm * h_mm ** 2 * yield_MPa   # plastic moment
    out = np.empty(len(F_path))

    def section_curvature(M):
        """Vectorised bisection: curvature change kappa per section with M(kappa) = M (monotone)."""
        k_e = M / (E_MPa * I)
        lo = np.minimum(k_e, 0.0) * 60.0 - 1e-12
        hi = np.maximum(k_e, 0.0) * 60.0 + 1e-12
        lo = np.minimum(lo, -np.abs(eps_p).max(initial=0.0) * 4 / h_mm - 1e-12)
        hi = np.maximum(hi, np.abs(eps_p).max(initial=0.0) * 4 / h_mm + 1e-12)
        for _ in range(45):
            mid = 0.5 * (lo + hi)
            sig = np.clip(E_MPa * (mid[:, None] * z[None, :] - eps_p), -yield_MPa, yield_MPa)
            m_mid = (sig * z[None, :]).sum(axis=1) * dA
            up = m_mid < M
            lo = np.where(up, mid, lo)
            hi = np.where(up, hi, mid)
        return 0.5 * (lo + hi)

    for k, F in enumerate(F_path):
        base = 0.5 * F * R_mm * np.sin(psi)
        # compatibility: integral of the curvature change over the quarter vanishes (C and A do not rotate)
        def compat(m_c):
            M = np.clip(-m_c + base, -0.999 * m_p, 0.999 * m_p)
            return float(w @ section_curvature(M))
        lim = 0.999 * m_p + 0.5 * abs(F) * R_mm
        m_c = brentq(compat, -lim, lim, xtol=1e-9 * max(m_p, 1.0))
        M = np.clip(-m_c + base, -0.999 * m_p, 0.999 * m_p)
        kappa = section_curvature(M)
        sig = np.clip(E_MPa * (kappa[:, None] * z[None, :] - eps_p), -yield_MPa, yield_MPa)
        eps_p = kappa[:, None] * z[None, :] - sig / E_MPa        # commit the plastic strain
        out[k] = 4.0 * float(w @ (kappa * 0.5 * R_mm * np.sin(psi))) * R_mm
    return out


def curved_beam_factor(R_mm: float, h_mm: float, b_mm: float, poisson_ratio: float) -> float:
    """delta_CD of the curved-beam Castigliano solution with Cowper's shear coefficient / thin-ring delta_CD."""
    from strainwave.analytic.thick_ring import RingSection, castigliano_deflections
    section = RingSection(R_mm, h_mm, b_mm)
    cowper = (12.0 + 11.0 * poisson_ratio) / (10.0 * (1.0 + poisson_ratio))   # 1/kappa for a rectangle
    E = 1.0
    G = E / (2.0 * (1.0 + poisson_ratio))
    dv = castigliano_deflections(section, E, G, thick=True, shear_form_factor=cowper)["dv"]
    return dv / (THIN_DV * R_mm ** 3 / (E * section.I_mm4))
