#!/usr/bin/env python
"""Held-out, black-box benchmark of `strainwave diagnose`.

Written independently of compare/ (the model and its own generators are not read or imported).
Recordings come from physics written here: torque-driven Bouc-Wen and twist-driven Maxwell-slip
friction (both dissipative), smooth/power-law/CHA-table stiffening, smooth backlash with Hertz-like
flanks, a crack open on one torque sign, kinematic error from the wave-generator angle, Roark thick
rings, a softening ring at large deflection, an elastic-plastic ring with permanent set; and physics
outside the catalogue (warm-up drift, thermal stiffness drift, gain step, ripple in time, channel lag,
Zener viscoelasticity at two rates, log creep at a hold, clipping, torque saturation, spliced specimens).
Noise: white, AR(1) up to rho 0.95, moving average, quantisation.

Each recording is diagnosed through the CLI (subprocess), one at a time. Prints a table and summaries.

    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/heldout_diagnose.py [--out DIR] [--only SUBSTR]
"""
from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from load_paths import ramp_path  # noqa: E402

ROOT = os.path.dirname(HERE)
CLI = os.path.join(ROOT, ".venv", "bin", "strainwave")
if not os.path.exists(CLI):
    CLI = shutil.which("strainwave") or "strainwave"

# scale of the default gear: published seed-000 K_HD (strainwave analytic --json, lambda_sum.published)
K0 = 6.18e8          # N*mm/rad
TR = 1.0e6           # N*mm, rated output torque of the default parameter file
PHI_FS = TR / K0     # full-scale twist, 1.6e-3 rad
SIG = 3e-6           # default encoder noise, rad (~0.6 arcsec, 0.2 % of full scale)
E_MOD = 2.1e5
RING_B = 12.0
RING_T = 0.012 * 72.0

ARCMIN = math.pi / (180 * 60)


# ---------------------------------------------------------------- load histories
def hist_full(n=2400, amp=1.0, cycles=3):
    pts = [0.0]
    for _ in range(cycles):
        pts += [amp, -amp]
    pts += [0.0]
    return ramp_path(pts, n)


def hist_onesided(n=2000, amp=1.0, cycles=4):
    pts = [0.0]
    for _ in range(cycles):
        pts += [amp, 0.0]
    return ramp_path(pts, n)


def hist_growing(n=2400):
    return ramp_path([0, .4, -.4, .7, -.7, 1, -1, 1, -1, 0], n)


def hist_tworate(n_slow=1600, n_fast=400):
    """2 slow full cycles then 2 fast ones at a constant sampling rate (fast = 4x the rate)."""
    a = ramp_path([0, 1, -1, 1, -1, 0], n_slow)
    b = ramp_path([0, 1, -1, 1, -1, 0], n_fast)
    return np.concatenate([a, b[1:]])


def hist_hold(n=2400):
    """0 -> +1, hold, -> -1, hold, -> 0 (holds take 25 % of the samples each)."""
    up = np.linspace(0, 1, 400)
    h1 = np.ones(600)
    dn = np.linspace(1, -1, 400)
    h2 = -np.ones(600)
    back = np.linspace(-1, 0, 400)
    return np.concatenate([up, h1, dn, h2, back])[:n]


# ---------------------------------------------------------------- noise
def noise(rng, n, kind="white", sigma=SIG, rho=0.0, q=0.0, ma=0):
    if kind == "white":
        e = rng.normal(0, sigma, n)
    elif kind == "ar1":
        w = rng.normal(0, sigma * math.sqrt(1 - rho ** 2), n)
        e = np.empty(n)
        e[0] = rng.normal(0, sigma)
        for i in range(1, n):
            e[i] = rho * e[i - 1] + w[i]
        e += rng.normal(0, 0.3 * sigma, n)      # a white floor under the coloured part
    elif kind == "ma":
        w = rng.normal(0, sigma * math.sqrt(ma), n + ma)
        e = np.convolve(w, np.ones(ma) / ma, "valid")[:n]
    else:
        raise ValueError(kind)
    return e


def quantise(x, q):
    return np.round(x / q) * q if q > 0 else x


# ---------------------------------------------------------------- torsion physics (twist from torque)
def bouc_wen_torque_driven(T, Ke, A, zs, sub=20):
    """T = Ke*phi + z, dz = A dphi (1 - (0.5 sgn(dphi z) + 0.5) |z/zs|). Dissipative (z opposes motion)."""
    return slip_torque_loop(T, Ke, A, lambda i, dT: zs, sub)


def slip_torque_loop(T, Ke, A, slip_torque, sub=20):
    """Torque-driven friction element with a slip torque that may depend on the step i and the loading
    direction (slip_torque(i, dT)): a stick spring A in parallel with the elastic path, whose force z
    saturates at the slip torque while loading in z's direction (dissipative, non-Masing if direction-dependent)."""
    ph = np.zeros_like(T)
    p_, z_ = 0.0, 0.0
    for i in range(1, len(T)):
        dT = (T[i] - T[i - 1]) / sub
        for _ in range(sub):
            zs_ = slip_torque(i, dT)
            sg = 1.0 if dT * z_ > 0 else 0.0
            gg = max(0.0, 1 - sg * abs(z_ / zs_))
            dp = dT / (Ke + A * gg)
            p_ += dp
            z_ += A * gg * dp
        ph[i] = p_
    return ph


def maxwell_slip_twist_driven(phi, Ke, k, f):
    """Generalised Maxwell slip: T = Ke phi + sum F_i, F_i = clip(F_i + k_i dphi, -f_i, f_i)."""
    F = np.zeros(len(k))
    T = np.zeros_like(phi)
    for i in range(1, len(phi)):
        F = np.clip(F + k * (phi[i] - phi[i - 1]), -f, f)
        T[i] = Ke * phi[i] + F.sum()
    return T


