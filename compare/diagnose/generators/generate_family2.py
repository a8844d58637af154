"""Family-2 concealed recordings for `strainwave benchmark-diagnose --family 2`.

Written from physics independent of the catalogue's model forms and of family 1 (see family2_*.py):
Bouc-Wen / play-operator / Preisach friction, smooth sinh and power-law stiffening, a Hertzian
dead-zone backlash, Ramberg-Osgood rings with Masing unloading, a crack closing over a load range;
coloured measurement noise (AR(1) up to rho = 0.95, low-pass filtered, random walk), drift,
quantisation; and physics outside the catalogue (viscoelastic loops, creep under a hold, clipping,
saturation, stick-slip, a lagging channel, spliced specimens, re-clamping, a ripple in time, warm-up
drift). The truth is returned next to the file text (``Concealed``), never inside it.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from strainwave.compare.diagnose.generators import family2_elastic as fe
from strainwave.compare.diagnose.generators import family2_hysteresis as fh
from strainwave.compare.diagnose.generators import family2_outside as fo
from strainwave.compare.diagnose.generators import family2_sensors as fs
from strainwave.compare.diagnose.baseline import ring_geometry, torsion_compliance
from strainwave.compare.diagnose.generators.cha import ARCMIN, ChaRow
from strainwave.compare.diagnose.generators.concealed import Concealed, projected_peak, weakest_peak
from strainwave.compare.diagnose.generators.loop_metrics import measure_loop, recorded_loss
from strainwave.compare.diagnose.recording import RecordingKind, format_recording

UNCERTAINTY = 0.02
COLOURED = ("ar1", "lowpass", "random_walk")
IN_CATALOGUE = {
    "bouc_wen": ("hysteresis",), "play_operators": ("hysteresis",), "preisach": ("hysteresis",),
    "sinh_stiffening": ("nonlinear_stiffness",), "power_stiffening": ("nonlinear_stiffness",),
    "hertz_backlash": ("lost_motion",), "gradual_crack": ("crack_closure",), "ramberg_osgood": ("plasticity",),
    "power_stiffening+bouc_wen": ("nonlinear_stiffness", "hysteresis"),
    "hertz_backlash+play_operators": ("lost_motion", "hysteresis"),
}
CLEAN = ("clean_white", "clean_coloured")
OUT_OF_CATALOGUE = ("viscoelastic", "creep_hold", "clipping", "saturation", "stick_slip", "channel_lag",
                    "spliced", "reclamped", "ripple_time", "warmup_drift")
RING_CAPABLE = ("clean_white", "clean_coloured", "clipping", "channel_lag", "spliced", "reclamped",
                "ripple_time", "warmup_drift")
CLASSES = CLEAN + tuple(IN_CATALOGUE) + OUT_OF_CATALOGUE


def _log_uniform(rng, lo: float, hi: float) -> float:
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


def _path(knots: list[float], n: int) -> np.ndarray:
    s = np.linspace(0.0, len(knots) - 1, n)
    return np.interp(s, np.arange(len(knots)), knots)


def _torque_path(rng, n: int, shape: str | None = None) -> np.ndarray:
    """Normalised torque (max |u| = 1): triangles, sines, or a half-amplitude cycle before full ones."""
    shape = shape or str(rng.choice(["triangle", "sine", "growing"]))
    cycles = int(rng.integers(1, 4))
    if shape == "sine":
        return np.sin(2.0 * math.pi * cycles * np.linspace(0.0, 1.0, n))
    if shape == "growing":
        return _path([0.0, 0.5, -0.5] + [1.0, -1.0] * cycles + [0.0], n)
    return _path([0.0] + [1.0, -1.0] * cycles + ([1.0, 0.0] if rng.random() < 0.5 else [0.0]), n)


def _ring_path(rng, n: int) -> np.ndarray:
    choice = int(rng.integers(0, 3))
    knots = ([0.0, 1.0, 0.0], [0.0, 0.6, 0.05, 1.0, 0.0], [0.0, 1.0, 0.0, 1.0, 0.0])[choice]
    return _path(knots, n)


def _noise_kind(rng, cls: str) -> str:
    if cls == "clean_white":
        return "white"
    if cls == "clean_coloured" or rng.random() < 0.5:
        return str(rng.choice(COLOURED))
    return "white"


def _noise(rng, n: int, sigma: float, kind: str) -> np.ndarray:
    return fs.coloured_noise(rng, n, sigma, kind, rho=rng.uniform(0.5, 0.95), fc=rng.uniform(0.05, 0.3),
                             wander=rng.uniform(0.3, 0.8))


def _scaled_loop(law, T: np.ndarray, target_loss_rad: float):
    """The law's loop on T with its secant compliance removed, its steady +/- max|T| width scaled to
    ``target_loss_rad``.

    Returns (effect, loss_rad, energy_Nmm_rad): the loss is the width the recording itself contains, on its
    last full-scale cycle (loop_metrics.recorded_loss; a Bouc-Wen joint's first cycle is wider than its steady
    one), the steady width where the path holds no full-scale cycle; the energy is the steady cycle's."""
    A = float(np.max(np.abs(T)))
    m = measure_loop(law, A)
    scale = target_loss_rad / m.loss_rad
    raw = law(T)
    recorded = recorded_loss(T, raw)
    loss = target_loss_rad if recorded is None else scale * recorded
    return scale * (raw - raw[0] - m.secant_compliance * T), loss, scale * m.energy_Nmm_rad


