#!/usr/bin/env python3
"""heldout5_diagnose: blind black-box benchmark no. 5 of ``strainwave diagnose``.

Written from docs/recordings.md, README's diagnose section, ``strainwave diagnose --help`` and issue 12
only; nothing is imported from the strainwave package and the tool is run only through its CLI
(``strainwave diagnose REC --json``) in subprocesses.  Every generator below is its own physics, derived
here from first principles, and checks itself at start-up (the run stops if a check fails).

What it covers (what the earlier held-out benchmarks covered least)
--------------------------------------------------------------------
RING COMPRESSION recordings (kind "ring_compression", specimen ewg_ring, columns force_N, delta_cd_mm, time_s;
force positive = compression).  The ring geometry is the EWG flexible ring of the parameter file
(Z_R = 72, m = 1, h_f* = 1.35, rim h = ratio * d_R, face width 12 mm, E = 210 GPa, nu = 0.3): mean radius
r_m = d_R/2 + h_f* m + h/2 (cross-checked at start-up against ``strainwave analytic --params``, a CLI).
The ring thickness is set per recording through ``[params.ewg_drive] rim_thickness_ratio`` in the header:
  * thin   0.012 (default, r/h = 44): large deflections (elastica) are visible at elastic loads;
  * medium 0.05  (r/h = 10.9): plasticity, cracks, creep and platen contact, where the geometric effect stays
    below the noise (checked per recording);
  * thick  0.10-0.13 (r/h = 8.7-6.6): curved-beam (thick-ring) compliance, stated baseline uncertainty 1 %.
Physics, in own forms:
  * elastica: inextensible Euler-Bernoulli ring between point loads, quarter ring shot to a vertical tangent
    at B (exact geometry, no series in delta/r); an elastic response is the tabulated elastica;
  * plasticity: quarter ring of 96 sections x 24 fibres, bilinear kinematic hardening (H = 1-5 % E), statics
    M = M0 - F R sin(phi)/2, M0 from compatibility (no rotation at C and B), deflection by virtual work;
    geometric increment of the elastica added (both are small corrections: first-order superposition);
  * thick ring: Castigliano on a Winkler-Bach curved beam (exact neutral-axis shift e = R - h/ln(Ro/Ri),
    M-N coupling derived from the fibre kinematics, shear with k = 1.2), M0 from dU/dM0 = 0;
  * compliance offset: the specimen's wall 3-9 % thinner/thicker, or its modulus off, than the simulation;
  * crack at the load point C: a rotational spring from LEFM (Tada's bending K, dC/da = 2B K^2/(E M^2)),
    open only when the crack face is in tension, closing smoothly by face contact; the statics of a half ring
    with the hinge at C solved self-consistently; on the outer fibre (opens under TENSION: bipolar
    tension-compression rig) or on the inner fibre held shut by residual stress up to a fraction of the peak
    (opens under compression beyond a knee, closes again on unloading: no permanent set);
  * platen seating: two crowned (point) Hertz contacts in series, delta_c = 2 (9 F^2 / (16 R* E*^2))^(1/3);
  * step-hold creep: linear viscoelastic log creep J(t) = J0 (1 + q ln(1 + t/tau)), Boltzmann superposition
    over the load history.
Protocols: load-unload cycles, unload to a preload, increasing peaks, single loading, step-hold, bipolar.

TORSION recordings (specimen output_shaft, the linear stiffness given in the header as
baseline_stiffness_Nmm_per_rad) with rig realities: a quantised encoder (step 0.5-2x the noise), AR(1)
noise rho 0.90-0.97, a torque sensor with a second-order non-linearity T_meas = T + k T^2/T_fs, a thermal
drift non-linear in time (first-order warm-up plus an air-conditioning swing), one or two spikes, very short
(60-150 rows) and very long (20,000 rows) recordings, each clean and with an in-catalogue effect
(own-form stiffening: algebraic sigmoid compliance; own-form crack: compliance opening by a Gaussian-CDF
contact fraction).

Truth convention
----------------
* signal-to-noise (SNR) of an effect = peak |effect| after a least-squares nuisance fit of offset, stiffness
  scale (the baseline's linear response) and linear drift in time, over the noise sigma (the marginal std of
  the noise, before quantisation).  The SNR of a recording is that of its weakest true effect.
* in catalogue: the set of catalogue ids (docs/recordings.md) whose effect has SNR >= 3.  A physical side
  effect with 0.2 <= SNR < 3 (e.g. the elastica beside plasticity, always present in a real ring) is
  OPTIONAL: the exact set may include it or not.  Below 0.2 it is absent.  (The band starts at 0.2, not 1:
  on the first run the tool named the elastica of "clean" rings whose elastica peaked at 0.3-0.7 sigma
  after the nuisance fit, with gamma 0.68-1.12 against the true 0.77, i.e. it found real physics: with
  ~1,000 samples a smooth 0.3-sigma shape is statistically visible, and the doc's 1.5-sigma naming floor
  is measured on the effect's own increment, before the stiffness scale takes its linear part.)
* compliance-like effects (compliance_offset, thick_ring) are linear in the load, so the stiffness scale of
  the nuisance fit absorbs them: their size is counted in PRIOR sigmas, z = |c_true/c_sim - 1| / u (the
  recording's baseline_uncertainty); they are in the truth when z >= 4 (the doc's mismatch threshold is 2.6),
  and a stiffness 0.8-1.5 prior sigmas off is CLEAN (verdict agrees).  Their SNR column shows z.
* clean: no effect with SNR >= 0.2 (white, AR(1), quantised, short, long; a ring whose crack stays closed
  under compression; a ring 0.8-1.5 prior sigmas off): expected verdict ``agrees``.  The loads of clean
  rings are lowered until their elastica is below 0.2 sigma (checked for every recording at build time).
* out of catalogue (truth ``ooc:<label>``): expected ``unexplained`` or a named effect flagged ambiguous.

Judgement calls (where the doc is silent or ambiguous), scored as a reliability engineer would expect:
* platen seating (Hertz contact) stiffens the force-deflection curve at low load; the doc says a ring's
  geometry SOFTENS it and that "a ring that stiffens does so through its platen contacts", so stiffening is
  not large_deflection (gamma must be positive), and a contact law is not the linear series compliance of
  compliance_offset: OUT of catalogue, expected ``unexplained``.
* a crack in the ring: crack_closure is a torsion-only catalogue entry; for a ring it is OUT of catalogue.
  A reversible knee (crack opening under compression) is not plasticity (no permanent set).  A crack on the
  outer fibre at the load point is closed under compression: the ring is the uncracked ring (checked to
  1e-12), the recording is CLEAN.  A tension-compression (bipolar) ring test is refused by the tool
  ("force_N is a compression force and must be >= 0"; the doc says "Ring force is compression, positive");
  it is kept as a probe and counted as a refusal, apart from the targets.
* step-hold creep: out of catalogue; the doc's stuck-load-channel rule also makes it ``unexplained``.
* spikes: the doc says samples the noise cannot have made make the verdict ``unexplained`` with the sample
  named; a 12-40 sigma spike in a clean recording is scored as out of catalogue (``ooc:spike``).
* a torque-sensor quadratic non-linearity is even in the load and may look like a crack that opens on one
  side; it is not specimen physics: out of catalogue.
* non-linear thermal drift is out of catalogue; its size is chosen above the doc's stated resolution
  (RMS after a linear detrend > 2 sigma), so the doc's "a drift smaller than a wander is not claimed" does
  not excuse a miss.
* Bad input (3 files) must exit 2 with one line on stderr.

Scoring (issue 12's targets): clean -> agrees, false alarms <= 5 %; in catalogue SNR >= 3 -> primary named
>= 95 %, exact set >= 90 %; out of catalogue -> unexplained or ambiguous >= 80 %, a confidently named
catalogue effect <= 10 %; crashes (exit not 0/2, or a traceback) and refusals (exit 2) counted apart.

Measured (commit of this text, 72 recordings + 3 bad inputs per seed, 2 jobs, ~3.6 min at load 3-5):
seed 0: clean 0/18 false alarms (white 0/11, coloured 0/7) PASS; in catalogue primary 31/33 MISS, exact
29/33 MISS; out of catalogue unexplained/ambiguous 20/20 PASS, confident wrong name 0/20 PASS; bad input 3/3;
0 crashes, 1 refusal (the bipolar ring).  seed 1: the same except primary 31/33 MISS, exact 31/33 PASS.
Misses: the exact elastica at 100-300 sigma is "unexplained" (gamma fitted 0.78-0.80; the doc's one-gamma
form leaves the elastica's second-order term, -0.24 (delta/r)^2, ~1 sigma peak / 0.4 sigma RMS); smooth
(algebraic-sigmoid) stiffening at 49-300 sigma gets a spurious compliance_offset (3.6 %, 10.5 %) and a
crack at 300 sigma / 20,000 rows a spurious lost_motion (0.013 arcmin).

Usage: benchmarks/heldout5_diagnose.py [--seed N] [--out DIR] [--only NAME[,NAME]] [--keep DIR] [--list]
[--jobs 2].  Runs with OMP_NUM_THREADS=1 etc. in the tool's environment.
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
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import NamedTuple

import numpy as np
from scipy.optimize import brentq
from scipy.special import erf

sys.path.insert(0, str(Path(__file__).resolve().parent))
from load_paths import ramp_path  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
EXE = REPO / ".venv" / "bin" / "strainwave"

# ----------------------------------------------------------------------------------------------------------
# material and ring geometry (the parameter file's EWG ring; units N, mm, MPa)
E_STEEL = 2.1e5
NU = 0.3
G_STEEL = E_STEEL / (2 * (1 + NU))
Z_R, MODULE, HF_COEF, FACE_W = 72, 1.0, 1.35, 12.0


class Ring:
    def __init__(self, ratio: float, E: float = E_STEEL, h_scale: float = 1.0):
        self.ratio = ratio
        self.h_nom = ratio * Z_R * MODULE
        self.r = Z_R * MODULE / 2 + HF_COEF * MODULE + self.h_nom / 2  # simulated mean radius (nominal wall)
        self.h = self.h_nom * h_scale                                   # the specimen's real wall
        self.B = FACE_W
        self.E = E
        self.I = self.B * self.h ** 3 / 12
        self.A = self.B * self.h
        self.I_nom = self.B * self.h_nom ** 3 / 12

    @property
    def c_thin_nom(self) -> float:  # the simulation's thin-ring compliance (mm/N), nominal E and wall
        return (math.pi / 4 - 2 / math.pi) * self.r ** 3 / (E_STEEL * self.I_nom)

    @property
    def c_thin(self) -> float:  # thin-ring compliance of the real specimen
        return (math.pi / 4 - 2 / math.pi) * self.r ** 3 / (self.E * self.I)

    def first_yield_force(self, sy: float) -> float:
        # |M| is largest at the load point, M = F R / pi; first yield at M = sy B h^2 / 6
        return math.pi * sy * self.B * self.h ** 2 / 6 / self.r


# ---------------------------------------------------------------- thick ring: Castigliano, Winkler-Bach
def thick_ring_compliance(ring: Ring, n: int = 4001) -> float:
    """Diametral compliance of a curved (thick) rectangular ring by Castigliano.

    Fibre kinematics of a curved bar (fibre length ~ R + y) give, per unit centroidal arc length,
    U' = N^2/(2EA) + M^2/(2 E A e R) - M N/(E A R) + k V^2/(2 G A) with M positive for tension at the INNER
    fibre and N positive in tension, e = R - h/ln(Ro/Ri).  Quarter ring from the load point C: M = M0 -
    F R sin(phi)/2, N = -F sin(phi)/2, V = F cos(phi)/2.  M0 from dU/dM0 = 0, delta = dU/dF.
    """
    R, h, A, E = ring.r, ring.h, ring.A, ring.E
    G = E / (2 * (1 + NU))
    e = R - h / math.log((R + h / 2) / (R - h / 2))
    k = 1.2
    phi = np.linspace(0, math.pi / 2, n)

    def U(M0, F):
        M = M0 - F * R * np.sin(phi) / 2
        N = -F * np.sin(phi) / 2
        V = F * np.cos(phi) / 2
        u = N ** 2 / (2 * E * A) + M ** 2 / (2 * E * A * e * R) - M * N / (E * A * R) + k * V ** 2 / (2 * G * A)
        return 4 * np.trapezoid(u, phi) * R

    # U is quadratic in (M0, F): recover its coefficients from a few evaluations
    F = 1.0
    a = (U(1.0, 0.0))  # coefficient of M0^2
    c = U(0.0, F)      # coefficient of F^2
    b = U(1.0, F) - a - c  # coefficient of M0 F
    M0 = -b * F / (2 * a)
    return 2 * c + b * M0 / F  # dU/dF at fixed (optimal) M0, per unit F


# ---------------------------------------------------------------- elastica (large deflection)
def elastica_delta(ring: Ring, F: float, nstep: int = 400, energy: bool = False):
    """Approach of the load points of an inextensible elastic ring under diametral point loads F (exact
    geometry).  Quarter ring from C (top) to B (side); tangent angle theta, dtheta/ds = -(1/R - M/EI),
    M = M0 - (F/2) x (x: horizontal distance from the load line, deformed; M > 0 = tension at the inner
    fibre = the ring straightens, as at the load point); theta(L) = -pi/2 by symmetry.
    energy=True also returns the strain energy 4 int M^2/(2EI) ds (for the work-energy self-check)."""
    R, EI = ring.r, ring.E * ring.I
    L = math.pi * R / 2
    ds = L / nstep

    def shoot(M0):
        st = np.array([0.0, 0.0, R, 0.0])  # theta, x, y, energy

        def f(v):
            th, x = v[0], v[1]
            M = M0 - F / 2 * x
            return np.array([-(1 / R - M / EI), math.cos(th), math.sin(th), M * M / (2 * EI)])

        for _ in range(nstep):
            k1 = f(st)
            k2 = f(st + ds / 2 * k1)
            k3 = f(st + ds / 2 * k2)
            k4 = f(st + ds * k3)
            st = st + ds / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        return st[0] + math.pi / 2, st[1], st[2], 4 * st[3]

    if abs(F) * (math.pi / 4 - 2 / math.pi) * R ** 3 / EI < 1e-9 * R:  # linear to round-off
        d = (math.pi / 4 - 2 / math.pi) * R ** 3 / EI * F
        return (d, 0.5 * F * d) if energy else d
    M0_lin = F * R / math.pi
    span = abs(M0_lin) * 0.5 + 1e-12
    M0 = brentq(lambda m: shoot(m)[0], M0_lin - span, M0_lin + span, xtol=1e-14 * max(1.0, abs(M0_lin)))
    _, _, y, U = shoot(M0)
    # C starts at height R above B's line; deformed, C is R - y(L) above B: delta_CD = 2 (R - (R - y(L)))
    return (2 * y, U) if energy else 2 * y


class ElasticaTable:
    def __init__(self, ring: Ring, fmin: float, fmax: float, n: int = 41):
        self.F = np.linspace(fmin, fmax, n)
        if not np.any(self.F == 0):
            self.F = np.sort(np.append(self.F, 0.0))
        self.d = np.array([elastica_delta(ring, f) for f in self.F])
        from scipy.interpolate import CubicSpline
        self.spline = CubicSpline(self.F, self.d)

    def __call__(self, F):
        return self.spline(np.asarray(F, float))


# ---------------------------------------------------------------- plasticity: fibre quarter ring
class FibreRing:
    def __init__(self, ring: Ring, sy: float, H: float, nsec: int = 96, nfib: int = 24):
        self.ring, self.sy, self.H = ring, sy, H
        self.phi = (np.arange(nsec) + 0.5) * (math.pi / 2) / nsec
        self.w = np.full(nsec, (math.pi / 2) / nsec)
        self.y = ((np.arange(nfib) + 0.5) / nfib - 0.5) * ring.h  # + toward the inner fibre
        self.dA = ring.B * ring.h / nfib
        self.ep = np.zeros((nsec, nfib))
        self.al = np.zeros((nsec, nfib))
        self.kap = np.zeros(nsec)
        self.M0 = 0.0

    def _section(self, kap):
        E, H, sy = self.ring.E, self.H, self.sy
        eps = kap[:, None] * self.y[None, :]
        st = E * (eps - self.ep)
        xi = st - self.al
        f = np.abs(xi) - sy
        pl = f > 0
        dg = np.where(pl, f / (E + H), 0.0)
        sg = np.sign(xi)
        sig = st - E * dg * sg
        et = np.where(pl, E * H / (E + H), E)
        M = (sig * self.y[None, :]).sum(1) * self.dA
        Kt = (et * self.y[None, :] ** 2).sum(1) * self.dA
        return M, Kt, (self.ep + dg * sg, self.al + H * dg * sg)

    def step(self, F: float) -> float:
        R = self.ring.r
        s = np.sin(self.phi) * R / 2
        kap, M0 = self.kap.copy(), self.M0
        for it in range(200):
            M, Kt, _ = self._section(kap)
            tgt = M0 - F * s
            g = np.sum(self.w * (kap + (tgt - M) / Kt))
            dM0 = -g / np.sum(self.w / Kt)
            M0 += dM0
            dk = (M0 - F * s - M) / Kt
            kap += dk
            if np.max(np.abs(M0 - F * s - M)) < 1e-9 * max(1.0, abs(F) * R) and it > 0 and abs(dM0) < 1e-9 * max(1.0, abs(F) * R):
                break
        else:
            raise RuntimeError("fibre ring did not converge")
        M, Kt, (ep, al) = self._section(kap)
        self.kap, self.M0, self.ep, self.al = kap, M0, ep, al
        # virtual work with the statically admissible unit system m_v = -(R/2) sin(phi), 4 quarters
        return 4 * np.sum(self.w * kap * (-(R / 2) * np.sin(self.phi))) * R

    def run(self, F: np.ndarray, sub: int = 4) -> np.ndarray:
        out = np.empty(len(F))
        prev = 0.0
        for i, f in enumerate(F):
            for j in range(1, sub + 1):
                d = self.step(prev + (f - prev) * j / sub)
            out[i] = d
            prev = f
        return out


# ---------------------------------------------------------------- crack at the load point (LEFM hinge)
def crack_rot_compliance(ring: Ring, a_over_h: float) -> float:
    """Extra rotation per moment of an edge crack in bending (rad/(N mm)): C = 72 pi/(E B h^2) int_0^alpha
    s F(s)^2 ds with Tada's F(s) = 1.122 - 1.40 s + 7.33 s^2 - 13.08 s^3 + 14.0 s^4."""
    s = np.linspace(0, a_over_h, 2001)
    Fs = 1.122 - 1.40 * s + 7.33 * s ** 2 - 13.08 * s ** 3 + 14.0 * s ** 4
    return 72 * math.pi / (ring.E * ring.B * ring.h ** 2) * np.trapezoid(s * Fs ** 2, s)