def loop_truth(T, phi):
    """True dissipated energy of the last full cycle (closed integral T dphi) and loop width at T=0."""
    Tn = T / np.max(np.abs(T))
    # last full cycle: last +1 peak to the +1 peak before it
    peaks = np.where((Tn[1:-1] >= Tn[:-2]) & (Tn[1:-1] > Tn[2:]) & (Tn[1:-1] > 0.95))[0] + 1
    if len(peaks) < 2:
        return float("nan"), float("nan")
    a, b = peaks[-2], peaks[-1]
    Tc, pc = T[a:b + 1], phi[a:b + 1]
    energy = float(np.sum(0.5 * (Tc[1:] + Tc[:-1]) * np.diff(pc)))
    # zero crossings: descending (unloading from +) and ascending (loading)
    w_unl, w_ld = None, None
    for j in range(len(Tc) - 1):
        if Tc[j] > 0 >= Tc[j + 1] and w_unl is None:
            w_unl = pc[j] + (pc[j + 1] - pc[j]) * Tc[j] / (Tc[j] - Tc[j + 1])
        if Tc[j] < 0 <= Tc[j + 1] and w_ld is None:
            w_ld = pc[j] + (pc[j + 1] - pc[j]) * (-Tc[j]) / (Tc[j + 1] - Tc[j])
    width = (w_unl - w_ld) if (w_unl is not None and w_ld is not None) else float("nan")
    return energy, float(width)


def zener(Tz, tz, K1z, K2z, tau):
    """Standard linear solid in compliance form: phi = T/K1 + phi_v, dphi_v/dt = (T/K2 - phi_v)/tau."""
    pv = np.zeros_like(Tz)
    for i in range(1, len(Tz)):
        h = tz[i] - tz[i - 1]
        a = math.exp(-h / tau)
        pv[i] = a * pv[i - 1] + (1 - a) * Tz[i] / K2z
    return Tz / K1z + pv


def cha_three_slope(T, K1, K2, K3, T1, T2):
    a = np.abs(T)
    phi = np.where(a <= T1, a / K1,
                   np.where(a <= T2, T1 / K1 + (a - T1) / K2, T1 / K1 + (T2 - T1) / K2 + (a - T2) / K3))
    return np.sign(T) * phi


def softplus(x, w):
    return w * np.logaddexp(0, x / w)


# ---------------------------------------------------------------- recording writer
def write_rec(path, kind, specimen, cols, header_extra=None, params=None, desc=""):
    lines = ["[test]", f'kind = "{kind}"', f'specimen = "{specimen}"']
    for k, v in (header_extra or {}).items():
        lines.append(f"{k} = {v!r}" if not isinstance(v, str) else f'{k} = "{v}"')
    if desc:
        lines.append(f'description = "{desc}"')
    for sec, kv in (params or {}).items():
        lines.append(f"[params.{sec}]")
        for k, v in kv.items():
            lines.append(f"{k} = {v!r}")
    names = list(cols)
    data = np.column_stack([np.asarray(cols[c], float) for c in names])
    with open(path, "w") as fh:
        for ln in lines:
            fh.write("# " + ln + "\n")
        fh.write(",".join(names) + "\n")
        for row in data:
            fh.write(",".join(f"{v:.10g}" for v in row) + "\n")


def run_diag(path):
    out = path[:-4] + ".json"
    t0 = time.time()
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    p = subprocess.run([CLI, "diagnose", path, "--json", out], capture_output=True, text=True, env=env,
                       timeout=300)
    dt = time.time() - t0
    if p.returncode != 0 or not os.path.exists(out):
        return {"_error": (p.stderr.strip().splitlines() or ["?"])[-1], "_rc": p.returncode}, dt
    with open(out) as fh:
        return json.load(fh), dt


# ---------------------------------------------------------------- cases
class _Cases:
    """The generator every torsion family draws from in turn, and the cases so far."""

    def __init__(self, rng):
        self.rng, self.C = rng, []
        self.base_hdr = {"baseline_stiffness_Nmm_per_rad": K0, "baseline_uncertainty": 0.05}

    def tors(self, name, cat, exp, T, phi, hdr=None, t=None, extra=None, truth=None, specimen="gear", nz=None):
        n = len(T)
        nz = nz if nz is not None else noise(self.rng, n)
        cols = {"torque_Nmm": T}
        if t is not None:
            cols["time_s"] = t
        cols["twist_rad"] = phi + nz
        if extra:
            cols.update(extra)
        self.C.append(dict(name=name, cat=cat, exp=exp, kind="torsion", specimen=specimen, cols=cols,
                           hdr=self.base_hdr if hdr is None else hdr, truth=truth or {}))


def _shared(*names):
    """The paths and effect sizes several torsion families share (no random draws), by name."""
    dt = 0.01
    T = TR * hist_full()
    th = np.linspace(0, 12 * 2 * np.pi, len(T))
    s = dict(dt=dt, T=T, t=np.arange(len(T)) * dt, To=TR * hist_onesided(), Tg=TR * hist_growing(),
             K1=K0, K3=2.0 * K0, T0=0.25 * TR,
             b=4e-5, wb=0.03 * TR,   # +-4e-5 rad (8 arcsec) band, 3 % of rated torque
             dC=0.15 / K0, th=th,
             ke=1.5e-5 * np.sin(2 * th + 0.4) + 0.6e-5 * np.sin(4 * th + 1.1))   # 3 + 1.2 arcsec
    return tuple(s[n] for n in names) if len(names) > 1 else s[names[0]]


