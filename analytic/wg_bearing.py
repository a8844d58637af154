"""Closed forms of the wave generator bearing's inner ring on the elliptical cam (issue 34, item 3).

Ring forced into the cam's shape. A thin ring of mid-surface radius r_m whose radial displacement is
w(phi) = w0 cos 2phi (outward +) and whose mid-surface does not stretch (v' = -w) changes its curvature by
d_kappa = -(w + w'')/r_m^2 = 3 w0 cos 2phi / r_m^2; a fibre at y outward of the mid-surface then strains
eps = y d_kappa, so at the race (y = +t/2)

    sigma_race(phi) = + 3 E t w0 cos 2phi / (2 r_m^2)          (thin ring; tension at the major axis phi = 0)

and the bore carries the opposite sign. The thick ring (t/r_m = 0.17 on the default): with w the same through
the thickness and plane sections normal (gamma_r phi = 0: v = w' + r C(phi)), every fibre strains
eps(r) = (w + w'')/r + C' = -3 w0 cos 2phi / r + C'. The cam presses radially only, so tangential equilibrium
gives N' = -M'/r_m, i.e. a membrane force N = -M/r_m (compressive where the race is in tension), which fixes
C'; with r_n = t/ln(r_o/r_i) (Winkler's neutral radius)

    sigma(r) = 3 E w0 cos 2phi [ (r - r_n)/(r r_n) - (r_m - r_n)/(r_n r_m) ]       (curved beam, shown)

What it leaves out (radial stress between cam and race, through-thickness strain) is second order in t/r_m;
the check asserts the exact plane-stress solution instead (``analytic.michell_ring``) and shows this beside it.

Ball loads (Stribeck, zero clearance, rigid rings): ball i at psi_i = 2 pi i/Z is pressed by
delta_0 cos psi_i, Hertz Q = K_n delta^(3/2), so Q_i = Q_max cos^(3/2) psi_i over |psi_i| < 90 deg, and
equilibrium sum Q_i cos psi_i = F_r fixes Q_max = F_r / sum cos^(5/2) psi_i (Z Q_max / F_r -> 4.37, Stribeck).

Race crack (2D edge crack of depth a through the ring width B, at the major axis): the FEA's uncracked hoop
stress sigma(x) along the crack line (x from the race) goes into the edge-crack weight function of a
half-plane (Tada, Paris & Irwin, The Stress Analysis of Cracks Handbook, 3rd ed., p. 8.2, accuracy 1 %):

    K = 2 sqrt(a/pi) int_0^(pi/2) sigma(a sin th) (1.3 - 0.3 sin^(5/4) th) dth      (x = a sin th)

and seed 000's eq 4 with dA = B da gives the added compliance dlambda = int_0^a 2/E (K/F)^2 B da. The back
face is the bore held by the cam, between a half-plane (the form) and a free strip (Tada's F_t(a/t)), whose
amplification of the compliance is the allowance (``back_face_allowance``).

The flexible bearing as a radial spring (issue 48; merged into this module, both halves kept):

A ball pressed between its two raceways by the load Q approaches them by (Palmgren 1959, "Ball and Roller
Bearing Engineering", 3rd ed., eq. for point contact of steel balls; Harris & Kotzalas, "Rolling Bearing
Analysis", 5th ed., 2006, the ball bearing's load-deflection constant)

    delta = 4.36e-4 Q^(2/3) / D_w^(1/3)          (mm, N, mm; both raceways, steel on steel)

so its tangent stiffness dQ/d(delta) = 1.5 Q / delta grows as Q^(1/3): the bearing stiffens with the load, one
source of K1 < K3. Under the flexspline's rim, balls a pitch s apart are a foundation of modulus k_ball / s per
unit rim length; the rim and the outer ring bend over it as a beam on an elastic foundation (Hetenyi), so a radial
load R on the rim presses the nearest ball with Q = R beta s / 2 (the foundation's peak pressure R beta / 2 times
the pitch; one ball at most carries R). A flank's radial push F sin(alpha) moves the tooth inward and opens the
flank circumferentially by tan(alpha) per unit travel: the output turns by delta tan(alpha) / r_p.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

__all__ = ["thin_ring_race_stress_MPa", "curved_beam_race_stress_MPa",
           "stribeck_ball_loads", "hertz_ball_constant", "ring_local_compliance_mm_per_N",
           "edge_crack_K", "edge_crack_compliance_mm_per_N", "seed_form_compliance_mm_per_N",
           "tada_strip_tension_factor", "back_face_allowance",
           "PALMGREN_SOURCE", "ball_contact_deflection_mm", "ball_contact_stiffness_N_per_mm", "BallBearing",
           "peak_ball_load_N", "linearised_foundation", "hertz_remainder_twist_rad"]

SEED_SURFACE_FACTOR = 1.95   # seed 000's K_I = 1.95 sigma sqrt(a/Q)


def thin_ring_race_stress_MPa(E_MPa: float, t_mm: float, r_m_mm: float, w0_mm: float, phi_rad: float = 0.0) -> float:
    """+3 E t w0 cos 2phi / (2 r_m^2): the race (outer) fibre of a thin ring forced into w0 cos 2phi."""
    return 3.0 * E_MPa * t_mm * w0_mm * math.cos(2.0 * phi_rad) / (2.0 * r_m_mm ** 2)


def _neutral_radius_mm(r_i_mm: float, r_o_mm: float) -> float:
    return (r_o_mm - r_i_mm) / math.log(r_o_mm / r_i_mm)


def curved_beam_race_stress_MPa(E_MPa: float, r_i_mm: float, r_o_mm: float, w0_mm: float, phi_rad: float = 0.0,
                                fibre_mm: float | None = None) -> float:
    """Hoop stress at radius ``fibre_mm`` (default the race r_o) of a thick ring whose radial displacement
    w0 cos 2phi is the same through the thickness, plane sections normal (module docstring):
    eps(r) = -3 w0 cos 2phi / r + C'; the membrane force N = -M/r_m fixes C', so
    sigma(r) = 3 E w0 cos 2phi [(r - r_n)/(r r_n) - (r_m - r_n)/(r_n r_m)],  r_n = t / ln(r_o/r_i)."""
    r = r_o_mm if fibre_mm is None else fibre_mm
    r_m, r_n = 0.5 * (r_o_mm + r_i_mm), _neutral_radius_mm(r_i_mm, r_o_mm)
    return 3.0 * E_MPa * w0_mm * math.cos(2.0 * phi_rad) * ((r - r_n) / (r * r_n) - (r_m - r_n) / (r_n * r_m))


def ball_angles_rad(ball_count: int) -> np.ndarray:
    """Angles of the balls that the load direction (psi = 0, a ball on it) can press: |psi| < 90 deg."""
    psi = 2.0 * np.pi * np.arange(ball_count) / ball_count
    psi = np.angle(np.exp(1j * psi))
    return np.sort(psi[np.cos(psi) > 1e-12])


def stribeck_ball_loads(force_N: float, ball_count: int) -> tuple[np.ndarray, np.ndarray]:
    """(psi_i, Q_i): Q_max cos^(3/2) psi_i with sum Q_i cos psi_i = F_r (zero clearance, rigid rings)."""
    psi = ball_angles_rad(ball_count)
    c = np.cos(psi)
    q_max = force_N / float(np.sum(c ** 2.5))
    return psi, q_max * c ** 1.5


def hertz_ball_constant(force_N: float, semi_axes_mm: tuple[float, float], E_MPa: float, nu: float) -> float:
    """K_n of Q = K_n delta^(3/2) for one ball between two races (two equal contacts in series), from the
    seed's contact ellipse taken at ``force_N``: delta_contact = 3 F/(2 k), k = pi a E*/K(e) (Johnson)."""
    from strainwave.analytic.bearing_stiffness import hertz_contact_stiffness_N_per_mm

    k = hertz_contact_stiffness_N_per_mm(*semi_axes_mm, E_MPa, nu)
    delta_pair = 2.0 * 1.5 * force_N / k
    return force_N / delta_pair ** 1.5