def _hysteresis(name: str, rng, T: np.ndarray, c0: float, X: float, Y: float):
    loss = Y * rng.uniform(0.005, 0.08)
    if name == "bouc_wen":
        beta = rng.uniform(0.5, 0.9)
        gamma = rng.uniform(-0.9 * beta, beta)
        friction = X * rng.uniform(0.05, 0.3)
        k_e = 1.0 / c0
        phi_y = friction / (k_e * rng.uniform(1.0, 10.0))
        n_bw = rng.uniform(1.0, 2.5)
        law = lambda x: fh.bouc_wen_twist(x, k_e, friction, phi_y, beta=beta, gamma=gamma, n=n_bw)
    elif name == "play_operators":
        m = int(rng.integers(8, 26))
        R = X * rng.uniform(0.1, 0.6)
        r = np.linspace(0.0, R, m)
        w = c0 * np.exp(-r / (R * rng.uniform(0.2, 1.0)))
        law = lambda x: fh.play_sum_twist(x, r, w)
    elif name == "preisach":
        kw = dict(coercive=rng.uniform(0.1, 0.5), coercive_spread=rng.uniform(0.3, 0.8),
                  bias_spread=rng.uniform(0.1, 0.5))
        law = lambda x: fh.preisach_twist(x, X, **kw) * c0 * X
    else:
        raise ValueError(name)
    return _scaled_loop(law, T, loss)


def _torsion_effect(name: str, rng, T: np.ndarray, c: float, c0: float, X: float, Y: float):
    """Additional twist beyond c T for one in-catalogue family-2 law; (effect, loss, energy)."""
    K1 = 1.0 / c
    if name in ("bouc_wen", "play_operators", "preisach"):
        return _hysteresis(name, rng, T, c0, X, Y)
    if name == "sinh_stiffening":
        ratio = rng.uniform(1.3, 3.0)                      # tangent stiffness at full scale / K1
        phi0 = X / (K1 * math.sqrt(ratio ** 2 - 1.0))
        return fe.sinh_stiffening_twist(T, K1, phi0) - T / K1, None, None
    if name == "power_stiffening":
        ratio, q = rng.uniform(1.3, 3.0), rng.uniform(0.7, 2.5)
        T_s = X / (ratio - 1.0) ** (1.0 / q)
        return fe.power_stiffening_twist(T, K1, T_s, q) - T / K1, None, None
    if name == "hertz_backlash":
        gap = 0.5 * Y * rng.uniform(0.005, 0.08)
        k_w = X * rng.uniform(0.005, 0.05) / gap            # the clearance is crossed over 0.5-5 % of full scale
        k_L = 1.0 / (c * rng.uniform(0.05, 0.3))
        d_h = X * rng.uniform(0.005, 0.04) / k_L
        centre = X * rng.uniform(-0.05, 0.05)
        phi = fe.hertz_backlash_twist(T, gap, k_w, k_L, d_h, centre)
        return phi - T / (k_w + k_L), None, None
    if name == "gradual_crack":
        return (fe.gradual_crack_twist(T, c0 * rng.uniform(0.05, 0.4), X * rng.uniform(0.02, 0.3),
                                       rng.uniform(1.0, 3.0), int(rng.choice([-1, 1]))), None, None)
    raise ValueError(name)


