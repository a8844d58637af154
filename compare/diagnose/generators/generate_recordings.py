"""Concealed recordings for `strainwave benchmark-diagnose`: effects from higher-fidelity models, no labels.

Each recording is produced in physical units from the default parameter set (plus header overrides
where the specimen must change, e.g. a thick rim), with
- a true linear stiffness off the simulated one by a random error within the stated uncertainty,
- an effect from diagnose_hifi_torsion / diagnose_hifi_ring (or none: clean),
- white noise + encoder quantization on the response, white noise on the load (the two
  ``clean_*_coloured`` classes use the coloured noise of family2_sensors instead: AR(1), low-pass, random walk),
- a linear thermal drift and zero offsets on both channels,
- sample counts and signal-to-noise ratios drawn over a wide range, down to the detection limit.
The truth (effect ids, signal-to-noise, noise colour, true hysteresis loss) is returned next to the file
text (``concealed.Concealed``), never inside it.
"""
from __future__ import annotations

import math

import numpy as np

from strainwave.compare.diagnose.generators import family2_sensors as fs
from strainwave.compare.diagnose.generators import hifi_ring as hr
from strainwave.compare.diagnose.generators import hifi_torsion as ht
from strainwave.compare.diagnose.baseline import ring_geometry, torsion_compliance
from strainwave.compare.diagnose.generators.concealed import Concealed, projected_peak, weakest_peak
from strainwave.compare.diagnose.generators.loop_metrics import measure_loop
from strainwave.compare.diagnose.recording import RecordingKind, format_recording

UNCERTAINTY = 0.02
ARCMIN = math.pi / (180.0 * 60.0)
COLOURED = ("ar1", "lowpass", "random_walk")
STIFFEST = 1.8          # largest K3/K1 of the contact-spread stiffening drawn here
TORSION_CLASSES = ("clean_torsion", "clean_torsion_coloured", "compliance_offset", "nonlinear_stiffness", "hysteresis", "lost_motion",
                   "crack_closure", "nonlinear_stiffness+hysteresis", "hysteresis+lost_motion")
RING_CLASSES = ("clean_ring", "clean_ring_coloured", "compliance_offset_ring", "thick_ring", "large_deflection", "plasticity")
CLASSES = TORSION_CLASSES + RING_CLASSES


def _torsion_path(rng, n: int) -> np.ndarray:
    cycles = int(rng.integers(1, 3))
    knots = [0.0] + [1.0, -1.0] * cycles + [1.0, 0.0] if rng.random() < 0.5 else [0.0] + [1.0, -1.0] * cycles + [0.0]
    s = np.linspace(0.0, len(knots) - 1, n)
    return np.interp(s, np.arange(len(knots)), knots)


def _ring_path(rng, n: int) -> tuple[np.ndarray, np.ndarray, list[float]]:
    """(u, path coordinate s, knots): load, unload, or two cycles with a growing peak."""
    knots = [0.0, 1.0, 0.0] if rng.random() < 0.5 else [0.0, 0.6, 0.05, 1.0, 0.0]
    s = np.linspace(0.0, len(knots) - 1, n)
    return np.interp(s, np.arange(len(knots)), knots), s, knots


def _noisy(rng, u_true, y_true_Y, effect_Y, snr, clean_noise, n, noise_kind="white"):
    """Add noise (white or coloured, + quantization), drift and offsets; returns (u, y, noise std, peak)."""
    t = np.linspace(0.0, 1.0, n)
    if effect_Y is None:
        sigma = clean_noise
        peak = 0.0
    else:
        # what the diagnosis sees is the effect plus the stiffness error, which may cancel part of it
        peak = projected_peak(u_true, t, effect_Y + (y_true_Y - u_true), UNCERTAINTY)
        sigma = peak / snr
    q = sigma * rng.uniform(0.0, 2.5)
    white = math.sqrt(max(sigma ** 2 - q ** 2 / 12.0, 0.25 * sigma ** 2))
    y = y_true_Y + (0.0 if effect_Y is None else effect_Y) + fs.coloured_noise(
        rng, n, white, noise_kind, rho=rng.uniform(0.5, 0.95), fc=rng.uniform(0.05, 0.3), wander=rng.uniform(0.3, 0.8))
    y += rng.uniform(-5.0, 5.0) * sigma * t + rng.uniform(-50.0, 50.0) * sigma   # drift, zero offset
    if q > 0:
        y = np.round(y / q) * q
    u = u_true + 2e-4 * rng.standard_normal(n) + rng.uniform(-0.003, 0.003)
    return u, y, math.sqrt(white ** 2 + q ** 2 / 12.0) if q else white, peak