def _torsion_clean(cases):
    """Clean torsion: white, AR(1), MA, quantised, drift, within the prior, one-sided, growing."""
    tors, rng = cases.tors, cases.rng
    dt, T, t, To, Tg = _shared("dt", "T", "t", "To", "Tg")
    tors("clean_white", "clean", set(), T, T / K0, t=t)
    tors("clean_white_big", "clean", set(), T, T / K0, t=t, nz=noise(rng, len(T), sigma=2e-5))
    for rho in (0.5, 0.9, 0.95):
        tors(f"clean_ar1_{rho}", "clean", set(), T, T / K0, t=t,
             nz=noise(rng, len(T), "ar1", sigma=SIG, rho=rho))
    tors("clean_ma15", "clean", set(), T, T / K0, t=t, nz=noise(rng, len(T), "ma", ma=15))
    tors("clean_quant", "clean", set(), T, T / K0, t=t,
         nz=quantise(T / K0 + noise(rng, len(T), sigma=1.5e-6), 6e-6) - T / K0)   # 2^20 count encoder
    tors("clean_drift_offset", "clean", set(), T, T / K0 + 4e-5 + 2e-5 * t / t[-1], t=t)
    tors("clean_stiff_in_prior", "clean", set(), T, T / (K0 * 1.03), t=t)
    tors("clean_onesided", "clean", set(), To, To / K0, t=np.arange(len(To)) * dt)
    tors("clean_growing", "clean", set(), Tg, Tg / K0, t=np.arange(len(Tg)) * dt)


def _torsion_stiffness(cases):
    """Non-linear stiffness (smooth; no knees) and rows of the CHA table."""
    tors, rng = cases.tors, cases.rng
    dt, T, t, To, K1, K3, T0 = _shared("dt", "T", "t", "To", "K1", "K3", "T0")
    phi = T / K3 + (1 / K1 - 1 / K3) * T0 * np.tanh(T / T0)
    tors("stiff_tanh", "in", {"nonlinear_stiffness"}, T, phi, t=t)
    phi = (T / K0) / np.sqrt(1 + np.abs(T) / (0.5 * TR))
    tors("stiff_powerlaw", "in", {"nonlinear_stiffness"}, T, phi, t=t,
         hdr={"baseline_stiffness_Nmm_per_rad": K0, "baseline_uncertainty": 0.3})
    phi = To / (1.4 * K0) + (1 / K0 - 1 / (1.4 * K0)) * 0.3 * TR * np.tanh(To / (0.3 * TR))
    tors("stiff_tanh_onesided_weak", "in", {"nonlinear_stiffness"}, To, phi, t=np.arange(len(To)) * dt)
    # CHA table rows, scaled like the catalogue: T_rated = 1.5 T2, user-given K1, uncertainty 0.3
    with open("/work/shared/data/cha_torsional_stiffness.csv") as fh:
        ln = [x.strip().split(",") for x in fh if x.strip() and not x.startswith("#")]
    cha = [dict(zip(ln[0], [v if k == "ratio" else float(v) for k, v in zip(ln[0], r)])) for r in ln[1:]]
    for row in [cha[10], cha[13], cha[1]]:
        Kk1, Kk2, Kk3 = (row["K1_e3"] * 1e6, row["K2_e3"] * 1e6, row["K3_e3"] * 1e6)   # N*mm/rad
        T1, T2 = row["T1_Nm"] * 1e3, row["T2_Nm"] * 1e3
        Tr = 1.5 * T2
        Tc = Tr * hist_full(2000)
        phic = cha_three_slope(Tc, Kk1, Kk2, Kk3, T1, T2)
        s = 0.002 * np.max(np.abs(phic))
        lbl = f"cha{int(row['size'])}_{row['ratio'].replace('>', 'gt')}"
        tors(lbl, "in", {"nonlinear_stiffness"}, Tc, phic, t=np.arange(len(Tc)) * dt,
             hdr={"baseline_stiffness_Nmm_per_rad": Kk1, "baseline_uncertainty": 0.3},
             nz=noise(rng, len(Tc), sigma=s), specimen="gear")
        if row["size"] == 25:
            # with a Bouc-Wen friction loop: z_s = 3 % of rated torque
            # series: twist = elastic CHA curve + friction slip (torque-driven Bouc-Wen with a soft spring)
            zs = 0.03 * Tr
            ph = phic + bouc_wen_torque_driven(Tc, 3.0 * Kk1, 6 * Kk1, zs) - Tc / (3.0 * Kk1)
            e, w = loop_truth(Tc, ph)
            tors(lbl + "_loop", "in", {"nonlinear_stiffness", "hysteresis"}, Tc, ph,
                 t=np.arange(len(Tc)) * dt, hdr={"baseline_stiffness_Nmm_per_rad": Kk1, "baseline_uncertainty": 0.3},
                 nz=noise(rng, len(Tc), sigma=s), truth={"energy": e, "width": w})