def crack_ring_delta(ring: Ring, F: np.ndarray, c_rot: float, side: int, m_open: float, m_width: float):
    """Half-ring statics with a hinge at C: M(phi) = M0 - F R sin(phi)/2, phi in [0, pi];
    compatibility int M/EI ds + (c_rot open(M0)/2) M0 = 0; delta = (R^2/EI)(pi F R/4 - 2 M0).
    side=+1: crack on the inner fibre (opens when M0 > 0, i.e. under compression);
    side=-1: outer fibre (opens when M0 < 0, under tension).  open() = smooth contact release from
    side*M0 = m_open over m_width (0 closed, 1 open)."""
    R, EI = ring.r, ring.E * ring.I
    out = np.empty(len(F))
    for i, f in enumerate(np.asarray(F, float)):
        def g(M0):
            u = (side * M0 - m_open) / m_width
            op = 0.5 * (1 + math.tanh(u))
            return M0 * (math.pi * R / EI + c_rot * op / 2) - f * R ** 2 / EI
        lo, hi = sorted([0.0, f * R / math.pi * 1.000001])
        if f == 0:
            M0 = 0.0
        else:
            # g is monotone increasing in M0 on the solution branch; bracket generously
            lo2, hi2 = min(lo, hi) - abs(f) * R, max(lo, hi) + abs(f) * R
            M0 = brentq(g, lo2, hi2, xtol=1e-14 * abs(f) * R)
        out[i] = R ** 2 / EI * (math.pi * f * R / 4 - 2 * M0)
    return out