def passive_slip_fraction(frac: float, loss_rad: float, T_max: float, c: float) -> float:
    """The slip range of a Maxwell-slip loop, widened where needed so the chain stays passive.

    A spring-and-slider chain's stuck compliance drop (right after a reversal) must stay below the specimen's
    compliance at full load, c / STIFFEST with the stiffest contact spread drawn; it is kept below half of
    it. The drop scales as 1/frac, so a loop too wide for its slip range gets a wider slip range (<= 0.5
    for loops up to 0.09 c T_max wide)."""
    return max(frac, frac * ht.maxwell_slip_stuck_drop(loss_rad, frac, T_max) / (0.5 * c / STIFFEST))


def generate(cls: str, rng: np.random.Generator, params, *, rows: tuple[int, int] = (200, 2000),
             elastica_table=None) -> Concealed:
    """One concealed recording of class ``cls`` (see CLASSES)."""
    n = int(rng.integers(rows[0], rows[1] + 1))
    snr = float(math.exp(rng.uniform(math.log(0.3), math.log(40.0))))
    clean_noise = 10.0 ** rng.uniform(-3.5, -2.0)
    eps = float(np.clip(rng.normal(0.0, 0.5 * UNCERTAINTY), -UNCERTAINTY, UNCERTAINTY))
    if cls in TORSION_CLASSES:
        return _torsion(cls, rng, params, n, snr, clean_noise, eps)
    return _ring(cls, rng, params, n, snr, clean_noise, eps, elastica_table)


def _torsion(cls, rng, params, n, snr, clean_noise, eps) -> Concealed:
    specimen = str(rng.choice(["output_shaft", "flexspline_cup", "gear"]))
    c0, _ = torsion_compliance(specimen, params)
    X = 1.0e6
    u = _torsion_path(rng, n)
    T = u * X
    c = c0 * (1.0 + eps)
    Y = c0 * X
    parts = cls.split("+")
    effect = np.zeros(n)
    loss = energy = None
    part_effects = []
    for p in parts:
        effect_before = effect.copy()
        if p == "compliance_offset":
            effect += ht.series_compliance_twist(T, c0 * rng.choice([-1, 1]) * rng.uniform(0.06, 0.4))
        elif p == "nonlinear_stiffness":
            K1 = 1.0 / c
            effect += ht.contact_spread_twist(T, K1, K1 * rng.uniform(1.1, STIFFEST), X * rng.uniform(0.15, 0.5),
                                              rng.uniform(1.0, 2.5))
        elif p == "hysteresis":
            target, frac = Y * rng.uniform(0.005, 0.08), rng.uniform(0.05, 0.4)
            frac = passive_slip_fraction(frac, target, X, c)
            effect += ht.maxwell_slip_twist(T, target, frac)
            loop = measure_loop(lambda x: ht.maxwell_slip_twist(x, target, frac), float(np.max(np.abs(T))))
            loss, energy = loop.loss_rad / ARCMIN, loop.energy_Nmm_rad
        elif p == "lost_motion":
            band = X * rng.uniform(0.01, 0.08)
            effect += ht.backlash_twist(T, Y * rng.uniform(0.005, 0.08), band, band * rng.uniform(0.0, 0.2))
        elif p == "crack_closure":
            effect += ht.breathing_crack_twist(T, c0 * rng.uniform(0.05, 0.4), X * rng.uniform(0.005, 0.05),
                                               int(rng.choice([-1, 1])))
        part_effects.append(effect - effect_before)
    clean = cls.startswith("clean")
    noise_kind = str(rng.choice(COLOURED)) if cls.endswith("_coloured") else "white"
    un, yn, noise, peak = _noisy(rng, u, c * T / Y, None if clean else effect / Y, snr, clean_noise, n, noise_kind)
    if not clean and len(parts) > 1:
        peak = weakest_peak(u, np.linspace(0.0, 1.0, n), [e / Y for e in part_effects], UNCERTAINTY)
    text = format_recording(RecordingKind.TORSION, specimen, un * X, yn * Y, baseline_uncertainty=UNCERTAINTY)
    return Concealed(cls, text, () if clean else tuple(parts), peak / noise if not clean else 0.0, "torsion",
                     noise=noise_kind, loss_arcmin=loss, energy_Nmm_rad=energy)