def _torsion_single_effects(cases):
    """Hysteresis, lost motion, crack, compliance offset and kinematic error."""
    tors, rng = cases.tors, cases.rng
    dt, T, t, Tg, b, wb, dC, th, ke = _shared("dt", "T", "t", "Tg", "b", "wb", "dC", "th", "ke")
    for zs_frac, nm, nzk in [(0.05, "hyst_boucwen", "white"), (0.015, "hyst_boucwen_small", "white"),
                             (0.04, "hyst_boucwen_ar95", "ar1")]:
        ph = bouc_wen_torque_driven(T, K0, 3 * K0, zs_frac * TR)
        e, w = loop_truth(T, ph)
        nz = noise(rng, len(T), nzk, sigma=SIG, rho=0.95)
        tors(nm, "in", {"hysteresis"}, T, ph, t=t, truth={"energy": e, "width": w}, nz=nz)
    # Maxwell-slip driven in twist (rig in angle control), growing amplitude
    k = np.full(10, 0.4 * K0)
    f = TR * np.linspace(0.002, 0.012, 10)
    ph_path = (TR - f.sum()) / K0 * hist_growing()
    Tm = maxwell_slip_twist_driven(ph_path, K0, k, f)
    e, w = loop_truth(Tm, ph_path)
    tors("hyst_maxwell_slip", "in", {"hysteresis"}, Tm, ph_path, t=np.arange(len(Tm)) * dt,
         truth={"energy": e, "width": w})
    # ---------------- lost motion (smooth backlash)
    tors("backlash_algebraic", "in", {"lost_motion"}, T, T / K0 + b * T / np.sqrt(T ** 2 + wb ** 2), t=t)
    Tc0 = 0.05 * TR
    x = T - Tc0
    tors("backlash_hertz_offcentre", "in", {"lost_motion"}, T,
         T / K0 + np.sign(x) * b * (1 - np.exp(-np.abs(x) / (0.02 * TR))) +
         np.sign(x) * (np.abs(x) / TR) ** (2 / 3) * 0.05 * PHI_FS, t=t)
    # ---------------- crack (open for one sign)
    tors("crack_pos", "in", {"crack_closure"}, T, T / K0 + dC * softplus(T, 0.05 * TR), t=t,
         truth={"crack_side": "+"})
    tors("crack_neg_gradual", "in", {"crack_closure"}, T, T / K0 - 0.2 / K0 * softplus(-T, 0.15 * TR), t=t,
         truth={"crack_side": "-"})
    tors("crack_pos_ar", "in", {"crack_closure"}, T, T / K0 + dC * softplus(T, 0.05 * TR), t=t,
         nz=noise(rng, len(T), "ar1", sigma=SIG, rho=0.9), truth={"crack_side": "+"})
    # ---------------- compliance offset
    tors("compliance_soft20", "in", {"compliance_offset"}, T, T / (K0 / 1.2), t=t)
    tors("compliance_stiff15", "in", {"compliance_offset"}, Tg, Tg / (K0 * 1.15), t=np.arange(len(Tg)) * dt)
    # ---------------- kinematic error (rotating test: wave generator angle, ratio 100)
    tors("kinematic_error", "in", {"kinematic_error"}, T, T / K0 + ke, t=t, extra={"input_angle_rad": th})


def _torsion_pairs_and_weak(cases):
    """Pairs, the analytic baseline and harder (weak, coloured) in-catalogue cases."""
    tors, rng = cases.tors, cases.rng
    dt, T, t, To, K1, K3, T0, b, wb, dC, th, ke = _shared("dt", "T", "t", "To", "K1", "K3", "T0", "b", "wb", "dC",
                                                          "th", "ke")
    ph = bouc_wen_torque_driven(T, K0, 3 * K0, 0.03 * TR) + dC * softplus(T, 0.05 * TR)
    e, w = loop_truth(T, ph)
    tors("pair_crack_hyst", "in", {"crack_closure", "hysteresis"}, T, ph, t=t,
         truth={"crack_side": "+", "energy": e, "width": w})
    ph = T / K3 + (1 / K1 - 1 / K3) * T0 * np.tanh(T / T0) + b * T / np.sqrt(T ** 2 + wb ** 2)
    tors("pair_stiff_backlash", "in", {"nonlinear_stiffness", "lost_motion"}, T, ph, t=t)
    # ---------------- default analytic baseline (no user stiffness), gear, uncertainty 0.3, true K 10 % off
    tors("clean_gear_analytic_baseline", "clean", set(), T, T / (K0 * 1.1), t=t,
         hdr={"baseline_uncertainty": 0.3})
    # ---------------- harder in-catalogue cases
    ph = bouc_wen_torque_driven(T, K0, 3 * K0, 0.004 * TR)
    e, w = loop_truth(T, ph)
    tors("hyst_boucwen_weak_snr4", "in", {"hysteresis"}, T, ph, t=t, truth={"energy": e, "width": w})
    ph = bouc_wen_torque_driven(T, K0, 3 * K0, 0.03 * TR)
    e, w = loop_truth(T, ph)
    tors("hyst_boucwen_ar90", "in", {"hysteresis"}, T, ph, t=t, truth={"energy": e, "width": w},
         nz=noise(rng, len(T), "ar1", sigma=SIG, rho=0.9))
    tors("hyst_boucwen_onesided", "in", {"hysteresis"}, To, bouc_wen_torque_driven(To, K0, 3 * K0, 0.03 * TR),
         t=np.arange(len(To)) * dt)
    phi = T / (1.15 * K0) + (1 / K0 - 1 / (1.15 * K0)) * 0.3 * TR * np.tanh(T / (0.3 * TR))
    tors("stiff_weak_15pct", "in", {"nonlinear_stiffness"}, T, phi, t=t)
    tors("backlash_small_snr3", "in", {"lost_motion"}, T, T / K0 + 1e-5 * T / np.sqrt(T ** 2 + wb ** 2), t=t)
    ph = (bouc_wen_torque_driven(T, K0, 3 * K0, 0.02 * TR) + b * T / np.sqrt(T ** 2 + wb ** 2))
    e, w = loop_truth(T, ph)
    tors("pair_backlash_friction", "in", {"lost_motion", "hysteresis"}, T, ph, t=t,
         truth={"energy": e, "width": w})
    tors("crack_small_4pct", "in", {"crack_closure"}, T, T / K0 + 0.04 / K0 * softplus(T, 0.03 * TR), t=t,
         truth={"crack_side": "+"})
    tors("kinematic_error_ar90", "in", {"kinematic_error"}, T, T / K0 + ke, t=t, extra={"input_angle_rad": th},
         nz=noise(rng, len(T), "ar1", sigma=SIG, rho=0.9))