def ring_local_compliance_mm_per_N(E_MPa: float, t_mm: float, width_mm: float, b_mm: float) -> float:
    """The ring's radial compliance under one ball: the load spreading at 45 deg through the thickness t onto
    the cam, ln((b + t)/b)/(2 E B), doubled for the indentation under the patch (an upper estimate)."""
    return math.log((b_mm + t_mm) / b_mm) / (E_MPa * width_mm)


# ---- race crack ----

_TH, _WT = np.polynomial.legendre.leggauss(64)
_TH = 0.25 * np.pi * (_TH + 1.0)
_WT = 0.25 * np.pi * _WT


def edge_crack_K(stress_fn: Callable[[np.ndarray], np.ndarray], a_mm: float) -> float:
    """K (MPa sqrt(mm)) of an edge crack of depth a in a half-plane whose uncracked normal stress on the crack
    line is ``stress_fn(x)``, x the depth from the surface (Tada p. 8.2 weight function, module docstring)."""
    s = np.sin(_TH)
    return 2.0 * math.sqrt(a_mm / math.pi) * float(np.sum(_WT * stress_fn(a_mm * s) * (1.3 - 0.3 * s ** 1.25)))


def edge_crack_compliance_mm_per_N(stress_per_N: Callable[[np.ndarray], np.ndarray], a_mm: float, E_MPa: float,
                                   width_mm: float, points: int = 48) -> float:
    """dlambda = int_0^a 2/E (K/F)^2 B da' (seed 000 eq 4, front length B) with K from ``edge_crack_K``."""
    x, w = np.polynomial.legendre.leggauss(points)
    aa, ww = 0.5 * a_mm * (x + 1.0), 0.5 * a_mm * w
    k = np.array([edge_crack_K(stress_per_N, float(ai)) for ai in aa])
    return float(np.sum(ww * 2.0 / E_MPa * k ** 2 * width_mm))


