#!/usr/bin/env python3
"""Held-out black-box benchmark no. 3 of `strainwave diagnose`.

Written blind: nothing under compare/, tests/ or the other held-out benchmarks was read or imported.
The only contract used is docs/recordings.md (file format, JSON keys, catalogue ids) and the CLI.

Generators use laws of their own (not the catalogue's forms):
  in catalogue   LuGre bristle friction joint (time-integrated, slightly rate dependent), a 3-element
                 generalised Maxwell-slip model (parallel, different stiffnesses, torque-driven by
                 bisection), cubic stiffening twist = c T - d T^3, a 5-breakpoint piecewise-linear
                 compliance table, an algebraic smooth dead zone b T / sqrt(T^2 + w^2), a crack whose
                 compliance rises linearly with |T| on one sign, stiffening + LuGre loop, kinematic ripple
                 at 2x and 4x (plus a weak 6x) of the input angle, a ring with a linear-hardening hinge.
  clean          white, pink (1/f), AR(1), random walk + white, mains hum (a time sinusoid at 0.3 sigma),
                 quantisation coarser than the noise, 0.2 % torque gain error, jittered time stamps, a
                 start mid-cycle, 200 to 20,000 rows, offsets and drift.
  out of cat.    a single spike, a 20-row dropout of the twist channel, a compliance drifting with
                 temperature, a clamp slip (step in twist), a response clipped at +2/3 of full scale, a
                 power-law damper at two loading rates, a friction loop widening with wear, a torque channel
                 reading 5 % high above half load, symmetric softening (yield onset).

SNR = peak |effect| left after a least-squares nuisance fit (offset, stiffness scale, linear drift in
time) / noise std.  For two effects the weaker effect's SNR is used.  "Must name" classes are scored
only at SNR >= 3.  Clean recordings have no SNR (printed as '-').

Scoring:
  in-catalogue  OK = verdict explained and named set == truth set (exact); "primary" = the truth's
                stronger effect is in `named`.
  clean         OK = verdict agrees.
  out of cat.   OK = verdict unexplained, or a named effect flagged ambiguous; "confidently wrong" =
                verdict explained and not ambiguous.
  loss          where the truth has a friction loop: reported hysteresis_loss_arcmin within 10 % of the
                truth width at zero torque of the recording's last full-scale cycle (noise-free curve).

Usage:
  python benchmarks/heldout3_diagnose.py [--seed 0] [--out DIR] [--only NAME[,NAME..]] [--keep DIR]
  (--keep DIR writes each generated CSV into DIR; --only restricts to the named recordings.)
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
import zlib
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
CLI = str(REPO / ".venv" / "bin" / "strainwave")

# Baselines of the default parameter file, read from a noiseless linear recording
# (`baseline_stiffness` parameter of compliance_offset); re-checked at start-up by calibrate().
K0 = 7.89357013815e8        # N*mm/rad, output_shaft analytic baseline
KRING = 16.8797             # N/mm, ewg_ring thin-ring baseline
TFS = 1.0e6                 # N*mm, rated output torque of the default gear
PHI_FS = TFS / K0           # rad
ARCMIN = 10800.0 / np.pi    # rad -> arcmin

# ----------------------------------------------------------------------------------------------
# paths and noise


def sine_path(n, cycles=2.6, phase=0.0, period_s=20.0, amp=TFS):
    """Torque in N*mm and time in s: a sinusoid from `phase`, `cycles` periods."""
    t = np.linspace(0.0, cycles * period_s, n)
    T = amp * np.sin(2 * np.pi * t / period_s + phase)
    return t, T


def white(rng, n, s):
    return rng.normal(0.0, s, n)


def pink(rng, n, s):
    f = np.fft.rfftfreq(n)
    spec = rng.normal(size=f.size) + 1j * rng.normal(size=f.size)
    spec[1:] /= np.sqrt(f[1:])
    spec[0] = 0.0
    x = np.fft.irfft(spec, n)
    return s * x / x.std()


def ar1(rng, n, s, rho):
    e = rng.normal(0.0, s * np.sqrt(1 - rho ** 2), n)
    x = np.empty(n)
    x[0] = rng.normal(0.0, s)
    for i in range(1, n):
        x[i] = rho * x[i - 1] + e[i]
    return x


def nuisance_peak(t, T, r):
    """Peak |r| after a least-squares fit of offset, stiffness scale and linear drift."""
    A = np.column_stack([np.ones_like(T), T / TFS, (t - t.mean()) / (np.ptp(t) + 1e-30)])
    c, *_ = np.linalg.lstsq(A, r, rcond=None)
    return float(np.max(np.abs(r - A @ c)))


def deslope(T, u):
    """u minus its least-squares line in T: the loop's mean compliance is given to the specimen, so the
    recording's mean stiffness is the baseline's (no compliance offset in the truth)."""
    A = np.column_stack([np.ones_like(T), T])
    c, *_ = np.linalg.lstsq(A, u, rcond=None)
    return u - c[1] * T


def loop_width_last(T, phi):
    """Width at zero torque of the last full-scale cycle: twist on the last descending zero crossing
    (after a peak > 0.95 FS) minus twist on the last ascending one (after a trough < -0.95 FS)."""
    fs = np.max(np.abs(T))
    desc, asc = None, None
    peak_hi, peak_lo = False, False
    for i in range(1, len(T)):
        if T[i - 1] > 0.95 * fs:
            peak_hi = True
        if T[i - 1] < -0.95 * fs:
            peak_lo = True
        if T[i - 1] > 0 >= T[i] and peak_hi:
            a = T[i - 1] / (T[i - 1] - T[i])
            desc = phi[i - 1] + a * (phi[i] - phi[i - 1])
            peak_hi = False
        if T[i - 1] < 0 <= T[i] and peak_lo:
            a = -T[i - 1] / (T[i] - T[i - 1])
            asc = phi[i - 1] + a * (phi[i] - phi[i - 1])
            peak_lo = False
    if desc is None or asc is None:
        return None
    return float((desc - asc) * ARCMIN)


# ----------------------------------------------------------------------------------------------
# physics


def lugre_joint(t, T, k_j, Fc, sig0, tau_bristle, tau_slide, sub=40):
    """Joint in series with the specimen: spring k_j in parallel with a LuGre friction element
    (bristle stiffness sig0, bristle damping sig1, viscous sig2, Coulomb level Fc, no Stribeck).
    Torque-driven: T = k_j u + sig0 z + sig1 dz/dt + sig2 du/dt, dz/dt = du/dt - sig0 |du/dt| z / Fc.
    Returns the joint deflection u (rad)."""
    sig1 = sig0 * tau_bristle
    sig2 = k_j * tau_slide
    u = 0.0
    z = 0.0
    out = np.empty_like(T)
    out[0] = 0.0
    for i in range(1, len(T)):
        dt = (t[i] - t[i - 1]) / sub
        for k in range(sub):
            Ti = T[i - 1] + (T[i] - T[i - 1]) * (k + 1) / sub
            R = Ti - k_j * u - sig0 * z
            s = np.sign(R)
            g = 1.0 - sig0 * s * z / Fc
            ud = R / (sig1 * g + sig2)
            zd = ud - sig0 * abs(ud) * z / Fc
            u += ud * dt
            z += zd * dt
        out[i] = u
    return out


def maxwell_slip(T, K, k, f):
    """Generalised Maxwell-slip: K phi + sum_i F_i = T, element i a spring k_i with a Coulomb slider f_i
    (F_i = k_i (phi - s_i) clipped to +-f_i, the slider s_i following).  Torque-driven by bisection."""
    k = np.asarray(k, float)
    f = np.asarray(f, float)
    s = np.zeros_like(k)
    phi_out = np.empty_like(T)
    phi = 0.0

    def forces(p, s):
        e = p - s
        F = k * e
        slip = np.abs(F) > f
        s_new = np.where(slip, p - np.sign(e) * f / k, s)
        return K * p + np.sum(np.clip(F, -f, f)), s_new

    span = 4 * TFS / K
    for i, Ti in enumerate(T):
        lo, hi = phi - span, phi + span
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            Fm, _ = forces(mid, s)
            if Fm < Ti:
                lo = mid
            else:
                hi = mid
        phi = 0.5 * (lo + hi)
        _, s = forces(phi, s)
        phi_out[i] = phi
    return phi_out


def cubic_twist(T, ratio):
    """twist = c T - d T^3, stiffness at full scale = ratio x the initial one (monotone)."""
    c = 1.0 / K0
    d = c * (1 - 1 / ratio) / (3 * TFS ** 2)
    return c * T - d * T ** 3


def table_twist(T, comp):
    """odd piecewise-linear compliance table: breakpoints 0.1/0.3/0.5/0.7/0.9 FS, 6 slopes."""
    bp = np.array([0.0, 0.1, 0.3, 0.5, 0.7, 0.9, 10.0]) * TFS
    a = np.abs(T)
    tw = np.zeros_like(T)
    for j in range(6):
        seg = np.clip(a - bp[j], 0, bp[j + 1] - bp[j])
        tw += comp[j] / K0 * seg
    return np.sign(T) * tw


def nonlinear_damper(t, T, K, c, alpha, sub=20):
    """Kelvin solid with a power-law damper: T = K phi + c sign(v)|v|^alpha."""
    phi = 0.0
    out = np.empty_like(T)
    out[0] = 0.0
    for i in range(1, len(T)):
        dt = (t[i] - t[i - 1]) / sub
        for k in range(sub):
            Ti = T[i - 1] + (T[i] - T[i - 1]) * (k + 1) / sub
            R = Ti - K * phi
            v = np.sign(R) * (abs(R) / c) ** (1 / alpha)
            # semi-implicit cap: never overshoot the static equilibrium within a substep
            v = np.clip(v, -abs(R) / K / dt, abs(R) / K / dt)
            phi += v * dt
        out[i] = phi
    return out


def play(T, r, y0=0.0):
    """play (backlash) operator of half-width r(t) on the torque."""
    y = np.empty_like(T)
    prev = y0
    for i, Ti in enumerate(T):
        prev = min(max(prev, Ti - r[i]), Ti + r[i])
        y[i] = prev
    return y


def wear_joint(T, growth):
    """Friction joint of three Jenkins elements in series with the specimen (spring k_i, slider f_i),
    u = sum_i play(T, f_i)/k_i, whose slider levels grow with the cycles done (wear):
    f_i = f0_i (1 + growth * cycles).  Loop width at zero torque = 2 sum f_i/k_i."""
    travel = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(T)))]) / (4 * TFS)
    u = np.zeros_like(T)
    for f0, k in zip([0.02, 0.05, 0.1], [3.0, 5.0, 10.0]):
        f = f0 * TFS * (1 + growth * travel)
        u += play(T, f) / (k * K0)
    return u


# ----------------------------------------------------------------------------------------------
# recordings


def header(kind="torsion", specimen="output_shaft", extra=""):
    h = ["[test]", f'kind = "{kind}"', f'specimen = "{specimen}"']
    if extra:
        h.append(extra)
    return "".join(f"# {line}\n" for line in h)


def csv_text(hdr, cols):
    names = list(cols)
    data = np.column_stack([np.asarray(cols[k], float) for k in names])
    lines = [hdr, ",".join(names) + "\n"]
    lines += [",".join(f"{v:.10g}" for v in row) + "\n" for row in data]
    return "".join(lines)


class Rec:
    def __init__(self, name, cls, truth, snr, text, loss=None, primary=None, note=""):
        self.name, self.cls, self.truth, self.snr = name, cls, truth, snr
        self.text, self.loss, self.note = text, loss, note
        self.primary = primary or (truth[0] if truth else None)


def torsion_rec(name, cls, truth, t, T, phi_clean, effect, rng, snr, noise="white", sigma=None,
                loss=None, primary=None, drift=True, extra_cols=None, note="", with_time=True,
                torque_read=None):
    """phi_clean: noise-free twist; effect: list of the effect components (for the SNR, weakest)."""
    if sigma is None:
        peaks = [nuisance_peak(t, T, e) for e in effect]
        sigma = min(peaks) / snr
    n = len(T)
    if noise == "white":
        nz = white(rng, n, sigma)
    elif noise == "pink":
        nz = pink(rng, n, sigma)
    elif noise == "ar1":
        nz = ar1(rng, n, sigma, 0.8)
    else:
        raise ValueError(noise)
    phi = phi_clean + nz
    if drift:
        phi = phi + rng.uniform(-3, 3) * sigma + rng.uniform(-2, 2) * sigma * (t - t[0]) / np.ptp(t)
    cols = {}
    if with_time:
        cols["time_s"] = t
    cols["torque_Nmm"] = T if torque_read is None else torque_read
    cols["twist_rad"] = phi
    if extra_cols:
        cols.update(extra_cols)
    return Rec(name, cls, truth, snr, csv_text(header(), cols), loss=loss, primary=primary, note=note)


def _rng(seed, name):
    """Each recording's own generator, seeded by (seed, its name)."""
    return np.random.default_rng([seed, zlib.crc32(name.encode())])


