"""A flexspline tooth-root crack sized by the channel a rig sees: the twist ripple as the cracked tooth passes
the mesh (issue 48 item 7).

The wave generator's two lobes sweep the flexspline at (1 + dZ/Z_f) of the input speed relative to it, so the
cracked tooth meets a loaded zone 2 (1 + dZ/Z_f) times per input revolution (tooth_mesh.crack_orders): 2.02 on the
default gear, not the 2 of anything fixed to the wave generator (its ovality, the cup's breathing). Each pass adds
a short pulse of twist that grows with the torque (fea/tooth_crack_curve.py: the FE mesh with the cracked tooth's
own added compliance).

Reading (``read_ripple``): the twist of a drive turning under a varying torque is fitted by least squares with
the crack's order and its harmonics 1..HARMONICS times the torque (the crack) and alone (a tooth's pitch or
profile error draws the same order at every load), beside nuisances: a cubic in the torque, a quadratic drift,
the wave generator's harmonics 1..4 alone and times the torque, and a loop's branch term where the torque
reverses. The pulse's shape is not assumed: the reading is the amplitude of the torque-scaled fundamental
(rad/(N mm)); its standard error from the residual, widened by the residual's lag-1 correlation. A crack is seen
where the torque-scaled harmonics together stand above the noise (Wald test, p < DETECT_P).

The curve (``curve_for``): the FE's twist change over tooth 0's positions at each torque of the ramp, its
fundamental over one pass period, projected on the same columns at the recording's own torques (the contact is
non-linear: the crack's ripple per unit torque is not the same at half and at full torque), on each of the study's
three meshes, so each point carries its GCI, and the trapezoidal rule's error over the positions. A depth is
given with crack_sizing's k = 2 interval, "not on the curve" beyond its deepest point, or "not sized" where the
curve's meshes disagree by more than MAX_CURVE_GCI (decision 067).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Mapping

import numpy as np

from strainwave.compare.diagnose.crack_sizing import COVERAGE_K, DeltaCurve, size_crack

__all__ = ["COMPONENT", "UNIT", "ToothCrackReading", "crack_order", "read_ripple", "curve_for", "fundamental",
           "mesh_curve_record", "size_tooth_crack", "tooth_ratios"]

COMPONENT = "flexspline tooth root (mesh)"
UNIT = "rad/(N*mm)"
HARMONICS = 12             # of the crack's order: the pulse (~7 of the 180 deg between passes) is not assumed
WG_HARMONICS = (1, 2, 3, 4)
DETECT_P = 1e-3            # the torque-scaled harmonics' Wald test: a false alarm in a thousand clean drives
MIN_TORQUE_SPREAD = 0.3    # of the peak torque: below it a crack and a tooth's pitch error are not told apart
SAMPLES_PER_CYCLE = 4.0    # of the highest fitted harmonic, per input revolution
# a curve point whose GCI exceeds this fraction of its value does not know the crack's ripple to within a factor
# of ~2 at k = 2: nothing is sized on it (the study's contact solution is not always mesh-converged: decision 067)
MAX_CURVE_GCI = 0.5


@dataclass(frozen=True)
class ToothCrackReading:
    order_per_input_rev: float
    revolutions: float
    needed_revolutions: float
    ripple: float | None              # the torque-scaled fundamental's amplitude, rad/(N mm)
    sigma: float | None
    chi2: float | None
    dof: int
    p_value: float | None
    pitch_p_value: float | None       # the same order at every load (a tooth's pitch error): its Wald p
    harmonics: int
    one_load: bool                    # the torque spread too little to tell a crack from a pitch error
    reason: str                       # why nothing was read ("" when read)

    @property
    def detected(self) -> bool:
        return self.p_value is not None and self.p_value < DETECT_P

    def line(self) -> str:
        head = f"tooth-crack order {self.order_per_input_rev:.4g} per input revolution"
        if self.ripple is None:
            return f"{head}: not read ({self.reason})"
        body = (f"{head}: ripple {self.ripple:.3g} +/- {self.sigma:.2g} {UNIT} growing with the torque "
                f"(fundamental; Wald chi2 {self.chi2:.3g} on {self.dof}, p = {self.p_value:.2g})")
        if not self.detected:
            return body + ": no tooth-crack signal"
        return body + (": a tooth-root crack's signal" + (
            " (one load: a tooth's pitch error at the same order would read the same, so the depth is an upper "
            "bound)" if self.one_load else ""))

    def to_dict(self) -> dict:
        return {**self.__dict__, "detected": self.detected, "line": self.line()}


def crack_order(params) -> dict:
    """The cracked tooth's passes per input and per output revolution (tooth_mesh.crack_orders)."""
    from strainwave.fea.tooth_mesh import crack_orders
    from strainwave.geometry.mesh_geometry import mesh_geometry
    geo = mesh_geometry(params)
    return crack_orders({"z_f": geo.z_f, "z_c": geo.z_c})