def _torsion_harder(cases):
    """The output shaft, quantised AR(1), asymmetric friction, more pairs, a long recording."""
    tors, rng = cases.tors, cases.rng
    dt, T, t, To, K1, K3, T0, b, wb, dC = _shared("dt", "T", "t", "To", "K1", "K3", "T0", "b", "wb", "dC")
    # output shaft, analytic baseline (doc formula, G = E/2(1+nu)), clean
    G = E_MOD / 2.6
    Ks = math.pi * G * (70.0 ** 4 - 45.0 ** 4) / (32 * 200.0)
    Tsh = 0.8e6 * hist_full()
    tors("clean_output_shaft_analytic", "clean", set(), Tsh, Tsh / Ks, t=t, hdr={}, specimen="output_shaft")
    tors("clean_ar95_quant_onesided", "clean", set(), To, To / K0, t=np.arange(len(To)) * dt,
         nz=quantise(To / K0 + noise(rng, len(To), "ar1", sigma=SIG, rho=0.95), 6e-6) - To / K0)
    ph = bouc_wen_torque_driven(T, K0, 3 * K0, 0.002 * TR)
    e, w = loop_truth(T, ph)
    tors("hyst_boucwen_weak_snr2", "in", {"hysteresis"}, T, ph, t=t, truth={"energy": e, "width": w})
    # direction-dependent friction: slip torque 4 % loading in +, 1.5 % in - (non-Masing, still dissipative)
    ph = slip_torque_loop(T, K0, 3 * K0, lambda i, dT: 0.04 * TR if dT > 0 else 0.015 * TR)
    e, w = loop_truth(T, ph)
    tors("hyst_direction_asym", "in", {"hysteresis"}, T, ph, t=t, truth={"energy": e, "width": w})
    phi = T / K3 + (1 / K1 - 1 / K3) * T0 * np.tanh(T / T0)
    tors("stiff_tanh_ar95", "in", {"nonlinear_stiffness"}, T, phi, t=t,
         nz=noise(rng, len(T), "ar1", sigma=SIG, rho=0.95))
    tors("crack_pos_ar95", "in", {"crack_closure"}, T, T / K0 + dC * softplus(T, 0.05 * TR), t=t,
         nz=noise(rng, len(T), "ar1", sigma=SIG, rho=0.95), truth={"crack_side": "+"})
    phi = T / K3 + (1 / K1 - 1 / K3) * T0 * np.tanh(T / T0) + dC * softplus(T, 0.05 * TR)
    tors("pair_stiff_crack", "in", {"nonlinear_stiffness", "crack_closure"}, T, phi, t=t,
         truth={"crack_side": "+"})
    x = T + 0.04 * TR
    tors("backlash_offcentre_pure", "in", {"lost_motion"}, T, T / K0 + b * x / np.sqrt(x ** 2 + wb ** 2), t=t)
    # torque channel noise (errors in variables) on a clean specimen
    tors("clean_torque_channel_noise", "clean", set(), T + rng.normal(0, 0.003 * TR, len(T)), T / K0, t=t)
    # a long recording (6000 rows, strided by the tool) with a friction loop
    T6 = TR * hist_full(6000)
    ph = bouc_wen_torque_driven(T6, K0, 3 * K0, 0.02 * TR, sub=8)
    e, w = loop_truth(T6, ph)
    tors("hyst_boucwen_6000rows", "in", {"hysteresis"}, T6, ph, t=np.arange(len(T6)) * 0.004,
         truth={"energy": e, "width": w})


def _torsion_ooc_harder(cases):
    """Harder out-of-catalogue cases: softening, lags, saturation, growing damage."""
    tors, rng = cases.tors, cases.rng
    dt, T, t, To = _shared("dt", "T", "t", "To")
    tors("ooc_softening_clamp", "out", None, T, T / K0 * (1 + 0.3 * (T / TR) ** 2), t=t)
    tors("ooc_even_sensor_nonlin", "out", None, T, T / K0 + 3e-5 * (T / TR) ** 2, t=t)
    phl1 = np.concatenate([np.zeros(5), (T / K0)[:-5]])
    tors("ooc_channel_lag_onerate", "out", None, T, phl1, t=t)
    tors("ooc_zener_onerate", "out", None, T, zener(T, t, 1.15 * K0, 1.15 * K0 / 0.15, 1.5), t=t)
    tors("ooc_torque_saturation_onesided", "out", None, np.minimum(To, 0.9 * TR), To / K0,
         t=np.arange(len(To)) * dt)
    # friction that grows during the test (wear-in / lubricant squeezed out): slip torque 2 % -> 5 %
    ph = slip_torque_loop(T, K0, 3 * K0, lambda i, dT: TR * (0.02 + 0.03 * i / len(T)))
    tors("ooc_friction_growing", "out", None, T, ph, t=t)
    # a crack that grows during the test: open-side extra compliance 5 % -> 25 %
    tors("ooc_crack_growing", "out", None, T, T / K0 + (0.05 + 0.20 * t / t[-1]) / K0 * softplus(T, 0.05 * TR),
         t=t)
    tors("ooc_gain_drift_linear", "out", None, T * (1 - 0.07 * t / t[-1]), T / K0, t=t)


