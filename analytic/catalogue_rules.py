"""One set of design rules that turns a catalogue size and ratio into a drive (decision 065).

Fixed before any comparison; no per-size or per-ratio factor. Every proportion is the shipped gear's
(defaults.toml, d1 = 160 mm) made dimensionless, or a standard's value. Nothing is fitted to the catalogue
(``foundation_coefficient`` is the first revision's fitted support, kept as an option and off: decision 065).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from enum import Enum
from functools import lru_cache

from strainwave.analytic.mesh_drive import MeshDesign, bearing_foundation
from strainwave.analytic.mesh_kinematics import MeshGeometry
from strainwave.analytic.wg_bearing import BallBearing

__all__ = ["MeshRules", "RATIO_OF_LABEL", "RimRule", "ratio_of_label", "fatigue_rim_mm"]


class RimRule(str, Enum):
    """How thick the rim under the teeth is (decision 069)."""
    BLANK = "blank"          # rim_over_d d (i/100)^p: one flexspline blank per size (decisions 065-068)
    MODULE = "module"        # rim_over_module m: the CJME 2021 benchmark's and the open twin's 2 m
    FATIGUE = "fatigue"      # the thickest rim the flexspline steel's Goodman line allows at [n] (HDS 9534681)


@lru_cache(maxsize=1)
def _steel() -> tuple[float, float, float, float]:
    """(sigma_-1, R_m, the tooth's notch K_delta K_sigma, [n]) of the project's flexspline steel and design
    (defaults.toml [material], [ewg_drive]: seed 003's factors and permissible safety)."""
    import warnings
    from strainwave.params import load_params
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")     # the defaults' own E/G note, not this rule's business
        p = load_params()
    e = p.ewg_drive
    return (p.material.fatigue_limit_MPa, p.material.ultimate_strength_MPa,
            e.tooth_influence * e.stress_concentration, e.permissible_safety)


def fatigue_rim_mm(d_mm: float, module_mm: float, w0_mm: float, E_MPa: float, torque_Nmm: float,
                   steel: tuple[float, float, float, float] | None = None) -> float:
    """The thickest rim under the teeth whose flexure at the open end passes the project's Goodman line
    (decision 066: n = 1 / (K sigma_a / sigma_-1 + sigma_m / R_m)) at [n]: sigma_a = 1.5 E t w0 / R^2 (the n = 2
    flexure, fully reversed as the wave passes), sigma_m = sqrt(3) T / (2 pi R^2 t) (the torque's shear, steady).
    R is the neutral radius (root radius - t/2), so t is a fixed point."""
    s_1, R_m, K, n = _steel() if steel is None else steel
    t = 0.01 * d_mm
    for _ in range(50):
        R = 0.5 * d_mm - 1.25 * module_mm - 0.5 * t
        a = K * 1.5 * E_MPa * w0_mm / (R * R * s_1)        # K sigma_a / sigma_-1 per mm of rim
        b = math.sqrt(3.0) * torque_Nmm / (2.0 * math.pi * R * R * R_m)     # sigma_m / R_m times t
        disc = 1.0 / n ** 2 - 4.0 * a * b
        if disc < 0.0:
            raise ValueError("no rim passes the Goodman line at this torque")
        t_new = (1.0 / n + math.sqrt(disc)) / (2.0 * a)     # the larger root: the thickest rim allowed
        if abs(t_new - t) < 1e-12 * d_mm:
            return t_new
        t = t_new
    return t

# ">50" rows hold for 80..160 (the CHA table's own footnote); 100, the middle of that band, is the rule
RATIO_OF_LABEL = {">50": 100.0}


def ratio_of_label(label: str) -> float:
    """A ratio column's number: a plain number, or a label the rules map (``>50`` -> 100)."""
    text = label.strip()
    if text in RATIO_OF_LABEL:
        return RATIO_OF_LABEL[text]
    value = float(text)
    if not value > 1.0:
        raise ValueError(text)
    return value


@dataclass(frozen=True)
class MeshRules:
    """How a catalogue size becomes a tooth mesh (lengths over the pitch diameter d)."""

    pitch_diameter_per_size_mm: float = 2.54    # size = pitch diameter in tenths of an inch (RT1-H-CS table)
    tooth_difference: int = 2                   # dual wave: Z_f = 2 i
    kappa: float = 1.0                          # w0 = kappa m, the standard (HDS patents' kappa = 1)
    pressure_angle_deg: float = 20.0            # ISO 53 rack, the shipped profile
    addendum_coefficient: float = 1.0
    rim_over_d: float = 2.24 / 160.0            # seed 000 example: delta / d1
    face_width_over_d: float = 30.0 / 160.0     # shipped circular spline: b / d1 (~0.19, catalogue cup drives)
    backlash_over_d: float = 0.0                # catalogue units are zero-backlash designs (decision 065)
    outer_ring_over_d: float = 2.5 / 160.0      # shipped WG bearing's outer ring / d1
    K_G_per_d_N_per_mm2: float = 6.303e4 / 160.0    # seed 000's implied K_G0 at d1 = 160, similar bodies
    length_over_d: float = 1.0                  # seed 000 example: cup length / d1
    face_slices: int = 1                        # coning slices: 1 (2-4-8 did not converge: decisions 065, 071)
    E_MPa: float = 2.1e5
    shear_modulus_MPa: float = 8.0e4
    friction_coefficient: float = 0.08          # shipped flank mu (0.05-0.12 band, references section 4)
    # the rim's effective radial support k = eta E b / d (N/mm per mm of rim) in series with the balls: the rim
    # wraps the bearing only near the major axis and lifts off beyond (CJME 2021 wrap angle), so eta lies between
    # a free ring's n = 2 stiffness and the Hertz ball bed (foundation_bounds); fitted on sizes 14-25 (decision 065,
    # benchmarks/fit_mesh_foundation.py); None: the balls alone
    foundation_coefficient: float | None = None
    rated_torque_per_d3_MPa: float = 1.0e6 / 160.0 ** 3   # shipped gear's rated torque / d1^3
    ball_diameter_over_d: float = 9.525 / 160.0  # shipped WG bearing: D_w / d1 (3/8 in at d1 = 160)
    ball_count: int = 24                        # shipped WG bearing (similar bodies keep the count)
    rim_ratio_exponent: float = 0.0             # rim = rim_over_d d (i/100)^p: 0 one blank per size (decision 065)
    # decision 069: the thickest rim the steel's Goodman line allows at [n] (HDS patent 9534681's sizing); the cup's
    # wall (cup_flexibility_rad_per_Nmm) stays rim_over_d d: the rule sizes the toothed rim only
    rim_rule: RimRule = RimRule.FATIGUE
    rim_over_module: float = 2.0                # RimRule.MODULE: CJME 2021 benchmark delta_0 = 2 m
    # the cup's extra twist when the torque enters at the two mesh zones (decision 067): measured by FE per ratio at
    # this size on meshes of these elements around the quarter wall (finest first), scaled by similitude; None: left out
    cup_zone_reference_size: float = 25.0
    cup_zone_elements: tuple[int, int, int] | None = (20, 14, 10)
    # decision 070: the circular spline's body (teeth's root to cs_outer_over_d d) with its mounting face clamped to
    # a rigid housing ("face": the stiff bound of any one-face mounting; "free": the soft bound), measured by 3D FE
    # per ratio at cup_zone_reference_size and scaled by similitude; None: left out
    cs_body_restraint: str | None = "face"
    cs_outer_over_d: float = 200.0 / 160.0      # shipped circular spline: outer diameter / d1
    # decision 070-engage48: the teeth's manufacturing deviations, ISO 1328-1:2013 tolerance class of both gears (None:
    # ideal teeth); each row's curve is the mean over this many units (seeds 0..n-1), as the catalogue averages tests
    accuracy_grade: float | None = None
    deviation_units: int = 8

    def foundation_N_per_mm2(self, E_MPa: float, face_width_mm: float, d_mm: float) -> float:
        return (self.foundation_coefficient or 0.0) * E_MPa * face_width_mm / d_mm

    def lumped_foundation_N_per_mm2(self, E_MPa: float, face_width_mm: float, d_mm: float) -> float | None:
        return None if self.foundation_coefficient is None else self.foundation_N_per_mm2(E_MPa, face_width_mm, d_mm)

    def foundation_bounds(self, size: float, ratio: float) -> tuple[float, float]:
        """(eta of the rim alone as a free ring in its n = 2 mode, 9 E I / R^4; eta of the Hertz ball bed at the
        rated torque): the physical range of the lumped support (lift-off to full wrap)."""
        dd = self.design(size, ratio)
        g, d = dd.geometry, self.pitch_diameter_mm(size)
        I_rim = g.face_width_mm * g.rim_thickness_mm ** 3 / 12.0
        k_ring = 9.0 * self.E_MPa * I_rim / g.neutral_radius_mm ** 4
        k_balls = replace(self, foundation_coefficient=None).design(size, ratio).foundation_N_per_mm2
        scale = d / (self.E_MPa * g.face_width_mm)
        return k_ring * scale, k_balls * scale

    def pitch_diameter_mm(self, size: float) -> float:
        return self.pitch_diameter_per_size_mm * size

    def design(self, size: float, ratio: float, unit: int | None = None) -> MeshDesign:
        """The drive of catalogue ``size`` at gear ratio ``ratio``: only the rules above; ``unit``: the seed of one
        unit's tooth deviations (with ``accuracy_grade``), None: ideal teeth."""
        d = self.pitch_diameter_mm(size)
        teeth = int(round(self.tooth_difference * ratio))
        m = d / teeth
        b = self.face_width_over_d * d
        rim = self.rim_mm(size, ratio)
        geom = MeshGeometry(teeth, m, self.kappa * m, self.pressure_angle_deg, self.addendum_coefficient,
                            self.backlash_over_d * d, rim, b, self.tooth_difference,
                            self.length_over_d * d, self.face_slices,
                            None if unit is None else self.accuracy_grade, 0 if unit is None else unit)
        ring, ball = self.outer_ring_over_d * d, self.ball_diameter_over_d * d
        # the ball set fills the envelope: under the cup's bore and the outer ring
        balls = BallBearing(ball, self.ball_count, d - 2.0 * (1.25 * m + rim) - 2.0 * ring - ball)
        k, ref = bearing_foundation(geom, balls, ring, self.E_MPa, 1e3 * self.rated_torque_Nm(size),
                                    self.lumped_foundation_N_per_mm2(self.E_MPa, b, d))
        return MeshDesign(geom, self.E_MPa, self.friction_coefficient, ring, k, self.K_G_per_d_N_per_mm2 * d,
                          balls, ref)

    def rim_mm(self, size: float, ratio: float) -> float:
        """The rim under the teeth by ``rim_rule``."""
        d = self.pitch_diameter_mm(size)
        m = d / int(round(self.tooth_difference * ratio))
        rule = RimRule(self.rim_rule)
        if rule is RimRule.MODULE:
            return self.rim_over_module * m
        if rule is RimRule.FATIGUE:
            return fatigue_rim_mm(d, m, self.kappa * m, self.E_MPa, 1e3 * self.rated_torque_Nm(size))
        return self.rim_over_d * d * (ratio / 100.0) ** self.rim_ratio_exponent

    def rated_torque_Nm(self, size: float) -> float:
        return 1e-3 * self.rated_torque_per_d3_MPa * self.pitch_diameter_mm(size) ** 3

    def cup_flexibility_rad_per_Nmm(self, size: float) -> float:
        """The cup in torsion: tube + diaphragm + hub in series (``torsion.cup_series_flexibility``, the project's
        corrected cup flexibility, docs/architecture.md), on the CAD's hub and diaphragm proportions with the
        rim as wall and diaphragm. The rules' cup (wall 0.014 d, length d) is the shipped cup scaled, on which
        validate's ``cup.flexibility`` holds the FE to this model (decision 067)."""
        from strainwave.analytic import torsion
        from strainwave.geometry.flexspline_cup import BAND_RATIO, BOSS_HEIGHT_WALLS, HUB_BORE_RATIO, HUB_RATIO
        d = self.pitch_diameter_mm(size)
        t = self.rim_over_d * d
        return torsion.cup_series_flexibility(
            d, t, self.length_over_d * d, self.shear_modulus_MPa, hub_radius_mm=HUB_RATIO * d,
            hub_bore_radius_mm=HUB_BORE_RATIO * d, hub_height_mm=BOSS_HEIGHT_WALLS * t, diaphragm_thickness_mm=t,
            band_length_mm=BAND_RATIO * d, diaphragm_z_mm=(BOSS_HEIGHT_WALLS - 0.5) * t).total

    def check_cup_length(self, size: float, ratio: float) -> None:
        """Refuse a cup whose tooth band (face_width_over_d) reaches the diaphragm's mid-plane, 3.5 rims from the
        closed end (the cup-zone FE's tube): exit 2 naming length_over_d and the shortest length allowed."""
        from strainwave.errors import InputError
        from strainwave.geometry.flexspline_cup import BOSS_HEIGHT_WALLS
        d = self.pitch_diameter_mm(size)
        need = self.face_width_over_d + (BOSS_HEIGHT_WALLS - 0.5) * self.rim_mm(size, ratio) / d
        if self.length_over_d <= need:
            raise InputError("length_over_d", self.length_over_d,
                             f"must be > {need:.4g} at ratio {ratio:g}: face_width_over_d {self.face_width_over_d:.4g} "
                             f"+ 3.5 rims of {self.rim_mm(size, ratio) / d:.4g} d (the tooth band must start above "
                             f"the diaphragm's mid-plane)")

    def cs_body_term(self, ratio: float):
        """The circular spline body's twist term at this ratio (``analytic.cs_housing``), measured at
        ``cup_zone_reference_size``; None when the rules leave it out."""
        if self.cs_body_restraint is None:
            return None
        from strainwave.analytic.cs_housing import cs_body_term
        size = self.cup_zone_reference_size
        return cs_body_term(self.design(size, ratio), self.cs_outer_over_d * self.pitch_diameter_mm(size),
                            self.cs_body_restraint)

    def cup_zone_term(self, ratio: float):
        """The cup's extra flexibility under the mesh zones' load at this ratio (``analytic.cup_zone``), measured
        at ``cup_zone_reference_size``; None when the rules leave it out."""
        if self.cup_zone_elements is None:
            return None
        from strainwave.analytic.cup_zone import cup_zone_term
        size = self.cup_zone_reference_size
        self.check_cup_length(size, ratio)
        return cup_zone_term(self.design(size, ratio), 1e3 * self.rated_torque_Nm(size), self.cup_zone_elements,
                             ratio)
