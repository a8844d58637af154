"""A thin ring (or the band of a long cylindrical shell) forced into the wave generator's shape
w = w0 cos(n phi): its change of curvature and its hoop bending stress. Derived here; seed 003's eqs 8-9
are for a ring squeezed by two point loads, not for a prescribed shape.

Derivation (mid-surface radius r, radial displacement w outward, tangential v towards +phi, thin ring):
- membrane strain eps = (v' + w)/r. The wave generator's deformation is inextensional (a flexspline's
  neutral line keeps its length), eps = 0, so v' = -w and v = -(w0/n) sin(n phi);
- change of curvature: the curvature 1/rho of the deformed mid-line is, to first order in w/r,
  1/r - (w + w'')/r^2 (a uniform w gives 1/(r + w) ~ 1/r - w/r^2; the w'' term is the beam's own bending),
  so kappa = -(w + w'')/r^2 = (n^2 - 1) w0 cos(n phi)/r^2;
- a fibre at distance y outward of the mid-line stretches by eps_y = y kappa (its length (rho + y) dpsi
  against rho dpsi, thin ring: y/r << 1), so sigma_theta = E' y kappa and at the fibres y = +-t/2:

      sigma_outer = +E' (t/2) (n^2 - 1) w0 cos(n phi) / r^2,   sigma_inner = -sigma_outer.

  For the double wave n = 2: +-E' t/2 * 3 w0/r^2 at the major axis (phi = 0, outer fibre in tension, the
  ellipse is sharper there than the circle) and the opposite sign at the minor axis (phi = 90 deg).
- E' = E (plane stress: a narrow free ring, anticlastic curvature free) or E/(1 - nu^2) (plane strain:
  the band of a long cylindrical shell, where shell theory gives M_theta = D (kappa_theta + nu kappa_z) with
  D = E t^3/12(1 - nu^2) and kappa_z = w_zz = 0 for a band whose w does not vary along z).
- neglected: terms of order t/(2r) (a curved beam's fibre strain is y kappa/(1 + y/r)), and the
  membrane stretching of order (w0/r)^2 (second order: the geometrically nonlinear FEA contains it).
"""
from __future__ import annotations

import math

import numpy as np


def effective_modulus_MPa(E_MPa: float, poisson_ratio: float, *, plane_strain: bool) -> float:
    """E' = E/(1 - nu^2) for the band of a long shell (no anticlastic curvature), E for a free narrow ring."""
    return E_MPa / (1.0 - poisson_ratio ** 2) if plane_strain else E_MPa


def curvature_change_per_mm(phi_rad, w0_mm: float, r_m_mm: float, wave_number: int = 2):
    """kappa = -(w + w'')/r^2 = (n^2 - 1) w0 cos(n phi)/r^2 for w = w0 cos(n phi) (derived above)."""
    n = float(wave_number)
    return (n * n - 1.0) * w0_mm * np.cos(n * np.asarray(phi_rad, dtype=float)) / r_m_mm ** 2


def hoop_bending_stress_MPa(phi_rad, w0_mm: float, thickness_mm: float, r_m_mm: float, E_MPa: float,
                            poisson_ratio: float, *, fibre: float = 1.0, plane_strain: bool = True,
                            wave_number: int = 2):
    """sigma_theta = E' (fibre t/2) (n^2 - 1) w0 cos(n phi)/r_m^2: fibre = +1 outer, -1 inner (derived above)."""
    if not -1.0 <= fibre <= 1.0:
        raise ValueError(f"fibre must lie in [-1, 1] (a fraction of t/2), got {fibre!r}")
    E_eff = effective_modulus_MPa(E_MPa, poisson_ratio, plane_strain=plane_strain)
    return E_eff * fibre * 0.5 * thickness_mm * curvature_change_per_mm(phi_rad, w0_mm, r_m_mm, wave_number)


def axis_stresses_MPa(w0_mm: float, thickness_mm: float, r_m_mm: float, E_MPa: float, poisson_ratio: float,
                      *, plane_strain: bool = True, wave_number: int = 2) -> dict[str, float]:
    """Outer- and inner-fibre hoop stress at the major axis (phi = 0) and the minor axis (phi = pi/n)."""
    out = {}
    for axis, phi in (("major", 0.0), ("minor", math.pi / wave_number)):
        for name, fibre in (("outer", 1.0), ("inner", -1.0)):
            out[f"{axis}_{name}"] = float(hoop_bending_stress_MPa(
                phi, w0_mm, thickness_mm, r_m_mm, E_MPa, poisson_ratio, fibre=fibre, plane_strain=plane_strain,
                wave_number=wave_number))
    return out


def curved_beam_allowance(thickness_mm: float, r_m_mm: float) -> float:
    """t/(2 r_m): the first-order size of what the thin ring leaves out (fibre strain y kappa/(1 + y/r))."""
    return 0.5 * thickness_mm / r_m_mm