def seed_form_compliance_mm_per_N(stress_per_N_MPa: float, a_mm: float, E_MPa: float, width_mm: float,
                                  Q: float = 1.0) -> float:
    """Seed 000's bearing form, K = 1.95 sigma sqrt(a/Q) with sigma the FEA's hoop stress at the crack mouth
    per newton (like for like) instead of beta p0/2, integrated by eq 4 over a front of length B:
    2/E 1.95^2 sigma^2 a^2 B / (2 Q). Q = 1: the 2D crack's front is straight (a/c = 0)."""
    return 2.0 / E_MPa * SEED_SURFACE_FACTOR ** 2 * stress_per_N_MPa ** 2 * a_mm ** 2 * width_mm / (2.0 * Q)


def tada_strip_tension_factor(alpha: float) -> float:
    """F(a/t) of K = F sigma sqrt(pi a), edge crack in a strip of width t under tension (Tada p. 2.11, 0.5 %)."""
    h = 0.5 * math.pi * alpha
    return math.sqrt(math.tan(h) / h) * (0.752 + 2.02 * alpha + 0.37 * (1.0 - math.sin(h)) ** 3) / math.cos(h)


def back_face_allowance(a_mm: float, t_mm: float) -> float:
    """How much a free back face could raise a uniformly loaded edge crack's compliance over the half-plane's:
    int_0^a F(x/t)^2 x dx / (F(0)^2 a^2/2) - 1, F(0) = 1.1215 (the cam holds the bore, so the ring lies between)."""
    x, w = np.polynomial.legendre.leggauss(32)
    xs, ws = 0.5 * a_mm * (x + 1.0), 0.5 * a_mm * w
    f2 = np.array([tada_strip_tension_factor(xi / t_mm) ** 2 for xi in xs])
    f0 = tada_strip_tension_factor(1e-9)
    return float(np.sum(ws * f2 * xs) / (f0 ** 2 * a_mm ** 2 / 2.0) - 1.0)