def _ring(cls, rng, params, n, snr, clean_noise, eps, table) -> Concealed:
    ratio = 0.012
    if cls == "thick_ring":
        ratio = float(rng.uniform(0.12, 0.3))
    elif cls == "plasticity":
        ratio = float(rng.uniform(0.02, 0.05))
    elif cls in ("clean_ring", "clean_ring_coloured", "compliance_offset_ring", "large_deflection"):
        ratio = float(rng.uniform(0.01, 0.015))
    p = params.with_value("ewg_drive.rim_thickness_ratio", ratio)
    g = ring_geometry(p)
    R, h, b, E = g["r_m_mm"], g["rim_thickness_mm"], g["face_width_mm"], g["E_MPa"]
    c0 = g["thin_compliance_mm_per_N"]
    c = c0 * (1.0 + eps)
    u, s_path, knots = _ring_path(rng, n)
    truth: tuple[str, ...] = ()
    if cls == "large_deflection" or cls.startswith("clean_ring"):
        d_max = R * (rng.uniform(0.03, 0.25) if cls == "large_deflection" else min(0.01, 0.3 * clean_noise))
        X = d_max / c
        lin = c * u * X
        total = hr.elastica_deflection(u * X, R, g["E_MPa"] * g["I_mm4"] / (1.0 + eps), table)
        effect = total - lin
        truth = ("large_deflection",) if cls == "large_deflection" else ()
    elif cls == "plasticity":
        sy = rng.uniform(400.0, 1200.0)
        F_y = math.pi * sy * b * h ** 2 / 6.0 / R
        X = F_y * rng.uniform(1.15, 1.6)
        F = u * X
        # the path-dependent model runs on 16 steps per leg (turning points exact), then is interpolated
        s_fine = np.linspace(0.0, len(knots) - 1, 16 * (len(knots) - 1) + 1)
        F_fine = np.interp(s_fine, np.arange(len(knots)), knots) * X
        total = np.interp(s_path, s_fine, hr.fibre_ring_deflection(F_fine, R, h, b, E / (1.0 + eps), sy))
        lin = c * F
        effect = total - lin
        truth = ("plasticity",)
    else:
        X = R * 0.02 / c
        lin = c * u * X
        if cls == "thick_ring":
            effect = (hr.curved_beam_factor(R, h, b, g["poisson_ratio"]) - 1.0) * lin
            truth = ("thick_ring",)
        else:
            effect = c0 * rng.choice([-1, 1]) * rng.uniform(0.06, 0.4) * u * X
            truth = ("compliance_offset",)
    Y = c0 * X
    clean = not truth
    noise_kind = str(rng.choice(COLOURED)) if cls.endswith("_coloured") else "white"
    un, yn, noise, peak = _noisy(rng, u, lin / Y, None if clean else effect / Y,
                                 snr, clean_noise, n, noise_kind)
    if clean:
        yn = yn + effect / Y
    overrides = {"ewg_drive": {"rim_thickness_ratio": ratio}}
    text = format_recording(RecordingKind.RING_COMPRESSION, "ewg_ring", un * X, yn * Y,
                            baseline_uncertainty=UNCERTAINTY, params=overrides)
    return Concealed(cls, text, truth, peak / noise if not clean else 0.0, "ring_compression", noise=noise_kind)