def _torsion_ooc(cases):
    """Out of catalogue: drifts, gain steps, lags, creep, clipping, splices, stick-slip."""
    tors, rng = cases.tors, cases.rng
    dt, T, t = _shared("dt", "T", "t")
    tors("ooc_warmup_drift", "out", None, T, T / K0 + 2.5e-4 * (1 - np.exp(-t / (0.3 * t[-1]))), t=t)
    Kt = K0 * (1 - 0.10 * (1 - np.exp(-t / (0.4 * t[-1]))))
    tors("ooc_thermal_stiffness_drift", "out", None, T, T / Kt, t=t)
    g = np.where(t < t[-1] / 2, 1.0, 0.92)    # torque channel range switch mid-test: recorded torque x g
    tors("ooc_gain_step", "out", None, T * g, T / K0, t=t)
    tors("ooc_ripple_time", "out", None, T, T / K0 + 2.5e-5 * np.sin(2 * np.pi * t / 0.37), t=t)
    Tt = TR * hist_tworate()
    tt = np.arange(len(Tt)) * dt
    lag = 5
    phl = np.concatenate([np.zeros(lag), (Tt / K0)[:-lag]])
    tors("ooc_channel_lag_tworate", "out", None, Tt, phl, t=tt)
    # Zener: phi = T/K_inf... standard linear solid in compliance form: phi = T/K1 + phi_v,
    # dphi_v/dt = (T/K2 - phi_v)/tau
    phz = zener(Tt, tt, 1.15 * K0, 1.15 * K0 / 0.15, 1.5)   # long-term compliance 1/K0
    tors("ooc_zener_tworate", "out", None, Tt, phz, t=tt)
    Th = TR * hist_hold()
    th_ = np.arange(len(Th)) * dt
    # log creep under each hold: grows with time at constant load, recovers at the load change
    cr = np.zeros_like(Th)
    start, sgn = None, 0
    for i in range(len(Th)):
        s = 1 if Th[i] > 0.999 * TR else (-1 if Th[i] < -0.999 * TR else 0)
        if s != 0 and s != sgn:
            start, sgn = th_[i], s
        if s == 0 and sgn != 0:
            sgn, start = 0, None
        cr[i] = s * 3e-5 * math.log1p((th_[i] - start) / 0.2) if s != 0 else 0.0
    # keep creep as a viscous state: decays exponentially after the hold (recovery)
    for i in range(1, len(cr)):
        if Th[i] != Th[i - 1] and abs(Th[i]) < 0.999 * TR:
            cr[i] = cr[i - 1] * math.exp(-dt / 0.5)
    tors("ooc_creep_hold", "out", None, Th, Th / K0 + cr, t=th_)
    phc = np.clip(T / K0, -0.85 * PHI_FS, 0.85 * PHI_FS)
    tors("ooc_twist_clipping", "out", None, T, phc, t=t)
    tors("ooc_torque_saturation", "out", None, np.clip(T, -0.9 * TR, 0.9 * TR), T / K0, t=t)
    Ks = np.where(t < t[-1] / 2, K0, 0.85 * K0)
    tors("ooc_spliced_specimens", "out", None, T, T / Ks + np.where(t < t[-1] / 2, 0, 3e-5), t=t)
    # stick-slip: twist advances in steps (the friction of the fixture releases every ~4 % of FS)
    step = 0.04 * PHI_FS
    tors("ooc_stick_slip_steps", "out", None, T, step * np.round(T / K0 / step) * 0.5 + 0.5 * T / K0, t=t)


TORSION_FAMILIES = (_torsion_clean, _torsion_stiffness, _torsion_single_effects, _torsion_pairs_and_weak,
                    _torsion_harder, _torsion_ooc_harder, _torsion_ooc)


def torsion_cases(rng):
    """The torsion cases (dicts: name, cat, exp, kind, specimen, cols, hdr, truth), family by family."""
    cases = _Cases(rng)
    for family in TORSION_FAMILIES:
        family(cases)
    return cases.C