def _sine_case(seed, name, n_lo, n_hi, cycles, **path):
    """The recording's own generator (seeded by its name), a row count in [n_lo, n_hi), its sine path."""
    rng = _rng(seed, name)
    n = int(rng.integers(n_lo, n_hi))
    t, T = sine_path(n, cycles=cycles, **path)
    return rng, t, T


def _out(snr, nm, t, T, phi, eff, rng, **kw):
    return torsion_rec(nm, "out", [], t, T, phi, [eff], rng, snr, **kw)


def _in_lugre(seed, j, snr):
    """LuGre friction joint in series with the specimen."""
    nm = f"in_lugre_{j}"
    rng = _rng(seed, nm)
    n = int(rng.integers(900, 1600))
    t, T = sine_path(n, cycles=2.6 + 0.2 * rng.random())
    kj = K0 * rng.uniform(3, 6)
    Fc = TFS * rng.uniform(0.15, 0.35)
    u = deslope(T, lugre_joint(t, T, kj, Fc, sig0=40 * K0, tau_bristle=20 / 4000, tau_slide=20 / 300))
    phi = T / K0 + u
    loss = loop_width_last(T, phi)
    return torsion_rec(nm, "in", ["hysteresis"], t, T, phi, [u], rng, snr, loss=loss,
                       note=f"LuGre kj={kj/K0:.1f}K0 Fc={Fc/TFS:.2f}FS")