def _branch(torque: np.ndarray) -> np.ndarray | None:
    """+1 loading, -1 unloading, where the torque reverses by more than a tenth of its range; None otherwise."""
    span = float(np.ptp(torque))
    if span <= 0:
        return None
    d = np.sign(np.gradient(torque))
    if np.count_nonzero(d > 0) < 0.1 * len(torque) or np.count_nonzero(d < 0) < 0.1 * len(torque):
        return None
    d[d == 0] = 1.0
    return d


def _columns(u: np.ndarray, s: np.ndarray, angle: np.ndarray, order: float, J: int, pitch: bool):
    """The design: nuisances first, then crack harmonics times the load (and alone when ``pitch``)."""
    cols = [np.ones_like(u), u, u ** 2, u ** 3, s, s ** 2]
    d = _branch(u)
    if d is not None:
        cols += [d, d * u, d * u ** 2]
    for k in WG_HARMONICS:
        for f in (np.cos, np.sin):
            cols += [f(k * angle), u * f(k * angle)]
    crack, plain = [], []
    for j in range(1, J + 1):
        phase = j * order * angle
        crack += [u * np.cos(phase), u * np.sin(phase)]
        plain += [np.cos(phase), np.sin(phase)] if pitch else []
    nuisance = _independent(np.column_stack(cols))     # a constant torque or time leaves some of them dependent
    n0 = nuisance.shape[1]
    X = np.column_stack([nuisance, *crack, *plain])
    return X, slice(n0, n0 + len(crack)), slice(n0 + len(crack), X.shape[1])


def _independent(N: np.ndarray) -> np.ndarray:
    """The columns of ``N`` a pivoted QR finds independent (relative tolerance 1e-9 on unit columns)."""
    from scipy.linalg import qr
    norms = np.linalg.norm(N, axis=0)
    keep = norms > 0
    N = N[:, keep] / norms[keep]
    R, piv = qr(N, mode="r", pivoting=True)
    d = np.abs(np.diag(R[0] if isinstance(R, tuple) else R))
    return N[:, np.sort(piv[:int(np.count_nonzero(d > 1e-9 * d[0]))])]