def ring_cases(rng, c_thin, c_thin_thick, r_thick, t_thick):
    C = []
    r_m = (c_thin * E_MOD * RING_B * RING_T ** 3 / 12 / 0.148778) ** (1 / 3)
    hdr = {"baseline_uncertainty": 0.02}

    def ring(name, cat, exp, F, d, sigma, hdr_=None, params=None, t=None, truth=None):
        cols = {"force_N": F}
        if t is not None:
            cols["time_s"] = t
        cols["delta_cd_mm"] = d + rng.normal(0, sigma, len(F))
        C.append(dict(name=name, cat=cat, exp=exp, kind="ring_compression", specimen="ewg_ring",
                      cols=cols, hdr=hdr if hdr_ is None else hdr_, params=params, truth=truth or {}))

    F = 40.0 * ramp_path([0, 1, 0, 1, 0, 1, 0], 1500)     # delta ~ 2.4 mm = 6 % of r_m
    sig = 0.002 * c_thin * 40
    ring("ring_clean", "clean", set(), F, c_thin * F, sig)
    ring("ring_clean_quant", "clean", set(), F, quantise(c_thin * F, 0.5 * sig), sig)
    # large deflection: under diametral compression the ring's sides bulge out, lengthening the load's lever arm
    # about them, so the ring SOFTENS (the exact inextensible elastica's first correction is about +0.77; this
    # file's first version had a stiffening ring, gamma = -0.5, which no ring geometry gives):
    # delta = cF / (1 - 0.75 cF/r), first order gamma = +0.75, at delta/r_m ~ 0.06 (as the other ring cases): there
    # the elastica's next terms are ~1 % of its first correction; at 0.23 (150 N, this file's first version) this
    # rational form's would be 17 %, a curve no ring draws
    Fl = 40.0 * ramp_path([0, 1, 0, 1, 0], 1500)
    d = c_thin * Fl / (1 - 0.75 * c_thin * Fl / r_m)
    ring("ring_large_deflection", "in", {"large_deflection"}, Fl, d, 0.002 * d.max())
    # plasticity: elastic-plastic with Ramberg-Osgood hardening above F_y, elastic unloading, permanent set
    sy = 400.0
    Fy = math.pi * sy * RING_B * RING_T ** 2 / 6 / r_m
    Fp = Fy * ramp_path([0, 0.8, 0, 1.2, 0, 1.5, 0, 1.5, 0], 2000)
    dpl = np.zeros_like(Fp)
    peak = 0.0
    for i in range(len(Fp)):
        peak = max(peak, Fp[i])
        dpl[i] = 0.8 * c_thin * Fy * max(0.0, peak / Fy - 1.0) ** 1.3
    ring("ring_plasticity", "in", {"plasticity"}, Fp, c_thin * Fp + dpl, 0.002 * c_thin * Fy * 1.5,
         truth={"Fy": Fy, "set": float(dpl[-1])})
    # thick ring (Roark, curved beam with hoop and shear), thick rim from the params table
    al = t_thick ** 2 / (12 * r_thick ** 2)
    be = 1.2 * 2 * 1.3 * al
    corr = ((1 - al + be) * math.pi / 4 - 2 * (1 - al) ** 2 / math.pi) / 0.148778
    Ft = 2000.0 * ramp_path([0, 1, 0, 1, 0, 1, 0], 1500)
    ring("ring_thick", "in", {"thick_ring"}, Ft, c_thin_thick * corr * Ft, 0.001 * c_thin_thick * 2000,
         hdr_={"baseline_uncertainty": 0.01}, params={"ewg_drive": {"rim_thickness_ratio": 0.1}},
         truth={"thick_corr": corr})
    # plasticity with an exponential (softplus) knee instead of a power law, AR noise on large deflection
    dpl2 = np.zeros_like(Fp)
    peak = 0.0
    for i in range(len(Fp)):
        peak = max(peak, Fp[i])
        dpl2[i] = 1.5 * c_thin * (0.05 * Fy) * math.log1p(math.exp((peak - Fy) / (0.05 * Fy)))
    ring("ring_plasticity_softknee", "in", {"plasticity"}, Fp, c_thin * Fp + dpl2, 0.002 * c_thin * Fy * 1.5,
         truth={"Fy": Fy, "set": float(dpl2[-1])})
    # ring pressed by friction plates: dissipative loop (Maxwell slip on the force, displacement driven)
    dd = c_thin * 40 * ramp_path([0, 1, 0.12, 1, 0.12, 1, 0.12], 1500)   # plates keep contact
    Fr = maxwell_slip_twist_driven(dd, 1 / c_thin, np.full(6, 0.5 / c_thin), 40 * np.linspace(0.005, 0.02, 6))
    ring("ring_ooc_friction_loop", "out", None, Fr, dd, sig)
    d95 = c_thin * Fl / (1 - 0.75 * c_thin * Fl / r_m)
    cols_nz = noise(rng, len(Fl), "ar1", sigma=0.002 * d95.max(), rho=0.95)
    ring("ring_large_deflection_ar95", "in", {"large_deflection"}, Fl, d95 + cols_nz, 1e-9)
    # out of catalogue: viscoelastic creep of a polymer-coated/fixtured ring at a hold, clipping
    Fh = 40.0 * np.concatenate([np.linspace(0, 1, 300), np.ones(800), np.linspace(1, 0, 300)])
    tt = np.arange(len(Fh)) * 0.01
    crp = np.zeros_like(Fh)
    for i in range(1, len(Fh)):
        crp[i] = crp[i - 1] + 0.01 / 2.0 * (0.06 * c_thin * Fh[i] - crp[i - 1])
    ring("ring_ooc_creep_hold", "out", None, Fh, c_thin * Fh + crp, sig, t=tt)
    ring("ring_ooc_clipping", "out", None, F, np.minimum(c_thin * F, 0.85 * c_thin * 40), sig)
    return C


def pilot_ring(tmp, params=None):
    """The tool's analytic ring compliance, read from its JSON. The tool refuses a baseline more than 10x off the
    recording (exit 2), so the pilot's compliance steps through decades until one is within reach."""
    F = np.linspace(0, 40, 200)
    p = os.path.join(tmp, "pilot_ring.csv")
    for c in 10.0 ** np.arange(-6, 1):
        write_rec(p, "ring_compression", "ewg_ring", {"force_N": F, "delta_cd_mm": F * c + 1e-4 * c * np.sin(F)},
                  params=params)
        j, _ = run_diag(p)
        if "baseline" in j:
            return j["baseline"]["compliance"]
    raise SystemExit(f"pilot ring: no compliance from 1e-6 to 1 mm/N was accepted ({j.get('_error')})")


def expected_str(c):
    if c["cat"] == "clean":
        return "agrees"
    if c["cat"] == "out":
        return "unexplained|ambiguous"
    return "explained:" + "+".join(sorted(c["exp"]))


def judge(c, j):
    v = j.get("verdict")
    named = set(j.get("named") or [])
    amb = bool(j.get("ambiguous"))
    prim = j.get("primary")
    r = {"verdict": v, "named": named, "amb": amb, "primary": prim}
    if c["cat"] == "clean":
        r["ok"] = v == "agrees"
        r["conf_wrong"] = v == "explained" and not amb
    elif c["cat"] == "out":
        r["ok"] = v == "unexplained" or (v == "explained" and amb)
        r["conf_wrong"] = v == "explained" and not amb
    else:
        exp = c["exp"]
        r["prim_ok"] = v == "explained" and (prim in exp)
        r["set_ok"] = v == "explained" and named == exp
        r["ok"] = r["set_ok"]
        r["conf_wrong"] = v == "explained" and not amb and not (named & exp)
    return r


def _run_case(c, tmp):
    """Write one case, diagnose it, print its line; (case, JSON, judgement)."""
    path = os.path.join(tmp, c["name"] + ".csv")
    write_rec(path, c["kind"], c["specimen"], c["cols"], c["hdr"], c.get("params"))
    j, dt = run_diag(path)
    if "_error" in j:
        r = {"ok": False, "conf_wrong": False, "verdict": "ERROR", "named": set(), "amb": False,
             "primary": None, "prim_ok": False, "set_ok": False}
        print(f"{c['name']:32s} {expected_str(c):40s} ERROR {j['_error']}")
        return c, j, r
    r = judge(c, j)
    fit = j.get("fit", {})
    ratio = (fit.get("rms_after") or float("nan")) / (j.get("noise_std") or float("nan"))
    dbic = (j["effects"][0]["delta_bic"] if j.get("effects") else float("nan"))
    gof = (j.get("goodness_of_fit") or {})
    gm = gof.get("model") or gof.get("baseline") or {}
    chi2, lag1 = gm.get("chi2_per_sample", float("nan")), gm.get("lag1", float("nan"))
    nm = "+".join(sorted(r["named"])) + (f" ({r['primary']})" if r["primary"] else "")
    if j.get("suggestion"):
        sg = j["suggestion"]
        nm += " sugg:" + (sg.get("id", "") if isinstance(sg, dict) else str(sg))[:20]
    nm += " AMB" if r["amb"] else ""
    print(f"{c['name']:32s} {expected_str(c):40s} {str(r['verdict']):12s} {nm:48s} {ratio:9.2f} "
          f"{dbic:8.1f} {chi2:6.1f} {lag1:5.2f} {dt:5.1f} {'OK' if r['ok'] else 'WRONG'}{' CONF-WRONG' if r['conf_wrong'] else ''}",
          flush=True)
    return c, j, r