def _in_maxslip3(seed, j, snr):
    """3-element Maxwell-slip."""
    nm = f"in_maxslip3_{j}"
    rng = _rng(seed, nm)
    n = int(rng.integers(800, 1500))
    t, T = sine_path(n, cycles=2.6 + 0.2 * rng.random(), phase=0.0)
    k = np.array([0.1, 0.25, 0.45]) * K0 * rng.uniform(0.8, 1.2)
    f = np.array([0.012, 0.035, 0.07]) * TFS * rng.uniform(0.8, 1.2)
    Kb = 0.85 * K0
    phi = maxwell_slip(T, Kb, k, f)
    phi = T / K0 + deslope(T, phi)
    eff = phi - T / K0
    loss = loop_width_last(T, phi)
    return torsion_rec(nm, "in", ["hysteresis"], t, T, phi, [eff], rng, snr, loss=loss,
                       note="3-element Maxwell-slip")


def _in_cubic(seed, j, snr):
    """Cubic stiffening."""
    nm = f"in_cubic_{j}"
    rng, t, T = _sine_case(seed, nm, 600, 1400, 2.3, phase=0.0)
    ratio = rng.uniform(1.6, 2.6)
    phi = cubic_twist(T, ratio)
    return torsion_rec(nm, "in", ["nonlinear_stiffness"], t, T, phi, [phi - T / K0], rng, snr,
                       note=f"cubic, K_fs/K_0={ratio:.2f}")