def _finish(rng, cls, kind, specimen, T, y_true, effect, snr, noise_kind, *, Y, t_s, with_time, params=None,
            truth=(), label="", loss=None, energy=None, load_transform=None, response_transform=None,
            uncertainty=UNCERTAINTY, parts=None) -> Concealed:
    """Scale the noise to the signal, add drift, offsets, noise, quantisation, sensor artefacts; format."""
    n = len(T)
    t = (t_s - t_s[0]) / (t_s[-1] - t_s[0])
    X = float(np.max(np.abs(T)))
    if effect is None:
        peak = 0.0
        sigma = Y * 10.0 ** rng.uniform(-3.5, -2.0)
    else:
        peak = projected_peak(T / X, t, effect / Y, uncertainty) * Y
        sigma = peak / snr
    q = sigma * rng.uniform(0.0, 1.5)
    sigma_n = math.sqrt(max(sigma ** 2 - q ** 2 / 12.0, 0.25 * sigma ** 2))
    drift = rng.uniform(-5.0, 5.0) * sigma * t + rng.uniform(-50.0, 50.0) * sigma
    y = y_true + drift + _noise(rng, n, sigma_n, noise_kind)
    if response_transform is not None:
        y = response_transform(y)
    y = fs.quantise(y, q)
    T_meas = T + X * (2e-4 * rng.standard_normal(n) + rng.uniform(-0.003, 0.003))
    if load_transform is not None:
        T_meas = load_transform(T_meas)
    noise_std = math.sqrt(sigma_n ** 2 + q ** 2 / 12.0)
    if parts is not None:      # several effects: scored by the weakest (the noise stays set by the sum)
        peak = weakest_peak(T / X, t, [p / Y for p in parts], uncertainty) * Y
    rk = RecordingKind.TORSION if kind == "torsion" else RecordingKind.RING_COMPRESSION
    text = format_recording(rk, specimen, T_meas, y, baseline_uncertainty=uncertainty, params=params,
                            time_s=t_s if with_time else None)
    return Concealed(cls, text, tuple(truth), peak / noise_std if effect is not None else 0.0, kind, family=2,
                     noise=noise_kind, out_of_catalogue=label,
                     loss_arcmin=None if loss is None else loss / ARCMIN, energy_Nmm_rad=energy)


def generate(cls: str, rng: np.random.Generator, params, *, rows: tuple[int, int] = (300, 2000)) -> Concealed:
    """One family-2 recording of class ``cls`` (see CLASSES)."""
    if cls not in CLASSES:
        raise ValueError(f"class {cls!r}: must be one of {CLASSES}")
    n = int(rng.integers(rows[0], rows[1] + 1))
    noise_kind = _noise_kind(rng, cls)
    if cls == "ramberg_osgood" or (cls in RING_CAPABLE and rng.random() < 0.3):
        return _ring(cls, rng, params, n, noise_kind)
    return _torsion(cls, rng, params, n, noise_kind)


def _stiffness_error(rng) -> float:
    return float(np.clip(rng.normal(0.0, 0.5 * UNCERTAINTY), -UNCERTAINTY, UNCERTAINTY))