def _fit(X: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """OLS coefficients and their covariance, the residual's variance widened by its lag-1 correlation."""
    from scipy.linalg import cho_factor, cho_solve
    scale = np.linalg.norm(X, axis=0)                  # unit columns: the normal equations stay well conditioned
    Xs = X / scale
    G = cho_factor(Xs.T @ Xs)
    beta = cho_solve(G, Xs.T @ y)
    r = y - Xs @ beta
    s2 = float(r @ r) / max(len(y) - X.shape[1], 1)
    rho = float(np.clip(np.dot(r[1:], r[:-1]) / max(float(r @ r), 1e-300), 0.0, 0.99))
    cov = s2 * (1 + rho) / (1 - rho) * cho_solve(G, np.eye(X.shape[1]))
    return beta / scale, cov / np.outer(scale, scale)


def _wald(beta: np.ndarray, cov: np.ndarray, sel: slice) -> tuple[float, int, float]:
    from scipy.stats import chi2
    b, C = beta[sel], cov[sel, sel]
    if b.size == 0:
        return 0.0, 0, 1.0
    stat = float(b @ np.linalg.solve(C, b))
    return stat, b.size, float(chi2.sf(stat, b.size))


def read_ripple(torque_Nmm, twist_rad, angle_rad, order: float, time_s=None) -> ToothCrackReading:
    """The torque-scaled ripple at the crack's ``order`` (per input revolution) in a drive's recording."""
    T, y, th = (np.asarray(v, float) for v in (torque_Nmm, twist_rad, angle_rad))
    revs = float(np.ptp(th)) / (2 * math.pi)
    need = 1.0 / abs(order - 2.0)        # the crack's fundamental one cycle off the WG's 2x over the record
    per_rev = len(T) / max(revs, 1e-12)
    J = min(HARMONICS, int(per_rev / (SAMPLES_PER_CYCLE * order)))
    empty = dict(ripple=None, sigma=None, chi2=None, dof=0, p_value=None, pitch_p_value=None, harmonics=max(J, 0))
    if revs < need:
        return ToothCrackReading(order, revs, need, **empty, one_load=False, reason=(
            f"the input turned {revs:.3g} revolutions; telling the crack's order from the wave generator's 2x takes "
            f">= {need:.3g}"))
    if J < 1:
        return ToothCrackReading(order, revs, need, **empty, one_load=False, reason=(
            f"{per_rev:.3g} samples per input revolution; the crack's order needs >= {SAMPLES_PER_CYCLE * order:.3g}"))
    peak = float(np.max(np.abs(T)))
    if not peak > 0:
        return ToothCrackReading(order, revs, need, **empty, one_load=False, reason="the torque is zero throughout")
    u = T / peak
    one_load = float(np.ptp(T)) < MIN_TORQUE_SPREAD * peak
    t = np.arange(len(T), dtype=float) if time_s is None else np.asarray(time_s, float)
    s = (t - t.mean()) / max(float(np.ptp(t)), 1e-300)
    X, crack, plain = _columns(u, s, th, order, J, pitch=not one_load)
    try:
        beta, cov = _fit(X, y)
    except np.linalg.LinAlgError:
        return ToothCrackReading(order, revs, need, **empty, one_load=one_load, reason=(
            "the crack's harmonics cannot be told from the load, the drift and the wave generator's harmonics in this "
            "recording"))
    chi, dof, p = _wald(beta, cov, crack)
    pitch_p = _wald(beta, cov, plain)[2] if not one_load else None
    a, b = beta[crack.start], beta[crack.start + 1]
    amp = math.hypot(a, b)
    g = np.array([a, b]) / amp if amp > 0 else np.array([1.0, 0.0])
    sd = math.sqrt(float(g @ cov[crack.start:crack.start + 2, crack.start:crack.start + 2] @ g))
    return ToothCrackReading(order, revs, need, amp / peak, sd / peak, chi, dof, p, pitch_p, J, one_load, "")


def fundamental(change: np.ndarray, phi_rad: np.ndarray, step: int = 1) -> np.ndarray:
    """Complex fundamental (rad) over one pass period (pi of tooth 0's angle phi, dual wave) of the twist change
    sampled at ``phi_rad`` (zero outside: the tooth is out of the loaded zone), per row; trapezoidal rule on
    every ``step``-th position."""
    c, p = np.asarray(change)[..., ::step], np.asarray(phi_rad)[::step]
    return (2.0 / math.pi) * np.trapezoid(c * np.exp(2j * p), p, axis=-1)


def _projected(F: np.ndarray, levels_Nmm: np.ndarray, T: np.ndarray, one_load: bool) -> float:
    """|slope| of the model's fundamental F(T) at the recording's torques on the reading's columns ([1, T] or [T]):
    what the fit of ``read_ripple`` returns for data made of that model (rad/(N mm)). The crack is taken at the root
    in tension under the recording's prevailing torque sign (the FE's +flank under a positive torque, its mirror under
    a negative one); the other sign loads the other flank, under which that root is in compression: the crack closes
    and adds nothing."""
    sign = 1.0 if float(np.mean(T)) >= 0.0 else -1.0
    Tl = np.clip(sign * T, 0.0, levels_Nmm[-1])
    Fi = np.interp(Tl, levels_Nmm, F.real) + 1j * np.interp(Tl, levels_Nmm, F.imag)
    Fi = sign * np.where(sign * T > 0, Fi, 0.0)
    A = T[:, None] if one_load else np.column_stack([np.ones_like(T), T])
    coef, *_ = np.linalg.lstsq(A.astype(complex), Fi, rcond=None)
    return float(abs(coef[-1]))


def curve_for(record: Mapping, torque_Nmm, *, one_load: bool) -> DeltaCurve:
    """The crack curve (rad/(N mm) against depth) as ``read_ripple`` would read it at the recording's torques, each
    point with the GCI of its three meshes and the trapezoidal rule's error over tooth 0's positions."""
    from strainwave.fea.refinement import converged_quantity
    T = np.asarray(torque_Nmm, float)
    levels = np.asarray(record["torque_fractions"]) * record["rated_torque_Nmm"]
    phi = np.asarray(record["phi_rad"])
    values, unc = [], []
    for i, a in enumerate(record["depths_mm"]):
        per_mesh = [_projected(fundamental(m[i]["change_rad"], phi), levels, T, one_load) for m in record["per_mesh"]]
        q = converged_quantity("tooth_crack_ripple_rad_per_Nmm", UNIT, record["sizes_mm"], per_mesh)
        fine = record["per_mesh"][0][i]["change_rad"]
        half = _projected(fundamental(fine, phi, step=2), levels, T, one_load)
        trap = abs(half - per_mesh[0]) / 3.0          # Richardson: the O(h^2) rule's error on the finer grid
        values.append(q.value)
        unc.append(math.hypot(q.uncertainty or 0.0, trap))
    return DeltaCurve(COMPONENT, UNIT, tuple(record["depths_mm"]), tuple(values), tuple(unc),
                      float(record["wall_mm"]), record.get("source", "FEA: tooth-mesh crack curve"))


def tooth_ratios(record: Mapping) -> list[dict]:
    """Per depth: the cracked tooth's own compliance over the sound tooth's (FE, at the major axis's contact
    radius) with the GCI of its three meshes."""
    from strainwave.fea.refinement import converged_quantity
    out = []
    for i, a in enumerate(record["depths_mm"]):
        q = converged_quantity("crack_tooth_compliance_ratio", "1", record["sizes_mm"],
                               [m[i]["tooth_ratio"] for m in record["per_mesh"]])
        out.append({"depth_mm": a, "tooth_compliance_ratio": q.value, "gci": q.uncertainty or 0.0})
    return out


def crack_angles(params) -> list[dict]:
    """The flank pairs with tooth 0 at each of the curve's PHI_DEG (the study's rule: psi = -phi / (1 + dZ/Z_f))."""
    from strainwave.analytic.mesh_engagement import pairs_at
    from strainwave.fea.tooth_crack_curve import PHI_DEG
    from strainwave.geometry.mesh_geometry import mesh_geometry
    geo = mesh_geometry(params)
    return [pairs_at(geo, -p / (1 + (geo.z_c - geo.z_f) / geo.z_f)) for p in np.radians(PHI_DEG)]


def mesh_curve_record(params, cache_dir: Path | None = None, progress: Callable[[str], None] = lambda m: None,
                      *, quick: bool = False) -> dict:
    """The raw FE curve (fea/tooth_crack_curve.curve_points on the study's three meshes), solved on demand and
    cached under ``cache_dir``."""
    from strainwave.analytic.mesh_engagement import study_loads
    from strainwave.cache import ResultCache, case_key
    from strainwave.fea.tooth_crack_curve import curve_points
    cache = ResultCache(Path(cache_dir)) if cache_dir is not None else None
    key = case_key("tooth-crack-curve", {"params": params.to_dict(), "quick": bool(quick)})
    schema = {"depths_mm": list, "per_mesh": list, "sizes_mm": list, "phi_rad": list, "torque_fractions": list,
              "rated_torque_Nmm": (int, float), "wall_mm": (int, float)}
    rec = cache.get(key, schema) if cache else None
    if rec is None:
        progress("tooth-crack curve: the tooth-mesh FE at each crack depth on three meshes (cached with --cache)")
        rec = curve_points(params, study_loads(params, quick=quick)["mesh"], crack_angles(params), quick=quick,
                           progress=progress)
        rec["source"] = (f"FEA: tooth-mesh crack curve ({'quick' if quick else 'full'} meshes h = "
                         f"{', '.join(f'{h:.3g}' for h in rec['sizes_mm'])} mm)")
        if cache:
            cache.put(key, rec)
    return rec


def _sized_lines(reading: ToothCrackReading, curve: DeltaCurve | None) -> tuple[list, list]:
    """The sizes and lines of a detected ripple on ``curve``."""
    if curve is None:
        return [], [f"{COMPONENT}: not sized (no FE curve)"]
    size = size_crack(reading.ripple, reading.sigma, [curve])[0]
    if size.possible:
        gci = curve.relative_uncertainty_at(size.depth_mm)
        if gci > MAX_CURVE_GCI:
            return [], [f"{COMPONENT}: not sized: the FE curve's uncertainty is {gci:.0%} of its ripple near "
                        f"a = {size.depth_mm:.3g} mm (over {MAX_CURVE_GCI:.0%}: its three meshes disagree), so the "
                        "data say a crack is there but not how deep"]
    lines = [size.line()]
    if not size.possible:
        lines.append(f"{COMPONENT}: not on the curve: its deepest crack (a = {curve.depths_mm[-1]:g} mm) ripples "
                     f"{curve.delta[-1]:.3g} {UNIT}, {reading.ripple / curve.delta[-1]:.2g}x less; look for another "
                     "source at this order (a tooth's pitch error, a second cracked tooth)")
    elif reading.one_load:
        lines.append(f"{COMPONENT}: one load, so this depth is an upper bound (a pitch error would add to it)")
    return [size], lines


def size_tooth_crack(load, response, angle, params, *, time_s=None, curve_record: Callable[[], Mapping]) -> dict:
    """The sizing record of a drive's recording on the tooth-crack channel: its reading, and the depth on the FE
    curve (``curve_record()``, called only when the order is readable) or why none."""
    reading = read_ripple(load, response, angle, crack_order(params)["per_input_revolution"], time_s)
    orders = crack_order(params)
    sizes, lines = [], [reading.line() + f" ({orders['per_output_revolution']:.4g} per output revolution)"]
    curve, ratios = None, None
    if reading.ripple is not None:
        try:
            record = curve_record()
            ratios = tooth_ratios(record)
            curve = curve_for(record, load, one_load=reading.one_load)
        except ValueError as exc:        # a curve that does not rise with depth sizes nothing
            lines.append(f"{COMPONENT}: not sized ({exc})")
    if reading.detected:
        sizes, more = _sized_lines(reading, curve)
        lines += more
        if sizes and sizes[0].possible and ratios:
            r = float(np.interp(sizes[0].depth_mm, [q["depth_mm"] for q in ratios],
                                [q["tooth_compliance_ratio"] for q in ratios]))
            lines.append(f"{COMPONENT}: at that depth the cracked tooth is {100 * (r - 1):.3g} % more compliant than a "
                         "sound one (FE, at the major axis's contact radius)")
    elif curve is not None:
        bound = reading.ripple + COVERAGE_K * reading.sigma
        a = curve.depth_for(bound)
        lines.append(f"no tooth-crack signal: a crack deeper than {a:.3g} mm would have shown (k = {COVERAGE_K:g})"
                     if a is not None else f"no tooth-crack signal, but this recording's noise hides every crack on "
                     f"the curve (up to a = {curve.depths_mm[-1]:g} mm)")
    # beside a crack the load-independent part also holds its non-linear contact's (FE: not proportional to T)
    if not reading.detected and reading.pitch_p_value is not None and reading.pitch_p_value < DETECT_P:
        lines.append("a ripple at the crack's order that does not grow with the torque: a tooth's pitch or profile "
                     "error, read apart from the crack")
    return {"effect": "tooth_crack_ripple", "quantity": "tooth-crack ripple (torque-scaled fundamental)",
            "reading": reading.to_dict(), "delta": reading.ripple, "sigma": reading.sigma, "unit": UNIT,
            "coverage_k": COVERAGE_K, "sizes": [s.to_dict() for s in sizes], "lines": lines,
            "orders": orders, "cracked_tooth": ratios,
            "curve": None if curve is None else {"depths_mm": list(curve.depths_mm), "ripple": list(curve.delta),
                                                 "uncertainty": list(curve.uncertainty), "source": curve.source},
            "_sizes": sizes, "_curve": curve}