def _in_table5(seed, j, snr):
    """5-breakpoint compliance table."""
    nm = f"in_table5_{j}"
    rng, t, T = _sine_case(seed, nm, 600, 1400, 2.3)
    comp = np.array([1.0, 0.88, 0.74, 0.62, 0.52, 0.46]) * rng.uniform(0.95, 1.05)
    phi = table_twist(T, comp)
    return torsion_rec(nm, "in", ["nonlinear_stiffness"], t, T, phi, [phi - T / K0], rng, snr,
                       note="piecewise-linear compliance, 5 breakpoints")


def _in_smoothdead(seed, j, snr):
    """Smooth (viscous-layer) dead zone."""
    nm = f"in_smoothdead_{j}"
    rng, t, T = _sine_case(seed, nm, 800, 1600, 2.4)
    b = PHI_FS * rng.uniform(0.03, 0.06)
    w = TFS * rng.uniform(0.02, 0.05)
    dz = b * T / np.sqrt(T ** 2 + w ** 2)
    phi = T / K0 + dz
    return torsion_rec(nm, "in", ["lost_motion"], t, T, phi, [dz], rng, snr,
                       note=f"algebraic dead zone b={b/PHI_FS:.3f}phi_fs w={w/TFS:.3f}FS")


def _in_crackramp(seed, j, snr):
    """Crack: compliance rising linearly with |T| on one sign."""
    nm = f"in_crackramp_{j}"
    rng, t, T = _sine_case(seed, nm, 700, 1500, 2.4)
    a = rng.uniform(0.12, 0.25)
    sgn = 1 if j % 2 == 0 else -1
    open_side = (sgn * T) > 0
    ext = np.where(open_side, sgn * a * T ** 2 / (2 * TFS * K0), 0.0)
    phi = T / K0 + ext
    return torsion_rec(nm, "in", ["crack_closure"], t, T, phi, [ext], rng, snr,
                       note=f"crack on {'+' if sgn > 0 else '-'} side, extra compliance a|T|/FS a={a:.2f}")


def _in_cubic_lugre(seed, j, snr):
    """Stiffening + LuGre loop (the weaker effect's SNR)."""
    nm = f"in_cubic_lugre_{j}"
    rng, t, T = _sine_case(seed, nm, 1000, 1700, 2.6)
    ratio = rng.uniform(1.8, 2.4)
    base = cubic_twist(T, ratio)
    u = lugre_joint(t, T, K0 * 5, TFS * rng.uniform(0.2, 0.3), sig0=40 * K0,
                    tau_bristle=20 / 4000, tau_slide=20 / 300)
    u = deslope(T, u)
    phi = base + u
    loss = loop_width_last(T, phi)
    stiff_eff = base - T / K0
    return torsion_rec(nm, "in", ["nonlinear_stiffness", "hysteresis"], t, T, phi,
                       [stiff_eff, u], rng, snr, loss=loss,
                       primary="nonlinear_stiffness" if nuisance_peak(t, T, stiff_eff) >
                       nuisance_peak(t, T, u) else "hysteresis",
                       note=f"cubic ratio {ratio:.2f} + LuGre loop")


def _in_kinematic(seed, j, snr):
    """Kinematic error: 2x, 4x and a weak 6x harmonic of the wave generator angle."""
    nm = f"in_kinematic_{j}"
    rng, t, T = _sine_case(seed, nm, 1500, 2400, 2.2, period_s=60.0)
    revs = rng.uniform(25, 45)
    theta = 2 * np.pi * revs * t / t[-1] + rng.uniform(0, 2 * np.pi)
    a2 = PHI_FS * 0.01
    a6 = 0.04 if j % 2 else 0.0     # a weak 6x (tooth-pitch) harmonic on odd variants only
    rip = a2 * (np.sin(2 * theta + rng.uniform(0, 6.3)) + 0.5 * np.sin(4 * theta + rng.uniform(0, 6.3))
                + a6 * np.sin(6 * theta + 1.0))
    phi = T / K0 + rip
    return torsion_rec(nm, "in", ["kinematic_error"], t, T, phi, [rip], rng, snr,
                       extra_cols={"input_angle_rad": theta},
                       note=f"ripple 2x/4x (+6x at {a6:.2f}) over {revs:.0f} input revolutions")