def _torsion(cls, rng, params, n, noise_kind) -> Concealed:
    specimen = str(rng.choice(["output_shaft", "flexspline_cup", "gear"]))
    c0, _ = torsion_compliance(specimen, params)
    c = c0 * (1.0 + _stiffness_error(rng))
    X = _log_uniform(rng, 2e5, 2e6)
    Y = c0 * X
    fs_hz = rng.uniform(5.0, 50.0)
    with_time = bool(rng.random() < 0.5)
    t_s = np.arange(n) / fs_hz
    snr = _log_uniform(rng, 1.5, 40.0) if cls in IN_CATALOGUE else _log_uniform(rng, 4.0, 40.0)
    common = dict(Y=Y, t_s=t_s, with_time=with_time)
    if cls in CLEAN:
        u = _torque_path(rng, n)
        T = u * X
        return _finish(rng, cls, "torsion", specimen, T, c * T, None, 0.0, noise_kind, **common)
    if cls in IN_CATALOGUE:
        u = _torque_path(rng, n)
        T = u * X
        effect = np.zeros(n)
        loss = energy = None
        parts = []
        for part in cls.split("+"):
            e, l, en = _torsion_effect(part, rng, T, c, c0, X, Y)
            effect += e
            parts.append(e)
            if l is not None:
                loss, energy = l, en
        return _finish(rng, cls, "torsion", specimen, T, c * T + effect, effect + (c - c0) * T, snr, noise_kind,
                       truth=IN_CATALOGUE[cls], loss=loss, energy=energy, parts=parts if len(parts) > 1 else None,
                       **common)
    return _outside_torsion(cls, rng, specimen, n, c, c0, X, Y, snr, noise_kind, fs_hz, with_time)


def _outside_torsion(cls, rng, specimen, n, c, c0, X, Y, snr, noise_kind, fs_hz, with_time) -> Concealed:
    t_s = np.arange(n) / fs_hz
    kw = dict(Y=Y, label=cls)
    if cls == "viscoelastic":
        # one slow and one fast cycle at the same sampling rate: the loop width depends on the rate
        slow_leg = max(int(n / 5), 10)
        fast_leg = max(int(slow_leg / 4), 5)
        legs = [slow_leg] * 4 + [fast_leg] * 4
        if rng.random() < 0.5:
            legs = legs[4:] + legs[:4]
        knots = [0.0, 1.0, 0.0, -1.0, 0.0] * 2
        u = np.concatenate([np.linspace(knots[i], knots[i + 1], m, endpoint=False) for i, m in enumerate(legs)]
                           + [np.array([0.0])])
        n = len(u)
        t_s = np.arange(n) / fs_hz
        T = u * X
        J1 = c0 * rng.uniform(0.05, 0.3)
        tau = (fast_leg / fs_hz) * rng.uniform(0.2, 1.0)
        phi = fo.zener_twist(T, t_s, c - J1, J1, tau)
        return _finish(rng, cls, "torsion", specimen, T, phi, phi - c0 * T, snr, noise_kind, t_s=t_s,
                       with_time=True, **kw)
    if cls == "creep_hold":
        hold = int(n * rng.uniform(0.12, 0.25))
        ramp = max(int((n - 2 * hold) / 4), 10)
        u = np.concatenate([np.linspace(0, 1, ramp, endpoint=False), np.ones(hold),
                            np.linspace(1, -1, 2 * ramp, endpoint=False), -np.ones(hold),
                            np.linspace(-1, 0, ramp)])
        n = len(u)
        t_s = np.arange(n) / fs_hz
        T = u * X
        amp = Y * rng.uniform(0.01, 0.06)
        tau = (hold / fs_hz) * rng.uniform(0.02, 0.2)
        h1 = (t_s[ramp], t_s[ramp + hold - 1])
        h2 = (t_s[3 * ramp + hold], t_s[3 * ramp + 2 * hold - 1])
        creep = fo.log_creep(t_s, *h1, amp, tau) - fo.log_creep(t_s, *h2, amp, tau)
        return _finish(rng, cls, "torsion", specimen, T, c * T + creep, creep + (c - c0) * T, snr, noise_kind,
                       t_s=t_s, with_time=True, **kw)
    u = _torque_path(rng, n, "sine" if cls == "channel_lag" else None)
    T = u * X
    y = c * T
    common = dict(t_s=t_s, with_time=with_time, **kw)
    if cls == "saturation":
        squeeze = rng.uniform(0.03, 0.15)            # the recorded peak torque is this much low
        x = brentq(lambda v: math.tanh(v) / v - (1.0 - squeeze), 1e-6, 10.0)
        full = X / x
        effect = c * (T - fs.soft_saturate(T, full))
        return _finish(rng, cls, "torsion", specimen, T, y, effect, snr, noise_kind,
                       load_transform=lambda Tm: fs.soft_saturate(Tm, full), **common)
    if cls == "stick_slip":
        step = X * rng.uniform(0.06, 0.2)
        slip = Y * rng.uniform(0.005, 0.04)
        effect = fo.stick_slip_twist(T, slip, step) - (slip / step) * T
        return _finish(rng, cls, "torsion", specimen, T, y + effect, effect + (c - c0) * T, snr, noise_kind,
                       **common)
    return _artefact(cls, rng, "torsion", specimen, T, y, c, c0, snr, noise_kind, **common)