def _physics_checks(rows):
    """The true energy, width, crack side and yield beside what the tool reported."""
    print("\n# physics checks")
    for c, j, r in rows:
        tr = c["truth"]
        if "energy" in tr and "_error" not in j:
            q = j.get("quantities", {})
            qs = {k: v.get("value") for k, v in q.items()}
            ek = next((k for k in qs if "energy" in k), None)
            wk = next((k for k in qs if "arcmin" in k or "width" in k or "loss" in k), None)
            e_rep = qs.get(ek) if ek else None
            w_rep = qs.get(wk) if wk else None
            w_true = tr["width"] / ARCMIN
            msg = f"{c['name']:28s} true energy {tr['energy']:.4g} N*mm*rad, width {w_true:.4g} arcmin"
            if e_rep is not None:
                msg += f" | reported {ek}={e_rep:.4g} ({(e_rep / tr['energy'] - 1) * 100:+.0f} %)"
            else:
                msg += " | reported energy: none"
            if w_rep is not None:
                msg += f", {wk}={w_rep:.4g} ({(w_rep / w_true - 1) * 100:+.0f} %)"
            print(msg)
        if "crack_side" in tr and "_error" not in j:
            loc = j.get("located") or {}
            crk = next((e for e in j.get("effects", []) if "crack" in e["id"]), None)
            side_par = {k: v.get("value") for k, v in (crk or {}).get("parameters", {}).items()
                        if "side" in k or "sign" in k}
            print(f"{c['name']:28s} true open side {tr['crack_side']} | located ranges {loc.get('ranges')} "
                  f"branch {loc.get('branch')} | crack params {side_par} | {str(loc.get('description'))[:90]}")
        if "Fy" in tr and "_error" not in j:
            pl = next((e for e in j.get("effects", []) if e["id"] == "plasticity"), None)
            pars = {k: round(v.get("value"), 4) for k, v in (pl or {}).get("parameters", {}).items()
                    if isinstance(v.get("value"), (int, float))}
            print(f"{c['name']:28s} true F_y {tr['Fy']:.3g} N (0.2%-type knee, RO), final set {tr['set']:.3g} mm"
                  f" | fitted {pars}")


def _summary(rows, commit, t_all):
    """The headline fractions per category."""
    def pct(a_, b_):
        return f"{100 * a_ / b_:.0f} % ({a_}/{b_})" if b_ else "n/a"
    ins = [(c, j, r) for c, j, r in rows if c["cat"] == "in"]
    cln = [(c, j, r) for c, j, r in rows if c["cat"] == "clean"]
    out = [(c, j, r) for c, j, r in rows if c["cat"] == "out"]
    print("\n# summary (commit %s, %d recordings, %.0f s)" % (commit, len(rows), time.time() - t_all))
    print("in-catalogue primary effect right :", pct(sum(r.get("prim_ok", False) for _, _, r in ins), len(ins)))
    print("in-catalogue exact set right      :", pct(sum(r.get("set_ok", False) for _, _, r in ins), len(ins)))
    print("clean false alarms                :", pct(sum(r["verdict"] != "agrees" for _, _, r in cln), len(cln)))
    print("out-of-cat unexplained-or-ambig.  :", pct(sum(r["ok"] for _, _, r in out), len(out)))
    print("confidently wrong (all cases)     :", pct(sum(r["conf_wrong"] for _, _, r in rows), len(rows)))


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=None, help="keep recordings and JSON here")
    ap.add_argument("--only", default=None)
    ap.add_argument("--seed", type=int, default=20261124)
    a = ap.parse_args(argv)
    tmp = a.out or tempfile.mkdtemp(prefix="heldout_diag_")
    os.makedirs(tmp, exist_ok=True)
    rng = np.random.default_rng(a.seed)
    commit = subprocess.run(["git", "-C", ROOT, "log", "--oneline", "-1"], capture_output=True,
                            text=True).stdout.strip()
    print(f"# held-out diagnose benchmark; commit {commit}; {time.strftime('%Y-%m-%d %H:%M:%S UTC', time.gmtime())}")
    c_thin = pilot_ring(tmp)
    c_thick = pilot_ring(tmp, {"ewg_drive": {"rim_thickness_ratio": 0.1}})
    t_thick = 0.1 * 72.0
    r_thick = (c_thick * E_MOD * RING_B * t_thick ** 3 / 12 / 0.148778) ** (1 / 3)
    cases = torsion_cases(rng) + ring_cases(rng, c_thin, c_thick, r_thick, t_thick)
    if a.only:
        cases = [c for c in cases if a.only in c["name"]]
    t_all = time.time()
    hdr = f"{'case':32s} {'expected':40s} {'verdict':12s} {'named (primary) amb':48s} {'rms/noise':>9s} {'dBIC':>8s} {'chi2':>6s} {'lag1':>5s} {'s':>5s} ok"
    print(hdr)
    print("-" * len(hdr))
    rows = [_run_case(c, tmp) for c in cases]
    _physics_checks(rows)
    _summary(rows, commit, t_all)
    if not a.out:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