def _in_ring_plastic(seed, j, snr):
    """Ring: elastic-plastic hinge with linear hardening, elastic unloading, reloading to a higher peak."""
    nm = f"in_ring_plastic_{j}"
    rng = _rng(seed, nm)
    n = int(rng.integers(500, 900))
    peaks = [0.6, 0.85, 1.0]
    Fmax = 110.0
    Fy = rng.uniform(55.0, 75.0)
    H = rng.uniform(0.15, 0.3)  # hardening: tangent stiffness ratio after yield
    # path: 0 -> p1 -> 0 -> p2 -> 0 -> p3 -> 0
    seg = []
    for p in peaks:
        seg += [np.linspace(0, p, n // 6), np.linspace(p, 0, n // 6)]
    F = Fmax * np.concatenate(seg)
    t = np.arange(F.size, dtype=float)
    d = np.empty_like(F)
    Fmx = Fy
    dp = 0.0
    for i, Fi in enumerate(F):
        if Fi > Fmx:
            # plastic increment: beyond the current yield level the extra compliance is (1/H - 1)/KRING
            dp += (Fi - Fmx) * (1 / H - 1) / KRING
            Fmx = Fi
        d[i] = Fi / KRING + dp
    eff = d - F / KRING
    sigma = nuisance_peak(t, F, eff) / snr
    dd = d + white(rng, F.size, sigma) + rng.uniform(-2, 2) * sigma
    txt = csv_text(header("ring_compression", "ewg_ring"), {"force_N": F, "delta_cd_mm": dd})
    return Rec(nm, "in", ["plasticity"], snr, txt, note=f"hinge Fy={Fy:.0f} N, hardening {H:.2f}")


def _out_spike(seed, j, snr):
    """A single spike."""
    nm = f"out_spike_{j}"
    rng = _rng(seed, nm)
    t, T = sine_path(1200, cycles=2.5)
    sig = PHI_FS * 0.003
    phi = T / K0
    i0 = int(rng.integers(300, 900))
    eff = np.zeros_like(T)
    eff[i0] = (40 if j == 0 else 150) * sig * rng.choice([-1, 1])
    r = torsion_rec(nm, "out", [], t, T, phi + eff, None, rng, None, sigma=sig,
                    note=f"single spike of {abs(eff[i0])/sig:.0f} sigma at row {i0}")
    r.snr = abs(eff[i0]) / sig
    return r


def _out_dropout(seed, j, snr):
    """The twist channel stuck for 20 rows on a loading flank."""
    nm = f"out_dropout_{j}"
    rng = _rng(seed, nm)
    t, T = sine_path(1200, cycles=2.5)
    sig = PHI_FS * (0.004 if j == 0 else 0.001)
    rr = torsion_rec(nm, "out", [], t, T, T / K0, None, rng, None, sigma=sig)
    # re-parse the twist column and hold it for 20 rows on a loading flank
    lines = rr.text.splitlines(True)
    hdr_n = sum(1 for ln in lines if ln.startswith("#")) + 1
    i0 = int(rng.integers(200, 900))
    while abs(T[i0]) > 0.6 * TFS:
        i0 += 7
    held = lines[hdr_n + i0].rstrip("\n").split(",")[2]
    for i in range(i0 + 1, i0 + 21):
        parts = lines[hdr_n + i].rstrip("\n").split(",")
        parts[2] = held
        lines[hdr_n + i] = ",".join(parts) + "\n"
    rr.text = "".join(lines)
    rr.snr = float(np.max(np.abs(T[i0:i0 + 21] - T[i0])) / K0 / sig)
    rr.note = f"twist channel stuck 20 rows from row {i0}"
    return rr


def _out_thermal_compliance(seed, j, snr):
    """Compliance warming up."""
    nm = f"out_thermal_compliance_{j}"
    rng = _rng(seed, nm)
    t, T = sine_path(1500, cycles=3.0)
    g = rng.uniform(0.06, 0.1) * (1 - np.exp(-t / (0.4 * t[-1]))) / (1 - np.exp(-2.5))
    phi = T / K0 * (1 + g)
    return _out(snr, nm, t, T, phi, phi - T / K0, rng, note="compliance warming up +6..10 %")


def _out_clamp_slip(seed, j, snr):
    """The clamp slips once."""
    nm = f"out_clamp_slip_{j}"
    rng = _rng(seed, nm)
    t, T = sine_path(1300, cycles=2.5)
    i0 = int(rng.integers(450, 850))
    step = np.zeros_like(T)
    step[i0:] = 0.03 * PHI_FS * np.sign(T[i0] + 1e-9)
    phi = T / K0 + step
    return _out(snr, nm, t, T, phi, step, rng, note=f"clamp slips once at row {i0}")


def _out_clip_pos(seed, j, snr):
    """The twist saturates at +2/3 full scale."""
    nm = f"out_clip_pos_{j}"
    rng = _rng(seed, nm)
    t, T = sine_path(1200, cycles=2.5)
    lin = T / K0
    phi = np.minimum(lin, (2 / 3) * PHI_FS)
    return _out(snr, nm, t, T, phi, phi - lin, rng, note="twist saturates at +2/3 full scale")


def _out_two_rates(seed, j, snr):
    """Power-law damper seen at two rates."""
    nm = f"out_two_rates_{j}"
    rng = _rng(seed, nm)
    n1, n2 = 700, 700
    t1 = np.linspace(0, 2 * 40.0, n1, endpoint=False)
    t2 = t1[-1] + (t1[1] - t1[0]) + np.linspace(0, 2 * 4.0, n2)
    t = np.concatenate([t1, t2])
    T = np.concatenate([TFS * np.sin(2 * np.pi * t1 / 40.0), TFS * np.sin(2 * np.pi * (t2 - t2[0]) / 4.0)])
    T = np.concatenate([T, TFS * np.sin(2 * np.pi * np.linspace(0, 0.25, 60))])
    t = np.concatenate([t, t[-1] + np.linspace(0.01, 1.0, 60)])
    c = 0.05 * TFS * (0.02 * PHI_FS) ** -0.5   # damper torque 5 % FS at 0.02 phi_fs/s
    phi = nonlinear_damper(t, T, K0, c, 0.5)
    return _out(snr, nm, t, T, phi, phi - T / K0, rng, note="power-law damper (alpha 0.5), period 40 s then 4 s")


def _out_wear_loop(seed, j, snr):
    """Friction loop widening with every cycle (wear)."""
    nm = f"out_wear_loop_{j}"
    rng = _rng(seed, nm)
    t, T = sine_path(1600, cycles=4.3)
    u = deslope(T, wear_joint(T, 0.8))
    phi = T / K0 + u
    return _out(snr, nm, t, T, phi, u, rng, note="friction loop widening with every cycle (wear)")


def _out_torque_range(seed, j, snr):
    """Torque channel 5 % high above half load."""
    nm = f"out_torque_range_{j}"
    rng = _rng(seed, nm)
    t, T = sine_path(1200, cycles=2.5)
    Tr = np.where(np.abs(T) > 0.5 * TFS, 1.05 * T, T)
    phi = T / K0
    # effect in the response-vs-read-torque frame
    eff = phi - Tr / K0
    return _out(snr, nm, t, Tr, phi, eff, rng, torque_read=Tr, note="torque channel 5 % high above half load")


def _out_softening(seed, j, snr):
    """Symmetric softening above half load (yield onset)."""
    nm = f"out_softening_{j}"
    rng = _rng(seed, nm)
    t, T = sine_path(1200, cycles=2.5)
    Ty = 0.5 * TFS
    a = np.abs(T)
    ext = np.sign(T) * np.where(a > Ty, 0.6 * (a - Ty) ** 2 / (2 * (TFS - Ty)), 0.0) / K0
    phi = T / K0 + ext
    return _out(snr, nm, t, T, phi, ext, rng, note="symmetric softening above half load (yield onset)")


def _post_hum(rng, t, T, phi, sigma, nm):
    fs = 97.3
    n = T.size
    tt = np.arange(n) / fs
    Tn = TFS * np.sin(2 * np.pi * tt / (n / fs / 2.5))
    ph = Tn / K0 + white(rng, n, sigma) + 0.3 * sigma * np.sin(2 * np.pi * 50.0 * tt + 0.4)
    return Rec(nm, "clean", [], None, csv_text(header(), {"time_s": tt, "torque_Nmm": Tn, "twist_rad": ph}),
               note="50 Hz hum at 0.3 sigma, fs 97.3 Hz")



def _post_quant(rng, t, T, phi, sigma, nm):
    q = 2.5 * sigma
    ph = np.round((phi + white(rng, T.size, sigma) + 0.3 * q) / q) * q
    return Rec(nm, "clean", [], None, csv_text(header(), {"time_s": t, "torque_Nmm": T, "twist_rad": ph}),
               note="quantisation step 2.5 sigma")



def _post_jitter(rng, t, T, phi, sigma, nm):
    n = T.size
    dt = t[1] - t[0]
    ts = t + rng.uniform(-0.4, 0.4, n) * dt          # true sampling instants
    ts = np.maximum.accumulate(ts)
    Tt = TFS * np.sin(2 * np.pi * ts / 20.0)
    ph = Tt / K0 + white(rng, n, sigma) + 2 * sigma * ts / ts[-1]
    return Rec(nm, "clean", [], None, csv_text(header(), {"time_s": ts, "torque_Nmm": Tt, "twist_rad": ph}),
               note="time stamps jittered +-0.4 dt, drift 2 sigma")



def _post_rwalk(rng, t, T, phi, sigma, nm):
    n = T.size
    ph = phi + white(rng, n, sigma) + np.cumsum(white(rng, n, 0.05 * sigma))
    return Rec(nm, "clean", [], None, csv_text(header(), {"time_s": t, "torque_Nmm": T, "twist_rad": ph}),
               note="white + random walk (steps 0.05 sigma)")



def _post_offsets(rng, t, T, phi, sigma, nm):
    n = T.size
    ph = phi + 1e-4 + white(rng, n, sigma) + 8 * sigma * (t / t[-1]) - 3 * sigma
    Tr = T + 0.004 * TFS
    return Rec(nm, "clean", [], None, csv_text(header(), {"torque_Nmm": Tr, "twist_rad": ph, "time_s": t}),
               note="torque offset 0.4 % FS, twist offset, 8-sigma drift; columns reordered")



def _post_ring_clean(rng, t, T, phi, sigma, nm):
    n = T.size
    F = 60.0 * (1 - np.cos(2 * np.pi * np.arange(n) / (n / 3))) / 2
    d = F / KRING * rng.uniform(0.995, 1.005)
    s = 0.004 * 60 / KRING
    dd = d + white(rng, n, s) + 0.01
    return Rec(nm, "clean", [], None, csv_text(header("ring_compression", "ewg_ring"),
                                               {"force_N": F, "delta_cd_mm": dd}), note="ring, white")



def _clean(seed, nm, n, noise, rel, cycles=2.5, phase=0.0, post=None, with_time=True, tq=None):
    rng = _rng(seed, nm)
    t, T = sine_path(n, cycles=cycles, phase=phase)
    sigma = PHI_FS * rel
    phi = T / K0 * rng.uniform(0.995, 1.005)
    r = torsion_rec(nm, "clean", [], t, T, phi, None, rng, None, noise=noise, sigma=sigma,
                    with_time=with_time, torque_read=None if tq is None else tq(T))
    if post is not None:
        r = post(rng, t, T, phi, sigma, nm)
    return r


IN_CASES = (_in_lugre, _in_maxslip3, _in_cubic, _in_table5, _in_smoothdead, _in_crackramp, _in_cubic_lugre,
            _in_kinematic)
OUT_CASES = (_out_spike, _out_dropout, _out_thermal_compliance, _out_clamp_slip, _out_clip_pos, _out_two_rates,
             _out_wear_loop, _out_torque_range, _out_softening)
# clean recordings: (name, rows, noise, noise over full scale, options of _clean)
CLEAN_CASES = (
    ("clean_white_n200", 200, "white", 0.004, dict()),
    ("clean_white_n20000", 20000, "white", 0.01, dict(cycles=4)),
    ("clean_white_n600_lownoise", 600, "white", 0.0005, dict()),
    ("clean_pink_a", 2000, "pink", 0.005, dict()),
    ("clean_pink_b", 5000, "pink", 0.002, dict(cycles=3.5)),
    ("clean_ar1", 1500, "ar1", 0.004, dict()),
    ("clean_gain0.2pct_torque", 1200, "white", 0.003, dict(tq=lambda T: 1.002 * T)),
    ("clean_midcycle_start", 1100, "white", 0.004, dict(phase=1.9, cycles=2.3)),
    ("clean_midcycle_notime", 900, "white", 0.004, dict(phase=4.0, with_time=False)),
    ("clean_mains_hum_a", 2000, "white", 0.004, dict(post=_post_hum)),
    ("clean_mains_hum_b", 8000, "white", 0.002, dict(post=_post_hum)),
    ("clean_quant_coarse_a", 1000, "white", 0.003, dict(post=_post_quant)),
    ("clean_quant_coarse_b", 3000, "white", 0.002, dict(post=_post_quant)),
    ("clean_time_jitter", 1400, "white", 0.004, dict(post=_post_jitter)),
    ("clean_randomwalk", 2500, "white", 0.004, dict(post=_post_rwalk)),
    ("clean_offsets_drift", 1300, "white", 0.003, dict(post=_post_offsets)),
    ("clean_ring_a", 600, "white", 0.004, dict(post=_post_ring_clean)),
    ("clean_ring_b", 1800, "white", 0.004, dict(post=_post_ring_clean)),
)


def build(seed):
    """Every recording, in catalogue then clean then out of catalogue; each draws from its own generator."""
    recs = [case(seed, j, snr) for j, snr in enumerate([2.0, 4.0, 8.0, 25.0]) for case in IN_CASES]
    recs += [_in_ring_plastic(seed, j, snr) for j, snr in enumerate([4.0, 10.0, 30.0])]
    recs += [_clean(seed, nm, n, noise, rel, **kw) for nm, n, noise, rel, kw in CLEAN_CASES]
    recs += [case(seed, j, snr) for j, snr in enumerate([6.0, 25.0]) for case in OUT_CASES]
    return recs


# ----------------------------------------------------------------------------------------------
# running and scoring


def run_diagnose(path, out_json):
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1")
    p = subprocess.run([CLI, "diagnose", "-q", str(path), "--json", str(out_json)],
                       capture_output=True, text=True, env=env, timeout=600)
    if p.returncode != 0 or not Path(out_json).exists():
        # the JSON contract failed: read the text verdict for the record (scored as a MISS anyway)
        q = subprocess.run([CLI, "diagnose", str(path)], capture_output=True, text=True, env=env, timeout=600)
        said = "?"
        for ln in q.stdout.splitlines():
            if ln.strip().startswith("verdict:"):
                said = ln.split(":", 1)[1].strip()
        return {"verdict": f"ERR{p.returncode}", "named": [], "ambiguous": False, "json_error": True,
                "text_verdict": said, "stderr": p.stderr.strip()[-300:]}
    return json.loads(Path(out_json).read_text())


def qval(d, key):
    q = (d.get("quantities") or {}).get(key)
    if isinstance(q, dict):
        return q.get("value")
    return q


def calibrate(tmp):
    """Checks the hard-coded baselines against the CLI (a noiseless linear recording)."""
    t, T = sine_path(300, cycles=2.0)
    p = Path(tmp) / "calib.csv"
    p.write_text(csv_text(header(), {"torque_Nmm": T, "twist_rad": T / K0 + 1e-12 * np.sin(np.arange(300) * 1.7)}))
    d = run_diagnose(p, Path(tmp) / "calib.json")
    for e in d.get("effects", []):
        bs = e.get("parameters", {}).get("baseline_stiffness")
        if bs:
            return bs["value"]
    return None


def score(rec, d):
    v = d.get("verdict")
    named = list(d.get("named") or [])
    amb = bool(d.get("ambiguous"))
    res = {"verdict": v, "named": named, "ambiguous": amb}
    if d.get("json_error"):
        res["json_error"] = True
        res["text_verdict"] = d.get("text_verdict")
        res["stderr"] = d.get("stderr")
    if rec.cls == "in":
        res["primary_ok"] = v == "explained" and rec.primary in named
        res["exact_ok"] = v == "explained" and set(named) == set(rec.truth)
        res["scored"] = rec.snr >= 3
        res["ok"] = res["exact_ok"]
        if rec.loss is not None and "hysteresis" in rec.truth:
            L = qval(d, "hysteresis_loss_arcmin")
            res["loss_reported"] = L
            res["loss_truth"] = rec.loss
            res["loss_ok"] = (L is not None and rec.loss and abs(L - rec.loss) <= 0.1 * abs(rec.loss))
    elif rec.cls == "clean":
        res["scored"] = True
        res["ok"] = v == "agrees"
    else:
        res["scored"] = True
        res["ok"] = v == "unexplained" or (v == "explained" and amb)
        res["confidently_wrong"] = v == "explained" and not amb
    return res


def _run_row(r, tmp, keep):
    """Diagnose one recording, print its line, return its row."""
    path = (keep or Path(tmp)) / f"{r.name}.csv"
    path.write_text(r.text)
    d = run_diagnose(path, Path(tmp) / f"{r.name}.json")
    s = score(r, d)
    tag = ("OK" if s["ok"] else "MISS") if s["scored"] else ("(ok)" if s["ok"] else "(n/s)")
    extra = ""
    if "loss_truth" in s:
        L = s["loss_reported"]
        extra = f"  loss {L if L is None else round(L, 3)} vs {s['loss_truth']:.3f} arcmin" + \
            ("" if s["loss_ok"] else " LOSS-MISS")
    snr = "-" if r.snr is None else f"{r.snr:.1f}"
    print(f"{r.name:28s} {r.cls:5s} {'+'.join(r.truth) or ('clean' if r.cls == 'clean' else 'out-of-cat'):34s} "
          f"{snr:>6s} {s['verdict']:11s} {'+'.join(s['named']) or '-':34s} {'y' if s['ambiguous'] else 'n':3s} "
          f"{tag}{extra}" + (f"  [no JSON: {s['stderr'].splitlines()[-1] if s.get('stderr') else ''}; "
                             f"text says {s.get('text_verdict')}]" if s.get("json_error") else ""), flush=True)
    return {"name": r.name, "class": r.cls, "truth": r.truth, "primary": r.primary, "snr": r.snr,
            "note": r.note, **s,
            "suggestion": (d.get("suggestion") or {}).get("id") if isinstance(d.get("suggestion"), dict)
            else d.get("suggestion"),
            "structure": d.get("structure")}


def _summary(rows):
    """The headline fractions of the scored classes."""
    def pct(xs):
        return f"{100.0 * sum(xs) / len(xs):.0f} % ({sum(xs)}/{len(xs)})" if xs else "n/a"

    ins = [x for x in rows if x["class"] == "in" and x["scored"]]
    cl = [x for x in rows if x["class"] == "clean"]
    oc = [x for x in rows if x["class"] == "out"]
    lo = [x for x in rows if x["class"] == "in" and "loss_ok" in x and x["scored"]]
    return {
        "in_catalogue_primary_named": pct([x["primary_ok"] for x in ins]),
        "in_catalogue_exact_set": pct([x["exact_ok"] for x in ins]),
        "clean_false_alarms": pct([not x["ok"] for x in cl]),
        "out_of_catalogue_flagged": pct([x["ok"] for x in oc]),
        "out_of_catalogue_confidently_wrong": pct([x["confidently_wrong"] for x in oc]),
        "loss_within_10pct": pct([bool(x["loss_ok"]) for x in lo]),
        "diagnose_failed_no_json (all classes)": pct([bool(x.get("json_error")) for x in rows]),
        "in_catalogue_below_snr3_exact (not scored)": pct(
            [x["exact_ok"] for x in rows if x["class"] == "in" and not x["scored"]]),
    }


def _print_misses(rows):
    """The scored recordings the tool missed, with what it said."""
    misses = [x for x in rows if x["scored"] and (not x["ok"] or x.get("loss_ok") is False)]
    if misses:
        print("\nMISSES:")
        for x in misses:
            why = "loss" if x["ok"] else "verdict"
            said = x["verdict"] if not x.get("json_error") else f"{x['verdict']} (text: {x.get('text_verdict')})"
            print(f"  {x['name']:28s} truth={'+'.join(x['truth']) or x['class']} said={said} "
                  f"{'+'.join(x['named'])} amb={x['ambiguous']} ({why}) [{x['note']}]")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", help="directory for heldout3_diagnose.json")
    ap.add_argument("--only", help="comma-separated recording names")
    ap.add_argument("--keep", help="write the generated CSVs into this directory")
    ap.add_argument("--list", action="store_true", help="list the recordings and exit")
    a = ap.parse_args(argv)

    recs = build(a.seed)
    if a.list:
        for r in recs:
            print(r.name, r.cls, r.truth, r.note)
        return 0
    if a.only:
        want = set(a.only.split(","))
        recs = [r for r in recs if r.name in want]
        if not recs:
            print("no recording matches --only", file=sys.stderr)
            return 2
    tmp = tempfile.mkdtemp(prefix="heldout3_")
    if not a.only:
        kb = calibrate(tmp)
        if kb is not None and abs(kb / K0 - 1) > 1e-3:
            print(f"warning: CLI baseline {kb:.6g} differs from K0 = {K0:.6g}", file=sys.stderr)
    keep = Path(a.keep) if a.keep else None
    if keep:
        keep.mkdir(parents=True, exist_ok=True)
    t0 = time.time()
    hdr = f"{'name':28s} {'class':5s} {'truth':34s} {'SNR':>6s} {'verdict':11s} {'named':34s} {'amb':3s} result"
    print(hdr)
    print("-" * len(hdr))
    rows = [_run_row(r, tmp, keep) for r in recs]
    summary = _summary(rows)
    print()
    print(f"seed {a.seed}, {len(rows)} recordings, {time.time() - t0:.0f} s")
    for k, v in summary.items():
        print(f"  {k:45s} {v}")
    _print_misses(rows)
    if a.out:
        od = Path(a.out)
        od.mkdir(parents=True, exist_ok=True)
        (od / "heldout3_diagnose.json").write_text(json.dumps({"seed": a.seed, "summary": summary,
                                                                "rows": rows}, indent=1, default=str))
    return 0


if __name__ == "__main__":
    sys.exit(main())