def _artefact(cls, rng, kind, specimen, T, y, c, c0, snr, noise_kind, *, Y, t_s, with_time, label,
              params=None) -> Concealed:
    """Sensor and handling artefacts that apply to either test kind."""
    n = len(T)
    t = np.linspace(0.0, 1.0, n)
    common = dict(Y=Y, t_s=t_s, with_time=with_time, label=label, params=params)
    if cls == "clipping":
        top = float(np.max(np.abs(y)))
        full = top * rng.uniform(0.8, 0.95)
        effect = fs.clip(y, -full, full) - y
        return _finish(rng, cls, kind, specimen, T, y, effect + (c - c0) * T, snr, noise_kind,
                       response_transform=lambda ym: fs.clip(ym, -full, full), **common)
    if cls == "channel_lag":
        lag = int(rng.integers(2, 7))
        effect = fs.delay(y, lag) - y
        return _finish(rng, cls, kind, specimen, T, fs.delay(y, lag), effect + (c - c0) * T, snr, noise_kind,
                       **common)
    # splice and re-clamp happen where the load is least near the middle of the test: a zero crossing of a
    # two-sided path, the unloaded point between two ring cycles, or (one ring cycle) the middle itself.
    # The first version looked only for sign changes, found the ring's end points and spliced nothing.
    interior = np.arange(n // 10, n - n // 10)
    zero = interior[np.diff(np.sign(T))[interior - 1] != 0] if kind == "torsion" else \
        interior[np.abs(T[interior]) <= 0.1 * float(np.max(np.abs(T)))]
    mid = int(zero[np.argmin(np.abs(zero - n // 2))]) + 1 if len(zero) else n // 2
    after = np.arange(n) >= mid
    if cls == "spliced":
        change = rng.choice([-1, 1]) * rng.uniform(0.1, 0.3)
        effect = after * (change * c * T + Y * rng.uniform(-0.05, 0.05))
    elif cls == "reclamped":
        effect = after * (rng.choice([-1, 1]) * Y * rng.uniform(0.01, 0.05) + rng.uniform(-0.03, 0.03) * c * T)
    elif cls == "ripple_time":
        period = rng.uniform(12.0, 150.0) / n
        effect = fo.ripple(t, Y * rng.uniform(0.005, 0.05), period, rng.uniform(0.0, 2.0 * math.pi))
    elif cls == "warmup_drift":
        effect = fo.warm_up(t, Y * rng.choice([-1, 1]) * rng.uniform(0.01, 0.1), rng.uniform(0.08, 0.3))
    else:
        raise ValueError(cls)
    return _finish(rng, cls, kind, specimen, T, y + effect, effect + (c - c0) * T, snr, noise_kind, **common)


def _ring(cls, rng, params, n, noise_kind) -> Concealed:
    ratio = float(rng.uniform(0.02, 0.05)) if cls == "ramberg_osgood" else float(rng.uniform(0.01, 0.015))
    p = params.with_value("ewg_drive.rim_thickness_ratio", ratio)
    g = ring_geometry(p)
    R, h, b = g["r_m_mm"], g["rim_thickness_mm"], g["face_width_mm"]
    c0 = g["thin_compliance_mm_per_N"]
    c = c0 * (1.0 + _stiffness_error(rng))
    overrides = {"ewg_drive": {"rim_thickness_ratio": ratio}}
    u = _ring_path(rng, n)
    fs_hz = rng.uniform(5.0, 50.0)
    t_s = np.arange(n) / fs_hz
    with_time = bool(rng.random() < 0.5)
    if cls == "ramberg_osgood":
        F_y = math.pi * rng.uniform(400.0, 1200.0) * b * h ** 2 / (6.0 * R)   # first yield, M = F R / pi
        X = F_y * rng.uniform(1.1, 1.6)
        n_ro = rng.uniform(5.0, 15.0)
        alpha = rng.uniform(0.03, 0.3) / (X / F_y) ** (n_ro - 1.0)      # plastic share at the peak load
        F = u * X
        d = fe.ramberg_osgood_masing(F, c, F_y, alpha, n_ro)
        return _finish(rng, cls, "ring_compression", "ewg_ring", F, d, d - c0 * F, _log_uniform(rng, 1.5, 40.0),
                       noise_kind, Y=c0 * X, t_s=t_s, with_time=with_time, params=overrides,
                       truth=IN_CATALOGUE[cls])
    X = R * 0.02 / c0
    F = u * X
    Y = c0 * X
    if cls in CLEAN:
        return _finish(rng, cls, "ring_compression", "ewg_ring", F, c * F, None, 0.0, noise_kind, Y=Y, t_s=t_s,
                       with_time=with_time, params=overrides)
    return _artefact(cls, rng, "ring_compression", "ewg_ring", F, c * F, c, c0, _log_uniform(rng, 4.0, 40.0),
                     noise_kind, Y=Y, t_s=t_s, with_time=with_time, label=cls, params=overrides)


def cha_recording(row: ChaRow, *, loop: bool, rng: np.random.Generator, n: int = 2000) -> Concealed:
    """The CHA table's curve (real data) with a family-2 Bouc-Wen loop and coloured encoder noise.

    Sine torque to 1.5-2 T2 (all three slopes seen); the given linear stiffness is K1 off by ~10 %
    (what a user's linear simulation would give) with the whole-gear uncertainty 0.3."""
    T = rng.uniform(1.5, 2.0) * row.T2_Nmm * np.sin(2.0 * math.pi * 2 * np.linspace(0.0, 1.0, n))
    twist = row.twist_rad(T)
    loss = energy = None
    if loop:
        target = rng.uniform(0.3, 0.9) * row.hysteresis_limit_arcmin * ARCMIN
        friction = float(np.max(np.abs(T))) * rng.uniform(0.05, 0.2)
        k = row.K1_Nmm_per_rad
        phi_y = friction / (k * rng.uniform(1.0, 5.0))
        law = lambda x: fh.bouc_wen_twist(x, k, friction, phi_y, beta=0.7, gamma=0.1, n=1.5)
        effect, loss, energy = _scaled_loop(law, T, target)
        twist = twist + effect
    step = 2.0 * math.pi / 2 ** int(rng.choice([19, 20]))
    twist = twist + fs.coloured_noise(rng, n, 0.5 * step, "ar1", rho=rng.uniform(0.5, 0.9)) + 3.0 * step
    twist = fs.quantise(twist, step)
    T_meas = T + 5e-4 * float(np.max(np.abs(T))) * rng.standard_normal(n)
    given = row.K1_Nmm_per_rad * (1.0 + float(np.clip(rng.normal(0.0, 0.1), -0.2, 0.2)))
    text = format_recording(RecordingKind.TORSION, "gear", T_meas, twist, baseline_uncertainty=0.3,
                            baseline_stiffness=given, description=f"CHA-{row.size} ratio {row.ratio}")
    truth = ("nonlinear_stiffness", "hysteresis") if loop else ("nonlinear_stiffness",)
    return Concealed(f"cha{'+loop' if loop else ''}", text, truth, 0.0, "torsion", family=2, noise="ar1",
                     loss_arcmin=None if loss is None else loss / ARCMIN, energy_Nmm_rad=energy,
                     stiffness_Nmm_per_rad=(row.K1_Nmm_per_rad, row.K2_Nmm_per_rad, row.K3_Nmm_per_rad))


__all__ = ["CLASSES", "CLEAN", "IN_CATALOGUE", "OUT_OF_CATALOGUE", "cha_recording", "generate"]