# ---- the flexible bearing as a radial spring (Palmgren; issue 48) ----

PALMGREN_SOURCE = ("Palmgren 1959 / Harris & Kotzalas 2006: delta = 4.36e-4 Q^(2/3) D_w^(-1/3) mm "
                   "(ball between both raceways, steel)")
_PALMGREN = 4.36e-4      # mm N^(-2/3) mm^(1/3)


def ball_contact_deflection_mm(Q_N, ball_diameter_mm: float):
    """Approach of both raceways over one ball under the load Q (Palmgren)."""
    return _PALMGREN * np.power(np.maximum(Q_N, 0.0), 2.0 / 3.0) / ball_diameter_mm ** (1.0 / 3.0)


def ball_contact_stiffness_N_per_mm(Q_N, ball_diameter_mm: float):
    """Tangent stiffness dQ/d(delta) = 1.5 Q^(1/3) D_w^(1/3) / 4.36e-4 (zero at zero load: no preload)."""
    return 1.5 * np.power(np.maximum(Q_N, 0.0), 1.0 / 3.0) * ball_diameter_mm ** (1.0 / 3.0) / _PALMGREN


@dataclass(frozen=True)
class BallBearing:
    """The WG bearing's balls under the rim (mm)."""

    ball_diameter_mm: float
    ball_count: int
    pitch_diameter_mm: float       # of the ball set

    @property
    def ball_pitch_mm(self) -> float:
        return math.pi * self.pitch_diameter_mm / self.ball_count


def peak_ball_load_N(radial_load_N: float, beta_per_mm: float, ball_pitch_mm: float) -> float:
    """The most loaded ball under a radial load R on a rim bending over the balls (Hetenyi's peak pressure)."""
    return radial_load_N * min(1.0, 0.5 * beta_per_mm * ball_pitch_mm)


def linearised_foundation(bearing: BallBearing, radial_load_N: float, EI_Nmm2: float,
                          lumped_N_per_mm2: float | None = None, iterations: int = 30) -> tuple[float, float]:
    """(foundation modulus N/mm per mm of rim, the peak ball load N) with the balls' tangent stiffness at the
    ball load that ``radial_load_N`` makes, in series with an optional lumped foundation (fixed point in beta)."""
    s = bearing.ball_pitch_mm
    Q = radial_load_N
    k = 0.0
    for _ in range(iterations):
        k_ball = ball_contact_stiffness_N_per_mm(max(Q, 1e-9), bearing.ball_diameter_mm) / s
        k = k_ball if lumped_N_per_mm2 is None else 1.0 / (1.0 / k_ball + 1.0 / lumped_N_per_mm2)
        beta = (k / (4.0 * EI_Nmm2)) ** 0.25
        Q_new = peak_ball_load_N(radial_load_N, beta, s)
        if abs(Q_new - Q) <= 1e-9 * max(Q, 1e-12):
            break
        Q = Q_new
    return float(k), float(Q)


def hertz_remainder_twist_rad(torque_Nmm, *, bearing: BallBearing, Q_at_reference_N: float,
                              reference_torque_Nmm: float, pitch_radius_mm: float, alpha_deg: float):
    """The balls' twist beyond their tangent line at the reference torque (which the linear mesh model holds):
    sign(T) tan(alpha)/r_p [delta(Q(|T|)) - Q(|T|) / k_t(Q_ref)], Q proportional to |T| (the zone's radial load
    per lobe is T tan(alpha) / (2 r_p)). Odd in T, zero slope at the reference torque, steep near zero."""
    T = np.asarray(torque_Nmm, float)
    Q = Q_at_reference_N * np.abs(T) / reference_torque_Nmm
    D = bearing.ball_diameter_mm
    extra = ball_contact_deflection_mm(Q, D) - Q / ball_contact_stiffness_N_per_mm(Q_at_reference_N, D)
    return np.sign(T) * math.tan(math.radians(alpha_deg)) / pitch_radius_mm * extra