# ---------------------------------------------------------------- torsion own-form effects
def stiffening_twist(T, c1, c3, Tk, n):
    """algebraic-sigmoid stiffening: compliance c1 at zero, c3 (< c1) at large |T|."""
    u = T / Tk
    return c3 * T + (c1 - c3) * Tk * u / (1 + np.abs(u) ** n) ** (1 / n)


def crack_twist(T, c0, dc, T0, w):
    """crack opening on the positive side: extra twist dc * int_0^T P(u) du, P = Gaussian CDF((u-T0)/w)."""
    def prim(x):
        z = (x - T0) / w
        P = 0.5 * (1 + erf(z / math.sqrt(2)))
        pdf = np.exp(-z * z / 2) / math.sqrt(2 * math.pi)
        return (x - T0) * P + w * pdf
    return c0 * T + dc * (prim(T) - prim(0.0))


# ---------------------------------------------------------------- self-checks
def self_check():
    checks = []
    ring = Ring(0.012)
    # 1 elastica small-load limit equals the thin-ring coefficient pi/4 - 2/pi (linear theory)
    f = 1e-3
    lin = elastica_delta(ring, f) / f / ring.c_thin
    checks.append(("elastica small-load limit = pi/4 - 2/pi", abs(lin - 1) < 1e-4, lin))
    # 2 elastica: compression softens (secant compliance rises), tension stiffens, monotone
    F = np.linspace(-40, 40, 9)
    d = np.array([elastica_delta(ring, x) for x in F])
    sec = d[F != 0] / F[F != 0]
    ok = np.all(np.diff(d) > 0) and sec[-1] > sec[len(sec) // 2] > sec[0]
    checks.append(("elastica monotone, softening in compression", bool(ok), sec[-1] / ring.c_thin))
    # 2b elastica work = strain energy (int F d(delta) along the loading = 4 int M^2/2EI ds at the end)
    Fw = np.linspace(0, 40, 81)
    dw = np.array([elastica_delta(ring, x) for x in Fw])
    W = np.trapezoid(Fw, dw)
    U = elastica_delta(ring, 40.0, energy=True)[1]
    checks.append(("elastica work = strain energy", abs(W / U - 1) < 1e-4, W / U))
    # 3 thick ring -> thin ring as h/r -> 0; thicker ring deviates more
    thin = Ring(0.0015)
    r1 = thick_ring_compliance(thin) / thin.c_thin
    r2 = thick_ring_compliance(Ring(0.12)) / Ring(0.12).c_thin
    checks.append(("Castigliano curved beam -> thin ring", abs(r1 - 1) < 1e-4, r1))
    checks.append(("thick ring deviates by O((h/r)^2)", abs(r2 - 1) > 10 * abs(r1 - 1), r2))
    # 4 plasticity: elastic below first yield with the thin-ring compliance, unloading elastic with the
    # initial stiffness, positive permanent set
    mr = Ring(0.05)
    sy = 500.0
    Fy = mr.first_yield_force(sy)
    fr = FibreRing(mr, sy, 0.02 * E_STEEL)
    d1 = fr.step(0.95 * Fy)
    checks.append(("fibre ring elastic below first yield", abs(d1 / (0.95 * Fy) / mr.c_thin - 1) < 2e-3,
                   d1 / (0.95 * Fy) / mr.c_thin))
    dpk = [fr.step(x) for x in np.linspace(0.95 * Fy, 1.5 * Fy, 40)][-1]
    sec_pk = dpk / (1.5 * Fy)
    du = fr.step(1.5 * Fy - 0.01 * Fy)
    k_un = (dpk - du) / (0.01 * Fy)
    checks.append(("plastic unloading elastic, initial stiffness", abs(k_un / mr.c_thin - 1) < 5e-3,
                   k_un / mr.c_thin))
    dset = [fr.step(x) for x in np.linspace(1.49 * Fy, 0, 40)][-1]
    checks.append(("plastic permanent set positive", dset > 0 and sec_pk > 1.02 * mr.c_thin, dset))
    # 5 crack: closed side has the uncracked stiffness; open side more compliant; elastic (no set)
    cr = crack_rot_compliance(mr, 0.3)
    Fs = np.array([-100.0, -50.0, 50.0, 100.0])
    dc = crack_ring_delta(mr, Fs, cr, side=-1, m_open=0.0, m_width=1e-6 * Fy * mr.r)
    closed = dc[2:] / Fs[2:] / mr.c_thin
    opened = dc[:2] / Fs[:2] / mr.c_thin
    checks.append(("crack closed under compression = uncracked", np.all(np.abs(closed - 1) < 1e-9), closed[0]))
    checks.append(("crack open under tension more compliant", np.all(opened > 1.01), opened[0]))
    # 6 torsion stiffening monotone, crack closed side uncracked
    T = np.linspace(-1, 1, 2001)
    tw = stiffening_twist(T, 1.0, 0.4, 0.3, 2.0)
    comp = np.diff(tw) / np.diff(T)
    mid = len(comp) // 2
    ok = np.all(comp > 0) and np.all(np.diff(comp[mid:]) <= 1e-12) and np.all(np.diff(comp[:mid]) >= -1e-12)
    checks.append(("stiffening monotone (compliance falls with |T|)", bool(ok), comp.min()))
    tc = crack_twist(T, 1.0, 0.5, 0.2, 0.05)
    comp = np.diff(tc) / np.diff(T)
    checks.append(("torsion crack closed side uncracked", abs(comp[:500].mean() - 1) < 1e-9 and comp[-1] > 1.49,
                   comp[-1]))
    # 7 Hertz seating stiffens monotonically
    Fh = np.linspace(0, 100, 201)
    dh = hertz_pair(Fh, 20.0)
    k = np.diff(dh) / np.diff(Fh)
    checks.append(("Hertz contact compliance falls with load", bool(np.all(np.diff(k) < 0)), k[-1]))
    # 8 log creep: creep increases under a hold, superposition linear
    t = np.linspace(0, 100, 201)
    Fc = np.where(t > 10, 50.0, 0.0)
    dcp = creep_response(t, Fc, 1.0, 0.05, 2.0)
    checks.append(("creep grows under a constant hold", bool(np.all(np.diff(dcp[t > 11]) > 0)), dcp[-1]))
    bad = [c for c in checks if not c[1]]
    for name, ok, val in checks:
        print(f"  self-check {'ok ' if ok else 'FAIL'} {name} ({val:.6g})")
    if bad:
        raise SystemExit("self-check failed: " + "; ".join(b[0] for b in bad))


def hertz_pair(F, Rstar):
    """two crowned point contacts (ring on platen, top and bottom) in series: approach 2 (9F^2/(16R E*^2))^(1/3)."""
    Es = E_STEEL / (2 * (1 - NU ** 2))
    F = np.clip(np.asarray(F, float), 0, None)
    return 2 * (9 * F ** 2 / (16 * Rstar * Es ** 2)) ** (1 / 3)


def creep_response(t, F, c0, q, tau):
    """Boltzmann superposition with J(t) = c0 (1 + q ln(1 + t/tau))."""
    dF = np.diff(np.concatenate([[0.0], F]))
    out = np.zeros(len(t))
    idx = np.nonzero(dF)[0]
    for i in idx:
        lag = np.clip(t - t[i], 0, None)
        out += np.where(t >= t[i], dF[i] * c0 * (1 + q * np.log1p(lag / tau)), 0.0)
    return out


# ---------------------------------------------------------------- load paths
def hold_path(levels, n_ramp, n_hold):
    out = [np.array([0.0])]
    prev = 0.0
    for lv in levels:
        out.append(np.linspace(prev, lv, n_ramp + 1)[1:])
        out.append(np.full(n_hold, lv))
        prev = lv
    out.append(np.linspace(prev, 0, n_ramp * 2 + 1)[1:])
    return np.concatenate(out)


# ---------------------------------------------------------------- helpers
def nuisance_resid(e, xlin, t):
    A = np.column_stack([np.ones_like(xlin), xlin, t])
    coef, *_ = np.linalg.lstsq(A, e, rcond=None)
    return e - A @ coef


def snr_of(e, xlin, t, sigma):
    return float(np.max(np.abs(nuisance_resid(e, xlin, t))) / sigma)


def loguni(rng, lo, hi):
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


def ar1(rng, n, rho, sigma):
    x = np.empty(n)
    x[0] = rng.normal(0, sigma)
    s = sigma * math.sqrt(1 - rho ** 2)
    eps = rng.normal(0, s, n)
    for i in range(1, n):
        x[i] = rho * x[i - 1] + eps[i]
    return x


def header_ring(ratio, u=None, desc=""):
    lines = ["[test]", 'kind = "ring_compression"', 'specimen = "ewg_ring"']
    if u is not None:
        lines.append(f"baseline_uncertainty = {u}")
    lines.append(f'description = "{desc}"')
    if abs(ratio - 0.012) > 1e-12:
        lines += ["[params.ewg_drive]", f"rim_thickness_ratio = {ratio}"]
    return lines


def header_torsion(K, u=0.02, desc=""):
    return ["[test]", 'kind = "torsion"', 'specimen = "output_shaft"', f"baseline_uncertainty = {u}",
            f"baseline_stiffness_Nmm_per_rad = {K:.9g}", f'description = "{desc}"']


def write_rec(path, header, cols, data):
    with open(path, "w") as fh:
        for h in header:
            fh.write("# " + h + "\n")
        fh.write(",".join(cols) + "\n")
        for row in zip(*data):
            fh.write(",".join(f"{v:.10g}" for v in row) + "\n")


# ---------------------------------------------------------------- recording builders
class Rec:
    def __init__(self, name, cls, truth, optional=(), snr=None, extra=None):
        self.name, self.cls, self.truth = name, cls, truth
        self.optional = list(optional)
        self.snr = snr
        self.extra = extra or {}
        self.header = None
        self.cols = None
        self.data = None
        self.raw_text = None


def pick_snr(rng, i, high_every=None):
    return loguni(rng, 3, 50)


def ring_effects_truth(effects, xlin, t, sigma):
    """effects: {id: vector}; returns (truth, optional, snrs)."""
    truth, opt, snrs = [], [], {}
    for k, v in effects.items():
        s = snr_of(v, xlin, t, sigma)
        snrs[k] = s
        if s >= 3:
            truth.append(k)
        elif s >= 0.2:
            opt.append(k)
    return truth, opt, snrs



def elastica_below_noise(el_med, med, F, xlin, t, sigma):
    """Scale the load down (x 0.7 per step) until the ring's elastica is neither a truth nor optional:
    (load scale, elastica increment, optional list, SNRs) of a recording kept clean of it."""
    Fs = 1.0
    while True:
        ld = el_med(F * Fs) - med.c_thin * F * Fs
        truth, opt, snrs = ring_effects_truth({"large_deflection": ld}, xlin * Fs, t, sigma * Fs)
        if not truth and not opt:
            return Fs, ld, opt, snrs
        Fs *= 0.7


class Lab(NamedTuple):
    """What every ring family draws on: the generator and the two rings with their elastica tables."""
    rng: np.random.Generator
    thin: Ring
    med: Ring
    el_thin: ElasticaTable
    el_med: ElasticaTable


K_TORSION = 7.89e8  # given linear stiffness, N mm / rad (a 70/45 mm shaft of 200 mm)


def _ld_inc(ring, table, F):
    return table(F) - ring.c_thin * F


def _ring_time(n, rate_s=0.05):
    return np.arange(n) * rate_s


def _snr_plan(rng, k, n300=0):
    """SNR plan: log-uniform 3..50 with a few at 300."""
    v = [loguni(rng, 3, 50) for _ in range(k)]
    for j in range(n300):
        v[j] = 300.0
    rng.shuffle(v)
    return v


def _tors_path(n, tmax, cycles=2):
    pts = [0]
    for _ in range(cycles):
        pts += [tmax, -tmax]
    pts += [0]
    return ramp_path(pts, n)


def _tors_rec(rng, name, cls, truth, opt, snrs, T, t, phi, sigma, noise="white", rho=0.0, q=0.0, spikes=(),
              drift=True, extra=None, snr_override=None, K_given=K_TORSION):
    n = len(T)
    if noise == "ar1":
        e = ar1(rng, n, rho, sigma)
    else:
        e = rng.normal(0, sigma, n)
    off = rng.normal(0, 50 * sigma)
    dr = rng.normal(0, 5 * sigma) * t / t[-1] if drift else 0.0
    meas = phi + e + off + dr
    if q > 0:
        meas = np.round(meas / q) * q
    for (j, amp) in spikes:
        meas[j] += amp * sigma
    r = Rec(name, cls, truth, opt, snr_override if snr_override is not None else
            (min(snrs[k] for k in truth) if isinstance(truth, list) and truth else None), extra)
    r.snrs = snrs
    r.header = header_torsion(K_given, desc=name)
    r.cols = ["time_s", "torque_Nmm", "twist_rad"]
    r.data = [t, T, meas]
    r.sigma = sigma
    return r


def _ring_large_deflection(lab):
    """Thin ring, elastic: the elastica at planned signal-to-noise ratios."""
    rng, thin, med, el_thin, el_med = lab
    recs = []
    protos = ["cycles", "preload", "single", "cycles", "increasing", "single"]
    sn = _snr_plan(rng, 6, n300=1)
    for i, proto in enumerate(protos):
        fmax = rng.uniform(15, 40)  # stays elastic for any steel >= 300 MPa at this section
        F, n = ring_path(rng, proto, fmax)
        t = _ring_time(len(F))
        xlin = thin.c_thin_nom * F
        inc = _ld_inc(thin, el_thin, F)
        peak = np.max(np.abs(nuisance_resid(inc, xlin, t)))
        sigma = peak / sn[i]
        scale = 1 + rng.uniform(-0.5, 0.5) * 0.02
        y = scale * thin.c_thin * F + inc
        truth, opt, snrs = ring_effects_truth({"large_deflection": inc}, xlin, t, sigma)
        recs.append(ring_rec(rng, f"ring_ld_{i}_{proto}", "ring_large_deflection", truth, opt, snrs, F, t, y,
                             sigma, 0.012, None, drift=rng.uniform() < 0.5,
                             extra={"F_max_N": fmax, "delta_max_mm": float(np.max(y)),
                                    "delta_over_r": float(np.max(y) / thin.r)}))
    return recs


def _ring_plasticity(lab):
    """Medium ring loaded past first yield: fibre-model plasticity with its elastica."""
    rng, thin, med, el_thin, el_med = lab
    recs = []
    protos = ["cycles", "increasing", "preload", "single", "cycles", "increasing"]
    sn = _snr_plan(rng, 6, n300=1)
    for i, proto in enumerate(protos):
        sy = loguni(rng, 300, 1200)
        Hk = rng.uniform(0.01, 0.05) * E_STEEL
        Fy = med.first_yield_force(sy)
        over = rng.uniform(1.15, 1.6)
        F, n = ring_path(rng, proto, over * Fy)
        t = _ring_time(len(F))
        fr = FibreRing(med, sy, Hk)
        dpl = fr.run(F)
        pl_inc = dpl - med.c_thin * F
        xlin = med.c_thin_nom * F
        peak = np.max(np.abs(nuisance_resid(pl_inc, xlin, t)))
        sigma = peak / sn[i]
        ld = _ld_inc(med, el_med, F)
        c_th = thick_ring_compliance(med)
        scale = 1 + rng.uniform(-0.5, 0.5) * 0.02
        y = scale * (c_th / med.c_thin) * dpl + ld
        truth, opt, snrs = ring_effects_truth({"plasticity": pl_inc, "large_deflection": ld}, xlin, t, sigma)
        # set after unloading: last zero-force sample
        recs.append(ring_rec(rng, f"ring_plastic_{i}_{proto}", "ring_plasticity", truth, opt, snrs, F, t, y,
                             sigma, 0.05, None, drift=rng.uniform() < 0.4,
                             extra={"sigma_y_MPa": sy, "H_over_E": Hk / E_STEEL, "F_first_yield_N": Fy,
                                    "F_peak_over_Fy": over, "thick_ratio": c_th / med.c_thin}))
    return recs


def _ring_thick(lab):
    """Thick rings (curved-beam compliance) against a stated 1 % uncertainty."""
    rng, thin, med, el_thin, el_med = lab
    recs = []
    sn = _snr_plan(rng, 3)
    for i, ratio in enumerate([0.10, 0.115, 0.13][:3]):
        rg = Ring(ratio)
        c_th = thick_ring_compliance(rg)
        z = abs(c_th / rg.c_thin - 1) / 0.01
        proto = ["cycles", "single", "preload"][i]
        # loads well below first yield of a 600 MPa steel, deflections tiny vs r (no elastica effect)
        F, n = ring_path(rng, proto, 0.5 * rg.first_yield_force(600.0))
        t = _ring_time(len(F))
        xlin = rg.c_thin_nom * F
        sigma = np.max(np.abs(xlin)) / loguni(rng, 300, 3000)
        ld = ElasticaTable(rg, -F.max(), F.max(), 11)(F) - rg.c_thin * F
        y = c_th * F + ld
        tr, opt, snrs = ring_effects_truth({"large_deflection": ld}, xlin, t, sigma)
        recs.append(ring_rec(rng, f"ring_thick_{i}", "ring_thick_ring", ["thick_ring"] + tr, opt,
                             {"thick_ring": z, **snrs}, F, t, y, sigma, ratio, 0.01, drift=True,
                             extra={"compliance_ratio_to_thin": c_th / rg.c_thin}, snr_override=z))
    return recs


def _ring_compliance_offset(lab):
    """Thin ring with its wall or modulus off, and one within the prior."""
    rng, thin, med, el_thin, el_med = lab
    recs = []
    u = 0.02
    for i, (kind, z_t, sign) in enumerate([("h", rng.uniform(4.5, 10), +1), ("E", rng.uniform(4.5, 10), +1),
                                           ("h", rng.uniform(4.5, 10), -1), ("h", rng.uniform(0.8, 1.5), +1)]):
        ratio_c = 1 + sign * z_t * u  # the specimen's compliance over the simulation's
        if kind == "h":  # wall thinner (softer) or thicker (stiffer) than drawn: c ~ h^-3
            val = ratio_c ** (-1 / 3) - 1
            rg = Ring(0.012, h_scale=1 + val)
        else:            # modulus lower than the simulation's 210 GPa
            val = 1 / ratio_c - 1
            rg = Ring(0.012, E=E_STEEL * (1 + val))
        z = abs(rg.c_thin / rg.c_thin_nom - 1) / u
        proto = ["cycles", "single", "preload", "cycles"][i]
        fmax = rng.uniform(3, 6)  # small deflections
        F0, n = ring_path(rng, proto, 1.0)
        rel = loguni(rng, 200, 2000)
        while True:
            F = F0 * fmax
            t = _ring_time(len(F))
            xlin = rg.c_thin_nom * F
            sigma = np.max(np.abs(xlin)) / rel
            ld = ElasticaTable(rg, -10, 10, 11)(F) - rg.c_thin * F
            _, _, s_ld = ring_effects_truth({"large_deflection": ld}, xlin, t, sigma)
            if z >= 4 or s_ld["large_deflection"] < 0.2:  # the within-prior one is kept clean
                break
            fmax *= 0.7
        y = rg.c_thin * F + ld
        if z >= 4:
            truth, cls = ["compliance_offset"], "ring_compliance_offset"
        else:
            truth, cls = [], "clean_ring_offset_within_prior"
        opt = ["large_deflection"] if s_ld["large_deflection"] >= 0.2 else []
        if s_ld["large_deflection"] >= 3:
            truth = truth + ["large_deflection"]
        recs.append(ring_rec(rng, f"ring_offset_{i}_{kind}", cls, truth, opt,
                             {"compliance_offset": z, **s_ld}, F, t, y, sigma, 0.012, u, drift=True,
                             extra={"what": kind, "relative_error": val,
                                    "compliance_ratio": rg.c_thin / rg.c_thin_nom},
                             snr_override=z if truth else None))
    return recs


def _ring_clean(lab):
    """Clean rings (white, AR(1)) with the elastica kept below the noise."""
    rng, thin, med, el_thin, el_med = lab
    recs = []
    for i in range(5):
        ar = i >= 3
        rg = [thin, med, thin, med, thin][i]
        table = el_thin if rg is thin else el_med
        proto = ["cycles", "preload", "single", "cycles", "increasing"][i]
        fmax = rng.uniform(3, 8) if rg is thin else 0.6 * rg.first_yield_force(300.0)
        F0, n = ring_path(rng, proto, 1.0)
        rel = loguni(rng, 100, 1000)
        scl = rng.uniform(-0.5, 0.5) * 0.02
        while True:  # keep clean clean: the load comes down until the elastica is below the noise
            F = F0 * fmax
            t = _ring_time(len(F))
            xlin = rg.c_thin_nom * F
            sigma = np.max(np.abs(xlin)) / rel
            ld = table(F) - rg.c_thin * F
            truth, opt, snrs = ring_effects_truth({"large_deflection": ld}, xlin, t, sigma)
            if not truth and not opt:
                break
            fmax *= 0.7
        c_th = thick_ring_compliance(rg)
        y = (1 + scl) * c_th * F + ld
        rho = rng.uniform(0.9, 0.97) if ar else 0.0
        recs.append(ring_rec(rng, f"ring_clean_{i}_{'ar1' if ar else 'white'}",
                             "clean_ring_ar1" if ar else "clean_ring_white", [], opt, snrs, F, t, y, sigma,
                             rg.ratio, None, drift=True, rho=rho, extra={"rho": rho}))
    return recs


def _ring_cracks(lab):
    """Cracks at the load point C: opening under tension (bipolar rig), closed under compression (outer fibre:
    invisible in a compression test -> clean), opening under compression beyond a residual-stress closure (inner
    fibre)."""
    rng, thin, med, el_thin, el_med = lab
    recs = []
    for i in range(4):
        kind = ["bipolar", "closed", "compression", "compression"][i]
        fy = med.first_yield_force(800.0)
        fmax = 0.7 * fy
        if kind == "bipolar":
            pts = [0]
            for _ in range(2):
                pts += [fmax, -fmax]
            pts += [0]
            F = ramp_path(pts, int(rng.integers(600, 1200)))
            cr = crack_rot_compliance(med, rng.uniform(0.2, 0.4))
            d = crack_ring_delta(med, F, cr, side=-1, m_open=0.0, m_width=0.03 * fmax * med.r / math.pi)
            label = "ooc:ring_crack_open_in_tension"
        elif kind == "closed":
            F, n = ring_path(rng, "cycles", fmax)
            cr = crack_rot_compliance(med, rng.uniform(0.2, 0.4))
            # faces in contact as soon as the load compresses them (sharp contact)
            d = crack_ring_delta(med, F, cr, side=-1, m_open=0.0, m_width=1e-9 * fmax * med.r / math.pi)
            label = []
        else:
            F, n = ring_path(rng, ["cycles", "increasing"][i - 2], fmax)
            cr = crack_rot_compliance(med, rng.uniform(0.25, 0.45))
            m_open = rng.uniform(0.3, 0.5) * fmax * med.r / math.pi
            d = crack_ring_delta(med, F, cr, side=+1, m_open=m_open, m_width=0.08 * fmax * med.r / math.pi)
            label = "ooc:ring_crack_opening_under_compression"
        t = _ring_time(len(F))
        inc = d - med.c_thin * F
        xlin = med.c_thin_nom * F
        c_th = thick_ring_compliance(med)
        if kind == "closed":
            if np.max(np.abs(inc)) > 1e-12 * np.max(d):
                raise RuntimeError("closed crack changed the ring's response")
            s_target = None
            sigma = np.max(np.abs(xlin)) / loguni(rng, 100, 1000)
            # the elastica kept below the noise: a clean recording
            Fs, ld, opt, snrs = elastica_below_noise(el_med, med, F, xlin, t, sigma)
            F, d, sigma = F * Fs, d * Fs, sigma * Fs
        else:
            s_target = loguni(rng, 3, 50) if i % 2 == 0 else loguni(rng, 10, 50)
            sigma = np.max(np.abs(nuisance_resid(inc, xlin, t))) / s_target
            ld = el_med(F) - med.c_thin * F
            _, opt, snrs = ring_effects_truth({"large_deflection": ld}, xlin, t, sigma)
            snrs["crack"] = s_target
        y = (c_th / med.c_thin) * d + ld
        recs.append(ring_rec(rng, f"ring_crack_{i}_{kind}", label if label else "clean_ring_crack_closed", label,
                             opt, snrs, F, t, y, sigma, 0.05, None, drift=rng.uniform() < 0.5,
                             snr_override=s_target, extra={"crack_rot_compliance": cr}))
    return recs


def _ring_platen_hertz(lab):
    """Out of catalogue: platen seating by Hertz point contacts."""
    rng, thin, med, el_thin, el_med = lab
    recs = []
    for i in range(3):
        fmax = 0.7 * med.first_yield_force(600.0)
        proto = ["cycles", "single", "increasing"][i]
        F, n = ring_path(rng, proto, fmax)
        t = _ring_time(len(F))
        Rstar = rng.uniform(8, 40)
        hz = hertz_pair(F, Rstar)
        xlin = med.c_thin_nom * F
        s_target = loguni(rng, 3, 50)
        sigma = np.max(np.abs(nuisance_resid(hz, xlin, t))) / s_target
        ld = el_med(F) - med.c_thin * F
        c_th = thick_ring_compliance(med)
        y = c_th * F + hz + ld
        _, opt, snrs = ring_effects_truth({"large_deflection": ld}, xlin, t, sigma)
        snrs["hertz"] = s_target
        recs.append(ring_rec(rng, f"ring_platen_hertz_{i}", "ooc:platen_seating_hertz", "ooc:platen_seating_hertz",
                             opt, snrs, F, t, y, sigma, 0.05, None, drift=False, snr_override=s_target,
                             extra={"R_star_mm": Rstar, "hertz_share_at_Fmax": float(hz.max() / y.max())}))
    return recs


def _ring_creep_hold(lab):
    """Out of catalogue: step-hold creep."""
    rng, thin, med, el_thin, el_med = lab
    recs = []
    for i in range(2):
        fmax = 0.7 * med.first_yield_force(600.0)
        levels = [fmax * x for x in ([0.3, 0.6, 1.0] if i == 0 else [0.5, 1.0, 0.5])]
        F = hold_path(levels, int(rng.integers(40, 80)), int(rng.integers(80, 160)))
        t = _ring_time(len(F), 0.5)
        q, tau = rng.uniform(0.01, 0.03), rng.uniform(1, 5)
        c_th = thick_ring_compliance(med)
        d = creep_response(t, F, c_th, q, tau)
        inc = d - c_th * F
        xlin = med.c_thin_nom * F
        s_target = loguni(rng, 5, 50)
        sigma = np.max(np.abs(nuisance_resid(inc, xlin, t))) / s_target
        ld = el_med(F) - med.c_thin * F
        y = d + ld
        _, opt, snrs = ring_effects_truth({"large_deflection": ld}, xlin, t, sigma)
        snrs["creep"] = s_target
        recs.append(ring_rec(rng, f"ring_creep_hold_{i}", "ooc:step_hold_creep", "ooc:step_hold_creep", opt, snrs,
                             F, t, y, sigma, 0.05, None, drift=False, snr_override=s_target,
                             extra={"q": q, "tau_s": tau}))
    return recs


def _ring_thin_plastic(lab):
    """Thin ring of a soft steel: plasticity with a strong elastica beside it."""
    rng, thin, med, el_thin, el_med = lab
    recs = []
    for i in range(2):
        sy = rng.uniform(250, 400)
        Fy = thin.first_yield_force(sy)
        over = rng.uniform(1.2, 1.5)
        F, n = ring_path(rng, ["cycles", "preload"][i], over * Fy)
        t = _ring_time(len(F))
        fr = FibreRing(thin, sy, rng.uniform(0.01, 0.05) * E_STEEL)
        dpl = fr.run(F)
        pl_inc = dpl - thin.c_thin * F
        xlin = thin.c_thin_nom * F
        sigma = np.max(np.abs(nuisance_resid(pl_inc, xlin, t))) / loguni(rng, 5, 50)
        tab = ElasticaTable(thin, 0, 1.05 * F.max(), 31)
        ld = tab(F) - thin.c_thin * F
        y = dpl + ld
        truth, opt, snrs = ring_effects_truth({"plasticity": pl_inc, "large_deflection": ld}, xlin, t, sigma)
        recs.append(ring_rec(rng, f"ring_thin_plastic_{i}", "ring_plasticity", truth, opt, snrs, F, t, y, sigma,
                             0.012, None, drift=True, extra={"sigma_y_MPa": sy, "F_first_yield_N": Fy,
                                                             "F_peak_over_Fy": over,
                                                             "delta_over_r": float(y.max() / thin.r)}))
    return recs


def _ring_ld_high_snr(lab):
    """Large deflection at high signal (100 and 300 sigma), load-unload cycles."""
    rng, thin, med, el_thin, el_med = lab
    recs = []
    for i, sn_i in enumerate([100.0, 300.0]):
        fmax = rng.uniform(15, 40)
        F, n = ring_path(rng, "cycles", fmax)
        t = _ring_time(len(F))
        xlin = thin.c_thin_nom * F
        inc = _ld_inc(thin, el_thin, F)
        sigma = np.max(np.abs(nuisance_resid(inc, xlin, t))) / sn_i
        y = (1 + rng.uniform(-0.5, 0.5) * 0.02) * thin.c_thin * F + inc
        truth, opt, snrs = ring_effects_truth({"large_deflection": inc}, xlin, t, sigma)
        recs.append(ring_rec(rng, f"ring_ld_high_{int(sn_i)}", "ring_large_deflection", truth, opt, snrs, F, t, y,
                             sigma, 0.012, None, drift=True, extra={"F_max_N": fmax,
                                                                    "delta_over_r": float(y.max() / thin.r)}))
    return recs


def _ring_ar1_and_quantised(lab):
    """Plasticity with AR(1) noise; large deflection read by a quantised transducer."""
    rng, thin, med, el_thin, el_med = lab
    recs = []
    sy = loguni(rng, 400, 1000)
    Fy = med.first_yield_force(sy)
    over = rng.uniform(1.2, 1.5)
    F, n = ring_path(rng, "increasing", over * Fy)
    t = _ring_time(len(F))
    fr = FibreRing(med, sy, rng.uniform(0.01, 0.05) * E_STEEL)
    dpl = fr.run(F)
    pl_inc = dpl - med.c_thin * F
    xlin = med.c_thin_nom * F
    sigma = np.max(np.abs(nuisance_resid(pl_inc, xlin, t))) / loguni(rng, 8, 50)
    ld = el_med(F) - med.c_thin * F
    y = thick_ring_compliance(med) / med.c_thin * dpl + ld
    truth, opt, snrs = ring_effects_truth({"plasticity": pl_inc, "large_deflection": ld}, xlin, t, sigma)
    rho = rng.uniform(0.9, 0.97)
    recs.append(ring_rec(rng, "ring_plastic_ar1", "ring_plasticity", truth, opt, snrs, F, t, y, sigma, 0.05, None,
                         rho=rho, extra={"sigma_y_MPa": sy, "F_peak_over_Fy": over, "rho": rho}))
    fmax = rng.uniform(15, 40)
    F, n = ring_path(rng, "preload", fmax)
    t = _ring_time(len(F))
    xlin = thin.c_thin_nom * F
    inc = _ld_inc(thin, el_thin, F)
    sigma = np.max(np.abs(nuisance_resid(inc, xlin, t))) / loguni(rng, 5, 50)
    qs = rng.uniform(0.5, 2.0) * sigma
    truth, opt, snrs = ring_effects_truth({"large_deflection": inc}, xlin, t, sigma)
    recs.append(ring_rec(rng, "ring_ld_quantised", "ring_large_deflection", truth, opt, snrs, F, t,
                         thin.c_thin * F + inc, sigma, 0.012, None, q=qs, extra={"quantum_over_sigma": qs / sigma}))
    return recs


def _ring_drift_and_spike(lab):
    """Out of catalogue on a ring: non-linear thermal drift of the displacement; a spike."""
    rng, thin, med, el_thin, el_med = lab
    recs = []
    for i in range(2):
        fmax = 0.6 * med.first_yield_force(600.0)
        F, n = ring_path(rng, ["cycles", "preload"][i], fmax)
        t = _ring_time(len(F))
        xlin = med.c_thin_nom * F
        sigma = np.max(np.abs(xlin)) / loguni(rng, 100, 1000)
        Fs, ld, opt, snrs = elastica_below_noise(el_med, med, F, xlin, t, sigma)
        F, xlin, sigma = F * Fs, xlin * Fs, sigma * Fs
        y = thick_ring_compliance(med) * F + ld
        if i == 0:
            tt = t / t[-1]
            shape = (1 - np.exp(-tt / rng.uniform(0.1, 0.3))) + rng.uniform(0.2, 0.6) * np.sin(
                2 * math.pi * tt * rng.uniform(1.2, 2.5))
            s_t = loguni(rng, 6, 50)
            y = y + s_t * sigma * shape / np.max(np.abs(nuisance_resid(shape, xlin, t)))
            recs.append(ring_rec(rng, "ring_thermal_drift", "ooc:thermal_drift_nonlinear", "ooc:thermal_drift_nonlinear",
                                 [], snrs, F, t, y, sigma, 0.05, None, snr_override=s_t))
        else:
            j = int(rng.integers(50, len(F) - 50))
            amp = float(rng.uniform(12, 40) * rng.choice([-1, 1]))
            recs.append(ring_rec(rng, "ring_spike", "ooc:spike", "ooc:spike", [], snrs, F, t, y, sigma, 0.05, None,
                                 spikes=[(j, amp)], snr_override=abs(amp), extra={"spikes": [(j, amp)]}))
    return recs


def _ring_offset_tight_loose(lab):
    """Compliance offset against a tight (0.5 %) and a loose (5 %) stated uncertainty."""
    rng, thin, med, el_thin, el_med = lab
    recs = []
    for i, (u, z_t) in enumerate([(0.005, rng.uniform(5, 12)), (0.05, rng.uniform(0.8, 1.4))]):
        ratio_c = 1 + z_t * u
        rg = Ring(0.012, h_scale=ratio_c ** (-1 / 3))
        z = abs(rg.c_thin / rg.c_thin_nom - 1) / u
        F0, n = ring_path(rng, "cycles", 1.0)
        rel = loguni(rng, 300, 3000)
        fmax = rng.uniform(2, 5)
        while True:
            F = F0 * fmax
            t = _ring_time(len(F))
            xlin = rg.c_thin_nom * F
            sigma = np.max(np.abs(xlin)) / rel
            ld = ElasticaTable(rg, 0, 10, 11)(F) - rg.c_thin * F
            tr_, opt, s_ld = ring_effects_truth({"large_deflection": ld}, xlin, t, sigma)
            if not tr_ and not opt:
                break
            fmax *= 0.7
        truth = ["compliance_offset"] if z >= 4 else []
        recs.append(ring_rec(rng, f"ring_offset_u{u}", "ring_compliance_offset" if truth else
                             "clean_ring_offset_within_prior", truth, [], {"compliance_offset": z, **s_ld}, F, t,
                             rg.c_thin * F + ld, sigma, 0.012, u, extra={"compliance_ratio": rg.c_thin / rg.c_thin_nom},
                             snr_override=z if truth else None))
    return recs


def _ring_linear_drift(lab):
    """Load-unload cycles with a strong linear drift (30-100 sigma): a nuisance."""
    rng, thin, med, el_thin, el_med = lab
    recs = []
    fmax = rng.uniform(15, 40)
    F, n = ring_path(rng, "cycles", fmax)
    t = _ring_time(len(F))
    xlin = thin.c_thin_nom * F
    inc = _ld_inc(thin, el_thin, F)
    sigma = np.max(np.abs(nuisance_resid(inc, xlin, t))) / loguni(rng, 5, 50)
    truth, opt, snrs = ring_effects_truth({"large_deflection": inc}, xlin, t, sigma)
    dsig = float(rng.uniform(30, 100))
    recs.append(ring_rec(rng, "ring_ld_drift", "ring_large_deflection", truth, opt, snrs, F, t,
                         thin.c_thin * F + inc, sigma, 0.012, None, drift_sigmas=dsig,
                         extra={"drift_sigmas_1sd": dsig}))
    sy = loguni(rng, 400, 1000)
    Fy = med.first_yield_force(sy)
    over = rng.uniform(1.2, 1.5)
    F, n = ring_path(rng, "cycles", over * Fy)
    t = _ring_time(len(F))
    dpl = FibreRing(med, sy, rng.uniform(0.01, 0.05) * E_STEEL).run(F)
    pl_inc = dpl - med.c_thin * F
    xlin = med.c_thin_nom * F
    sigma = np.max(np.abs(nuisance_resid(pl_inc, xlin, t))) / loguni(rng, 5, 50)
    ld = el_med(F) - med.c_thin * F
    truth, opt, snrs = ring_effects_truth({"plasticity": pl_inc, "large_deflection": ld}, xlin, t, sigma)
    dsig = float(rng.uniform(30, 100))
    recs.append(ring_rec(rng, "ring_plastic_drift", "ring_plasticity", truth, opt, snrs, F, t,
                         thick_ring_compliance(med) / med.c_thin * dpl + ld, sigma, 0.05, None, drift_sigmas=dsig,
                         extra={"sigma_y_MPa": sy, "F_first_yield_N": Fy, "F_peak_over_Fy": over,
                                "drift_sigmas_1sd": dsig}))
    return recs


def _torsion_clean(lab):
    """Clean torsion: quantised encoder, AR(1), short and long."""
    rng = lab.rng
    c = 1 / K_TORSION
    recs = []
    # clean quantised encoder
    for i in range(3):
        n = int(rng.integers(800, 2000))
        tmax = rng.uniform(2e5, 8e5)
        T = _tors_path(n, tmax)
        t = np.arange(n) * 0.02
        sigma = c * tmax / loguni(rng, 200, 2000)
        qs = rng.uniform(0.5, 2.0) * sigma
        phi = c * (1 + rng.uniform(-0.01, 0.01)) * T
        recs.append(_tors_rec(rng, f"tors_clean_quantised_{i}", "clean_torsion_quantised", [], [], {}, T, t, phi,
                              sigma, q=qs, extra={"quantum_over_sigma": qs / sigma}))
    # clean AR(1)
    for i in range(5):
        n = int(rng.integers(800, 2500))
        tmax = rng.uniform(2e5, 8e5)
        T = _tors_path(n, tmax, cycles=int(rng.integers(1, 4)))
        t = np.arange(n) * 0.02
        sigma = c * tmax / loguni(rng, 200, 2000)
        rho = rng.uniform(0.9, 0.97)
        phi = c * (1 + rng.uniform(-0.01, 0.01)) * T
        recs.append(_tors_rec(rng, f"tors_clean_ar1_{i}", "clean_torsion_ar1", [], [], {}, T, t, phi, sigma,
                              noise="ar1", rho=rho, extra={"rho": rho}))
    # clean short and long
    for i, n in enumerate([int(rng.integers(60, 151)), 20000]):
        tmax = rng.uniform(2e5, 8e5)
        T = _tors_path(n, tmax)
        t = np.arange(n) * 0.02
        sigma = c * tmax / loguni(rng, 200, 2000)
        phi = c * (1 + rng.uniform(-0.01, 0.01)) * T
        recs.append(_tors_rec(rng, f"tors_clean_{'short' if i == 0 else 'long'}_{n}", "clean_torsion_length", [], [],
                              {}, T, t, phi, sigma, extra={"rows": n}))
    return recs


def _torsion_in_catalogue(lab):
    """In catalogue: stiffening and crack closure, short, quantised, AR(1), long."""
    rng = lab.rng
    c = 1 / K_TORSION
    recs = []
    # in catalogue: short stiffening, quantised stiffening, AR(1) stiffening, long crack
    specs = [("short", "nonlinear_stiffness"), ("quantised", "nonlinear_stiffness"), ("ar1", "nonlinear_stiffness"),
             ("long", "crack_closure"), ("quantised", "crack_closure"), ("short", "crack_closure")]
    sn = _snr_plan(rng, 6, n300=1)
    for i, (what, eff) in enumerate(specs):
        n = {"short": int(rng.integers(60, 151)), "long": 20000}.get(what, int(rng.integers(800, 2000)))
        tmax = rng.uniform(3e5, 8e5)
        T = _tors_path(n, tmax)
        t = np.arange(n) * 0.02
        if eff == "nonlinear_stiffness":
            r3 = rng.uniform(1.5, 3.0)
            phi = stiffening_twist(T, c, c / r3, rng.uniform(0.15, 0.4) * tmax, rng.uniform(1.5, 4))
            params = {"K3_over_K1": r3}
        else:
            phi = crack_twist(T, c, rng.uniform(0.1, 0.4) * c, rng.uniform(0.0, 0.2) * tmax, 0.05 * tmax)
            params = {}
        inc = phi - c * T
        xlin = c * T
        sigma = np.max(np.abs(nuisance_resid(inc, xlin, t))) / sn[i]
        noise = "ar1" if what == "ar1" else "white"
        rho = rng.uniform(0.9, 0.97) if noise == "ar1" else 0.0
        qs = rng.uniform(0.5, 2.0) * sigma if what == "quantised" else 0.0
        recs.append(_tors_rec(rng, f"tors_{what}_{eff}", f"torsion_{eff}", [eff], [], {eff: sn[i]}, T, t, phi, sigma,
                              noise=noise, rho=rho, q=qs, extra={"rows": n, "rho": rho, **params}))
    return recs


def _torsion_sensor_and_drift(lab):
    """Out of catalogue: torque sensor quadratic non-linearity; non-linear thermal drift."""
    rng = lab.rng
    c = 1 / K_TORSION
    recs = []
    # OOC: torque sensor quadratic non-linearity
    for i in range(5):
        n = int(rng.integers(800, 2000))
        tmax = rng.uniform(3e5, 8e5)
        Ttrue = _tors_path(n, tmax)
        kq = rng.uniform(0.001, 0.005) * rng.choice([-1, 1])
        Tm = Ttrue + kq * Ttrue ** 2 / tmax
        t = np.arange(n) * 0.02
        phi = c * Ttrue
        inc = phi - c * Tm
        xlin = c * Tm
        s_target = loguni(rng, 3, 50) if i else 300.0
        sigma = np.max(np.abs(nuisance_resid(inc, xlin, t))) / s_target
        recs.append(_tors_rec(rng, f"tors_sensor_quadratic_{i}", "ooc:torque_sensor_quadratic",
                              "ooc:torque_sensor_quadratic", [], {"sensor": s_target}, Tm, t, phi, sigma,
                              snr_override=s_target, extra={"k_fs": kq}))
    # OOC: non-linear thermal drift
    for i in range(4):
        n = int(rng.integers(1000, 3000))
        tmax = rng.uniform(3e5, 8e5)
        T = _tors_path(n, tmax, cycles=int(rng.integers(2, 5)))
        t = np.arange(n) * 0.05
        tt = t / t[-1]
        tau = rng.uniform(0.1, 0.3)
        ac = rng.uniform(0.2, 0.6)
        shape = (1 - np.exp(-tt / tau)) + ac * np.sin(2 * math.pi * tt * rng.uniform(1.2, 2.5))
        xlin = c * T
        r = nuisance_resid(shape, xlin, t)
        s_target = loguni(rng, 6, 50)
        sigma = 1.0
        amp = s_target / np.max(np.abs(r))
        sigma = c * tmax / loguni(rng, 300, 2000)
        drift = amp * sigma * shape
        rms = float(np.sqrt(np.mean(nuisance_resid(drift, xlin, t) ** 2)) / sigma)
        recs.append(_tors_rec(rng, f"tors_thermal_drift_{i}", "ooc:thermal_drift_nonlinear",
                              "ooc:thermal_drift_nonlinear", [], {"drift": s_target}, T, t, c * T + drift, sigma,
                              snr_override=s_target, extra={"rms_after_linear_detrend_sigmas": rms}))
    return recs


def _torsion_spikes(lab):
    """Out of catalogue: one and two spikes."""
    rng = lab.rng
    c = 1 / K_TORSION
    recs = []
    # OOC: spikes
    for i in range(2):
        n = int(rng.integers(800, 2000))
        tmax = rng.uniform(3e5, 8e5)
        T = _tors_path(n, tmax)
        t = np.arange(n) * 0.02
        sigma = c * tmax / loguni(rng, 200, 2000)
        k = i + 1
        js = sorted(rng.choice(np.arange(50, n - 50), k, replace=False))
        spikes = [(int(j), float(rng.uniform(12, 40) * rng.choice([-1, 1]))) for j in js]
        recs.append(_tors_rec(rng, f"tors_spike_{k}", "ooc:spike", "ooc:spike", [], {}, T, t, c * T, sigma,
                              spikes=spikes, snr_override=min(abs(a) for _, a in spikes),
                              extra={"spikes": spikes}))
    return recs


def _bad_inputs():
    """Bad input: each must exit 2 with one line."""
    bad = []
    b = Rec("bad_missing_column", "bad_input", "exit2")
    b.raw_text = "# [test]\n# kind = \"ring_compression\"\n# specimen = \"ewg_ring\"\nforce_N,time_s\n" + \
        "".join(f"{i},{i * 0.1}\n" for i in range(40))
    bad.append(b)
    b = Rec("bad_specimen_for_kind", "bad_input", "exit2")
    b.raw_text = "# [test]\n# kind = \"ring_compression\"\n# specimen = \"output_shaft\"\nforce_N,delta_cd_mm\n" + \
        "".join(f"{i},{i * 0.06}\n" for i in range(40))
    bad.append(b)
    b = Rec("bad_nonnumeric_ring", "bad_input", "exit2")
    b.raw_text = "# [test]\n# kind = \"ring_compression\"\n# specimen = \"ewg_ring\"\nforce_N,delta_cd_mm\n" + \
        "".join(f"{i},{i * 0.06}\n" for i in range(20)) + "21,twelve\n" + \
        "".join(f"{i},{i * 0.06}\n" for i in range(22, 40))
    bad.append(b)
    return bad


FAMILIES = (_ring_large_deflection, _ring_plasticity, _ring_thick, _ring_compliance_offset, _ring_clean,
            _ring_cracks, _ring_platen_hertz, _ring_creep_hold, _ring_thin_plastic, _ring_ld_high_snr,
            _ring_ar1_and_quantised, _ring_drift_and_spike, _ring_offset_tight_loose, _ring_linear_drift,
            _torsion_clean, _torsion_in_catalogue, _torsion_sensor_and_drift, _torsion_spikes)


def build_all(seed: int):
    """Every recording in a fixed order (the families draw from one generator in turn), then the bad inputs."""
    thin, med = Ring(0.012), Ring(0.05)
    lab = Lab(np.random.default_rng(seed), thin, med, ElasticaTable(thin, -60, 60),
              ElasticaTable(med, -4500, 4500))
    recs = []
    for family in FAMILIES:
        recs += family(lab)
    check_truths(recs)
    return recs + _bad_inputs()


CATALOGUE = {"compliance_offset", "nonlinear_stiffness", "hysteresis", "lost_motion", "crack_closure",
             "kinematic_error", "thick_ring", "large_deflection", "plasticity"}


def check_truths(recs):
    """every recording's truth follows the convention of the module docstring (guards the generators)."""
    for r in recs:
        snrs = getattr(r, "snrs", {})
        if isinstance(r.truth, str):
            continue
        for k in r.truth + r.optional:
            if k not in CATALOGUE:
                raise RuntimeError(f"{r.name}: {k} is not a catalogue id")
        for k, v in snrs.items():
            if k not in CATALOGUE:
                continue
            if k in ("compliance_offset", "thick_ring"):
                ok = (v >= 4 and k in r.truth) or (v < 2 and k not in r.truth)
            elif v >= 3:
                ok = k in r.truth
            elif v >= 0.2:
                ok = k in r.optional
            else:
                ok = k not in r.truth and k not in r.optional
            if not ok:
                raise RuntimeError(f"{r.name}: truth {r.truth} / optional {r.optional} contradict {k} at {v:.3g}")


def ring_path(rng, proto, fmax):
    n = int(rng.integers(400, 1500))
    if proto == "cycles":
        k = int(rng.integers(2, 4))
        pts = [0] + [fmax, 0] * k
    elif proto == "preload":
        pre = rng.uniform(0.1, 0.3) * fmax
        k = int(rng.integers(2, 4))
        pts = [0] + [fmax, pre] * k + [fmax, 0]
    elif proto == "increasing":
        pts = [0, 0.4 * fmax, 0, 0.7 * fmax, 0, fmax, 0]
    elif proto == "single":
        pts = [0, fmax, 0]
    else:
        raise ValueError(proto)
    return ramp_path(pts, n), n


def ring_rec(rng, name, cls, truth, opt, snrs, F, t, y, sigma, ratio, u, drift=True, rho=0.0, extra=None,
             snr_override=None, q=0.0, spikes=(), drift_sigmas=5.0):
    n = len(F)
    e = ar1(rng, n, rho, sigma) if rho > 0 else rng.normal(0, sigma, n)
    off = rng.normal(0, 20 * sigma)
    dr = rng.normal(0, drift_sigmas * sigma) * t / t[-1] if drift else 0.0
    meas = y + e + off + dr
    if q > 0:  # quantised displacement transducer
        meas = np.round(meas / q) * q
    for (j, amp) in spikes:
        meas[j] += amp * sigma
    if isinstance(truth, list):
        s = snr_override if snr_override is not None else (min(snrs[k] for k in truth) if truth else None)
    else:
        s = snr_override
    r = Rec(name, cls, truth, opt, s, extra)
    r.snrs = snrs
    r.header = header_ring(ratio, u, desc=name)
    r.cols = ["time_s", "force_N", "delta_cd_mm"]
    r.data = [t, F, meas]
    r.sigma = sigma
    return r


# ---------------------------------------------------------------- running the tool
def run_one(rec: Rec, workdir: Path):
    path = workdir / f"{rec.name}.csv"
    if rec.raw_text is not None:
        path.write_text(rec.raw_text)
    else:
        write_rec(path, rec.header, rec.cols, rec.data)
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1")
    t0 = time.time()
    try:
        p = subprocess.run([str(EXE), "diagnose", str(path), "--json"], capture_output=True, text=True,
                           timeout=600, env=env)
        rc, out, err = p.returncode, p.stdout, p.stderr
    except subprocess.TimeoutExpired:
        rc, out, err = -999, "", "timeout"
    dt = time.time() - t0
    res = {"name": rec.name, "class": rec.cls, "truth": rec.truth, "optional": rec.optional, "snr": rec.snr,
           "snrs": getattr(rec, "snrs", {}), "extra": rec.extra, "exit": rc, "seconds": round(dt, 2),
           "stderr_tail": err.strip().splitlines()[-3:] if err.strip() else []}
    res["traceback"] = "Traceback" in err
    if rc == 0:
        try:
            d = json.loads(out)
        except json.JSONDecodeError:
            res["json_error"] = True
            return res
        res["verdict"] = d.get("verdict")
        res["named"] = sorted(d.get("named") or [])
        res["primary"] = d.get("primary")
        res["ambiguous"] = bool(d.get("ambiguous"))
        conf = d.get("confidence") or {}
        res["runner_up"] = conf.get("runner_up")
        res["margin_bic"] = conf.get("margin_bic")
        sug = d.get("suggestion")
        res["suggestion"] = sug if isinstance(sug, (str, type(None))) else json.dumps(sug)[:300]
        res["structure"] = (d.get("structure") if isinstance(d.get("structure"), str)
                            else json.dumps(d.get("structure"))[:400])
        eff = d.get("effects") or []
        if eff:
            top = eff[0]
            res["top_effect"] = {"id": top.get("id"), "model": top.get("model"),
                                 "delta_bic": top.get("delta_bic"),
                                 "parameters": {k: v.get("value") if isinstance(v, dict) else v
                                                for k, v in (top.get("parameters") or {}).items()},
                                 "warnings": top.get("warnings")}
        res["noise_std"] = d.get("noise_std")
        res["explanation"] = (d.get("explanation") or "")[:600]
    return res


def score(res):
    cls, truth = res["class"], res["truth"]
    if res["class"] == "bad_input":
        one_line = len([l for l in res.get("stderr_tail", []) if l.strip()]) == 1
        return "bad_ok" if res["exit"] == 2 and one_line and not res["traceback"] else "bad_wrong"
    if res["exit"] not in (0, 2) or res.get("traceback") or res.get("json_error"):
        return "crash"
    if res["exit"] == 2:
        return "refused"
    v = res.get("verdict")
    named = set(res.get("named") or [])
    if isinstance(truth, str):  # out of catalogue
        if v == "unexplained" or (v == "explained" and res.get("ambiguous")):
            return "ooc_ok"
        if v == "explained":
            return "ooc_wrong_named"
        return "ooc_agrees"
    opt = set(res.get("optional") or [])
    if not truth:
        if v == "agrees":
            return "clean_ok"
        # a real physical side effect between 0.2 and 3 sigma named with nothing else: not a false alarm
        return "clean_optional_named" if (v == "explained" and named and named <= opt) else "false_alarm"
    t = set(truth)
    prim_ok = v == "explained" and res.get("primary") in t and _primary_true(res) == res.get("primary")
    exact = v == "explained" and t <= named <= (t | opt)
    return ("exact" if exact else ("primary_only" if prim_ok else "wrong"))


def _primary_true(res):
    truth = res["truth"]
    snrs = res.get("snrs") or {}
    if len(truth) == 1:
        return truth[0]
    return max(truth, key=lambda k: snrs.get(k, 0))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", type=Path, default=Path("heldout5_out"))
    ap.add_argument("--only", default="")
    ap.add_argument("--keep", type=Path, default=None, help="keep the generated recordings in DIR")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args(argv)
    if a.jobs < 1:
        ap.error("--jobs must be >= 1")
    t0 = time.time()
    print("self-checks (first principles):")
    self_check()
    check_geometry()
    recs = build_all(a.seed)
    if a.only:
        want = set(a.only.split(","))
        recs = [r for r in recs if r.name in want or r.cls in want]
        if not recs:
            sys.exit(f"error: --only {a.only}: no such recording or class")
    if a.list:
        for r in recs:
            print(f"{r.name:40s} {r.cls:36s} truth={r.truth} opt={r.optional} snr={r.snr}")
        return 0
    a.out.mkdir(parents=True, exist_ok=True)
    work = Path(tempfile.mkdtemp(prefix="heldout5_"))
    try:
        with ThreadPoolExecutor(max_workers=min(a.jobs, 2)) as ex:
            results = list(ex.map(lambda r: run_one(r, work), recs))
        if a.keep:
            a.keep.mkdir(parents=True, exist_ok=True)
            for f in work.glob("*.csv"):
                shutil.copy(f, a.keep / f.name)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    for r in results:
        r["outcome"] = score(r)
    report(results, a, time.time() - t0)
    return 0


def fmt_truth(t):
    return t if isinstance(t, str) else ("+".join(t) if t else "clean")


def report(results, a, elapsed):
    print(f"\n{'name':38s} {'truth':40s} {'snr':>6s} {'verdict':11s} {'named':36s} amb  outcome")
    for r in results:
        snr = "" if r["snr"] is None else f"{r['snr']:.1f}"
        named = "+".join(r.get("named") or []) or "-"
        print(f"{r['name']:38s} {fmt_truth(r['truth'])[:40]:40s} {snr:>6s} {str(r.get('verdict', 'exit ' + str(r['exit']))):11s} "
              f"{named[:36]:36s} {'y' if r.get('ambiguous') else 'n'}    {r['outcome']}")
    # per-class table
    classes = {}
    for r in results:
        classes.setdefault(r["class"], []).append(r["outcome"])
    print("\nper class:")
    for c, outs in classes.items():
        cnt = {}
        for o in outs:
            cnt[o] = cnt.get(o, 0) + 1
        print(f"  {c:40s} n={len(outs):3d}  " + ", ".join(f"{k} {v}" for k, v in sorted(cnt.items())))
    # targets
    # refusals (exit 2) are counted apart, not in the targets' denominators; crashes count as misses
    scored = [r for r in results if r["outcome"] != "refused" and r["class"] != "bad_input"]
    clean = [r for r in scored if isinstance(r["truth"], list) and not r["truth"]]
    cat = [r for r in scored if isinstance(r["truth"], list) and r["truth"] and (r["snr"] or 0) >= 3]
    ooc = [r for r in scored if isinstance(r["truth"], str)]
    bad = [r for r in results if r["class"] == "bad_input"]
    crashes = [r for r in results if r["outcome"] == "crash"]
    refused = [r for r in results if r["outcome"] == "refused"]

    def frac(xs, pred):
        return (sum(1 for x in xs if pred(x)), len(xs))

    tg = []
    k, n = frac(clean, lambda r: r["outcome"] in ("false_alarm", "crash"))
    tg.append(("clean: false alarms <= 5 %", k, n, n == 0 or k / n <= 0.05))
    for sub, lab in [("white", lambda r: "ar1" not in r["class"]), ("coloured", lambda r: "ar1" in r["class"])]:
        xs = [r for r in clean if lab(r)]
        k2, n2 = frac(xs, lambda r: r["outcome"] in ("false_alarm", "crash"))
        tg.append((f"  clean {sub}: false alarms <= 5 %", k2, n2, n2 == 0 or k2 / n2 <= 0.05))
    k, n = frac(cat, lambda r: r["outcome"] in ("exact", "primary_only"))
    tg.append(("in catalogue: primary named >= 95 %", k, n, n and k / n >= 0.95))
    k, n = frac(cat, lambda r: r["outcome"] == "exact")
    tg.append(("in catalogue: exact set >= 90 %", k, n, n and k / n >= 0.90))
    k, n = frac(ooc, lambda r: r["outcome"] == "ooc_ok")
    tg.append(("out of catalogue: unexplained or ambiguous >= 80 %", k, n, n and k / n >= 0.80))
    k, n = frac(ooc, lambda r: r["outcome"] == "ooc_wrong_named")
    tg.append(("out of catalogue: confident wrong name <= 10 %", k, n, n and k / n <= 0.10))
    k, n = frac(bad, lambda r: r["outcome"] == "bad_ok")
    tg.append(("bad input: exit 2 with one line", k, n, k == n))
    print("\ntargets:")
    for name, k, n, ok in tg:
        print(f"  {('PASS' if ok else 'MISS') if n else 'n/a '}  {name:52s} {k}/{n}")
    print(f"\ncrashes: {len(crashes)}  refusals: {len(refused)}  ({', '.join(r['name'] for r in crashes + refused)})")
    print(f"elapsed {elapsed:.1f} s, seed {a.seed}")
    out = a.out / "heldout5_diagnose.json"
    out.write_text(json.dumps({"seed": a.seed, "targets": [{"target": t[0].strip(), "k": t[1], "n": t[2],
                                                               "pass": bool(t[3])} for t in tg],
                               "results": results}, indent=1, default=float))
    print(f"wrote {out}")


def check_geometry():
    """cross-check the ring geometry this file assumes with the tool's own CLI (strainwave analytic)."""
    with tempfile.TemporaryDirectory() as d:
        for ratio in (0.012, 0.05):
            p = Path(d) / "p.toml"
            p.write_text(f"[ewg_drive]\nrim_thickness_ratio = {ratio}\n")
            out = subprocess.run([str(EXE), "analytic", "--params", str(p), "--json"], capture_output=True,
                                 text=True, env=dict(os.environ, OMP_NUM_THREADS="1"))
            if out.returncode != 0:
                raise SystemExit("strainwave analytic failed: " + out.stderr[-300:])
            g = json.loads(out.stdout)["seed003"]["geometry"]
            rg = Ring(ratio)
            if abs(g["r_m_mm"] / rg.r - 1) > 1e-9 or abs(g["I_mm4"] / rg.I - 1) > 1e-9:
                raise SystemExit(f"ring geometry differs from the tool's: r_m {g['r_m_mm']} vs {rg.r}, "
                                 f"I {g['I_mm4']} vs {rg.I}")
    print("  geometry ok  r_m and I agree with `strainwave analytic` for rim ratios 0.012, 0.05")


if __name__ == "__main__":
    sys.exit(main())
