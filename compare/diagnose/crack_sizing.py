"""A crack sized from its recording: the measured compliance change read off the FEA's delta-lambda(a) curves.

Seed 000 proposes the torsional stiffness as a predictive-maintenance signal. Here the inverse is taken
per candidate component: the depth at which that component's FEA crack adds the measured compliance.
The curve is the FEA's own (the shaft's axisymmetric section solved on demand and cached, or the crack
sweeps of a ``validate`` run's results.json); between its points it is interpolated by a monotone cubic in
log-log (every crack curve here is close to a power law), below its first point the first segment's power
law runs to zero, and above its last point nothing is asserted: the answer is "not on the curve".

The stated interval is k = 2 standard uncertainties of the measured change, combined in quadrature
with the curve's own discretization error (its GCI) and its interpolation error (the gap between the cubic
and the chord between its points) at that change.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from strainwave.errors import InputError

__all__ = ["DeltaCurve", "CrackSize", "size_crack", "curve_from_results", "shaft_curve_fea", "COVERAGE_K"]

COVERAGE_K = 2.0          # the stated interval: about 95 % for a normal error


@dataclass(frozen=True)
class DeltaCurve:
    """One component's FEA crack curve: added compliance against depth, each point with its GCI."""

    component: str
    unit: str
    depths_mm: tuple[float, ...]
    delta: tuple[float, ...]
    uncertainty: tuple[float, ...]           # absolute, from each point's GCI
    wall_mm: float                            # the deepest crack the component can hold
    source: str
    front_length_mm: Callable[[float], float] | None = field(default=None, compare=False)

    def __post_init__(self):
        a, d = np.asarray(self.depths_mm), np.asarray(self.delta)
        if len(a) < 2 or np.any(np.diff(a) <= 0) or np.any(d <= 0) or np.any(np.diff(d) <= 0):
            raise ValueError(f"{self.component}: a crack curve needs >= 2 depths, increasing, with a rising "
                             "positive delta")

    def _loglog(self):
        """Monotone cubic (PCHIP) of log delta against log a: it follows the curve's bend between points, where
        a straight log-log chord errs to one side; below the first point the first chord's power law."""
        from scipy.interpolate import PchipInterpolator

        return PchipInterpolator(np.log(self.depths_mm), np.log(self.delta), extrapolate=False)

    def _chord(self, log_a: float) -> float:
        la, ld = np.log(self.depths_mm), np.log(self.delta)
        return float(np.interp(log_a, la, ld)) if log_a >= la[0] else float(ld[0] + (ld[1] - ld[0]) / (la[1] - la[0]) * (log_a - la[0]))

    def delta_at(self, depth_mm: float) -> float:
        """Added compliance at ``depth_mm`` (<= the last point's depth)."""
        if depth_mm <= 0:
            return 0.0
        if depth_mm > self.depths_mm[-1] * (1 + 1e-12):
            raise ValueError(f"{self.component}: a = {depth_mm} mm is beyond the curve ({self.depths_mm[-1]} mm)")
        la = math.log(depth_mm)
        if la < math.log(self.depths_mm[0]) or len(self.depths_mm) < 3:
            return math.exp(self._chord(la))
        return float(np.exp(self._loglog()(la)))

    def interpolation_error_at(self, depth_mm: float) -> float:
        """Relative gap between the cubic and the chord at ``depth_mm``: the error interpolation may leave."""
        if len(self.depths_mm) < 3 or depth_mm <= self.depths_mm[0]:
            return 0.0
        la = math.log(min(depth_mm, self.depths_mm[-1]))
        return abs(math.expm1(float(self._loglog()(la)) - self._chord(la)))

    def slope_at(self, depth_mm: float) -> float:
        """d(delta)/da, for the energy release rate."""
        if len(self.depths_mm) < 3 or depth_mm <= self.depths_mm[0]:
            i = 0 if depth_mm <= self.depths_mm[0] else min(int(np.searchsorted(self.depths_mm, depth_mm)) - 1,
                                                             len(self.depths_mm) - 2)
            la, ld = np.log(self.depths_mm), np.log(self.delta)
            p = (ld[i + 1] - ld[i]) / (la[i + 1] - la[i])
            return p * self.delta_at(depth_mm) / depth_mm
        f = self._loglog()
        la = math.log(depth_mm)
        return float(f.derivative()(la)) * self.delta_at(depth_mm) / depth_mm

    def depth_for(self, delta: float) -> float | None:
        """Depth whose added compliance is ``delta``; 0 for delta <= 0, None above the curve's last point."""
        if delta <= 0:
            return 0.0
        if delta > self.delta[-1] * (1 + 1e-12):
            return None
        if delta <= self.delta[0] or len(self.depths_mm) < 3:
            la, ld = np.log(self.depths_mm), np.log(self.delta)
            i = 0 if delta <= self.delta[0] else min(int(np.searchsorted(self.delta, delta)) - 1, len(self.delta) - 2)
            p = (ld[i + 1] - ld[i]) / (la[i + 1] - la[i])
            return float(math.exp(la[i] + (math.log(delta) - ld[i]) / p))
        from scipy.optimize import brentq

        la = np.log(self.depths_mm)
        f = self._loglog()
        target = math.log(delta)
        return float(math.exp(brentq(lambda x: float(f(x)) - target, la[0], la[-1], xtol=1e-13)))

    def relative_uncertainty_at(self, depth_mm: float) -> float:
        """The curve's GCI, relative, interpolated between its points (the nearest point's beyond them)."""
        rel = np.asarray(self.uncertainty) / np.asarray(self.delta)
        return float(np.interp(depth_mm, self.depths_mm, rel))


@dataclass(frozen=True)
class CrackSize:
    component: str
    possible: bool
    depth_mm: float | None
    low_mm: float | None
    high_mm: float | None
    reason: str
    source: str

    @property
    def std_mm(self) -> float | None:
        """The standard uncertainty of the depth: the k-interval's half-width over k."""
        return None if self.low_mm is None else (self.high_mm - self.low_mm) / (2.0 * COVERAGE_K)

    def to_dict(self) -> dict:
        return {**self.__dict__, "std_mm": self.std_mm}

    def line(self) -> str:
        if not self.possible:
            return f"{self.component}: cannot hold such a crack ({self.reason})"
        return (f"{self.component}: crack depth {self.depth_mm:.3g} +/- {self.std_mm:.2g} mm (k = {COVERAGE_K:g} interval "
                f"{self.low_mm:.3g}..{self.high_mm:.3g} mm){'; ' + self.reason if self.reason else ''}")


def _one(curve: DeltaCurve, delta: float, sigma: float) -> CrackSize:
    top = curve.delta[-1]
    if delta - COVERAGE_K * sigma > top:
        return CrackSize(curve.component, False, None, None, None,
                         f"the measured change {delta:.3g} {curve.unit} exceeds its FEA curve's largest, "
                         f"{top:.3g} at a = {curve.depths_mm[-1]:g} mm of a {curve.wall_mm:g} mm wall", curve.source)
    a = curve.depth_for(min(delta, top))
    at = a or curve.depths_mm[0]
    rel_curve = math.hypot(curve.relative_uncertainty_at(at), curve.interpolation_error_at(at))
    sigma_tot = math.hypot(sigma, rel_curve * max(delta, 0.0))
    lo = curve.depth_for(delta - COVERAGE_K * sigma_tot)
    hi = curve.depth_for(delta + COVERAGE_K * sigma_tot)
    notes = []
    if delta > top:
        notes.append(f"the change lies above the curve's end (a = {curve.depths_mm[-1]:g} mm)")
    if lo == 0.0:
        notes.append("its lower bound is no crack: the change is within its uncertainty of zero")
    if hi is None:
        hi = curve.depths_mm[-1]
        notes.append(f"its upper bound passes the curve's end at {hi:g} mm")
    return CrackSize(curve.component, True, a if a is not None else curve.depths_mm[-1], lo, hi,
                     "; ".join(notes), curve.source)


def size_crack(delta: float, sigma: float, curves: list[DeltaCurve]) -> tuple[CrackSize, ...]:
    """The depth in each candidate component whose FEA crack adds ``delta`` (standard uncertainty ``sigma``,
    same unit as the curves), or why that component cannot hold it."""
    if not (math.isfinite(delta) and math.isfinite(sigma) and sigma >= 0):
        raise ValueError(f"compliance change {delta!r} +- {sigma!r} must be finite with sigma >= 0")
    return tuple(_one(c, delta, sigma) for c in curves)


def read_results(path: Path) -> dict:
    """A validate run's results.json (a JSON object with its crack sweeps), refused in one line naming --curves
    otherwise: read before any work, so a wrong file is never silently left unread."""
    from strainwave.input_guard import read_regular
    raw = read_regular(path, 64 << 20, "--curves")   # a regular file, bounded (a validate results.json is ~1 MB)
    try:
        doc = json.loads(raw.decode("utf-8"))
    except (ValueError, RecursionError) as exc:
        raise InputError("--curves", str(path), f"a validate results.json ({type(exc).__name__})") from None
    if not isinstance(doc, dict) or not isinstance(doc.get("crack_sweeps"), dict):
        raise InputError("--curves", str(path), "a validate results.json with its 'crack_sweeps'")
    return doc


def curve_from_results(path: Path, component: str) -> DeltaCurve:
    """A component's crack curve from a validate run's results.json (its crack-depth sweep, resolved points)."""
    doc = read_results(path)
    try:
        sweep = doc["crack_sweeps"][component]
    except (OSError, ValueError, KeyError, TypeError, RecursionError) as exc:
        raise InputError("--curves", str(path), f"a validate results.json with a '{component}' crack sweep "
                         f"({type(exc).__name__})") from None
    rows = sorted((a, v, u) for a, v, u, ok in zip(sweep["depths_mm"], sweep["fea"], sweep["fea_uncertainty"],
                                                   sweep["resolved"]) if ok)
    wall = float(doc.get("crack_walls_mm", {}).get(component, rows[-1][0]) if rows else 0.0)
    return DeltaCurve(component, sweep["unit"], tuple(r[0] for r in rows), tuple(r[1] for r in rows),
                      tuple(r[2] for r in rows), wall, f"FEA crack sweep in {path}")


# The curve's GCI enters every stated depth: its sections are this much finer than the full run's, paid once per
# shaft and cached (docs/decisions/053).
SHAFT_CURVE_DENSITY = 3.0
# Of the wall, shallow to nearly through; closer where the curve steepens, so its interpolation error stays
# below the points' GCI there.
SHAFT_DEPTH_FRACTIONS = (0.03, 0.08, 0.16, 0.28, 0.42, 0.5, 0.58, 0.65, 0.71, 0.76, 0.8, 0.84, 0.88, 0.92)


def shaft_curve_fea(params, cache_dir: Path | None = None,
                    progress: Callable[[str], None] = lambda m: None) -> DeltaCurve:
    """The output shaft's FEA crack curve (full circumferential crack, the exact axisymmetric section),
    solved on demand at SHAFT_DEPTH_FRACTIONS of the wall on sections SHAFT_CURVE_DENSITY times finer than the
    full run's, and cached per point under ``cache_dir``."""
    from strainwave.cache import NUMBER, ResultCache, case_key

    shaft = params.output_shaft
    wall = 0.5 * (shaft.outer_diameter_mm - shaft.inner_diameter_mm)
    r_o = 0.5 * shaft.outer_diameter_mm
    cache = ResultCache(Path(cache_dir)) if cache_dir is not None else None
    depths = [round(frac * wall, 6) for frac in SHAFT_DEPTH_FRACTIONS]
    keys = [case_key("shaft-crack-curve", {"params": params.to_dict(), "a_mm": a, "density": SHAFT_CURVE_DENSITY})
            for a in depths]
    records = {a: cache.get(key, {"value": NUMBER, "uncertainty": NUMBER}) if cache else None
               for a, key in zip(depths, keys)}
    missing = [a for a in depths if records[a] is None]
    for a, rec in zip(missing, _solve_points(params, missing, progress)):
        records[a] = rec
        if cache:
            cache.put(keys[depths.index(a)], rec)
    points = [(a, records[a]["value"], records[a]["uncertainty"]) for a in depths]
    return DeltaCurve("shaft", "rad/(N*mm)", tuple(p[0] for p in points), tuple(p[1] for p in points),
                      tuple(p[2] for p in points), wall,
                      f"FEA: output shaft, axisymmetric crack section ({SHAFT_CURVE_DENSITY:g}x the full run's mesh density)",
                      front_length_mm=lambda a: 2.0 * math.pi * (r_o - a))


def _curve_point(params, depth_mm: float) -> dict:
    from strainwave.fea.shaft_axisym_study import section_delta
    q = section_delta(params, depth_mm, density=SHAFT_CURVE_DENSITY)
    return {"value": q.value, "uncertainty": q.uncertainty or 0.0}


def _solve_points(params, depths: list[float], progress: Callable[[str], None]) -> list[dict]:
    """The curve's points at ``depths``, in order: on both cores where forking is safe (each point is its own
    three section solves), else one after another."""
    from strainwave.compare.diagnose.parallel import usable_workers
    workers = min(usable_workers(), len(depths))
    if workers < 2:
        out = []
        for k, a in enumerate(depths, 1):
            progress(f"shaft crack curve: a = {a:g} mm ({k}/{len(depths)})")
            out.append(_curve_point(params, a))
        return out
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor
    progress(f"shaft crack curve: {len(depths)} depths on {workers} processes")
    with ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("fork")) as pool:
        futures = [pool.submit(_curve_point, params, a) for a in depths]
        out = []
        for k, (a, future) in enumerate(zip(depths, futures), 1):
            out.append(future.result())
            progress(f"shaft crack curve: a = {a:g} mm ({k}/{len(depths)})")
        return out


SPECIMEN_COMPONENTS = {"output_shaft": ("shaft",), "flexspline_cup": ("cup",), "gear": ("shaft", "cup")}


MIDLINE_SPAN = 0.7     # of the peak load: past it a reversal's friction transition has not settled


def _branches(x: np.ndarray) -> list[tuple[int, int, int]]:
    """(start, stop, direction) of the monotone runs of the load."""
    d = np.sign(np.diff(x))
    d[d == 0] = 1
    cuts = np.flatnonzero(d[1:] != d[:-1]) + 1
    edges = [0, *cuts.tolist(), len(d)]
    return [(a, b + 1, int(d[a])) for a, b in zip(edges, edges[1:]) if b - a >= 5]


def midline_compliance(load: np.ndarray, response: np.ndarray) -> tuple[float, float]:
    """Slope of the loop's mean curve (the average of its loading and unloading branches at one load) over
    the central +/- MIDLINE_SPAN of the peak load, and its standard error: the elastic compliance of a
    specimen behind a friction loop, which neither the secant nor the reversal tangent gives."""
    x, y = np.asarray(load, dtype=float), np.asarray(response, dtype=float)
    grid = np.linspace(-MIDLINE_SPAN, MIDLINE_SPAN, 41) * float(np.max(np.abs(x)))
    sides = {1: [], -1: []}
    for a, b, direction in _branches(x):
        xs, ys = x[a:b][::direction], y[a:b][::direction]
        covered = (grid >= xs[0]) & (grid <= xs[-1])
        sides[direction].append(np.where(covered, np.interp(grid, xs, ys), np.nan))
    if not sides[1] or not sides[-1]:              # no loop: the plain least-squares slope
        A = np.column_stack([x, np.ones_like(x)])
        mid, keep = y, np.ones_like(x, dtype=bool)
        grid = x
    else:
        with np.errstate(all="ignore"):
            mid = 0.5 * (np.nanmean(sides[1], axis=0) + np.nanmean(sides[-1], axis=0))
        keep = np.isfinite(mid)
        A = np.column_stack([grid, np.ones_like(grid)])
    A, m = A[keep], mid[keep]
    if len(m) < 5:
        raise ValueError("too few loop points for a midline")
    coef, *_ = np.linalg.lstsq(A, m, rcond=None)
    resid = m - A @ coef
    cov = np.linalg.inv(A.T @ A) * float(resid @ resid) / max(len(m) - 2, 1)
    return float(coef[0]), float(math.sqrt(cov[0, 0]))


def measured_change(diagnosis, load=None, response=None) -> tuple[float, float, str] | None:
    """(added compliance, its standard uncertainty, the effect it came from) of an explained diagnosis that
    names a crack-type effect; None otherwise. crack_closure: the open side's compliance over the closed
    side's (one specimen, so the baseline's uncertainty cancels). A compliance change: the recording's midline
    compliance over whole cycles minus the model's, known only to the baseline's own uncertainty."""
    if not diagnosis.named or not diagnosis.effects:
        return None
    c0, u_b = diagnosis.baseline.compliance, diagnosis.baseline.uncertainty
    p, err = diagnosis.effects[0].parameters, diagnosis.effects[0].errors

    def get(effect: str, name: str) -> tuple[float, float] | None:
        """A reported parameter, prefixed by its effect when the model is a pair, bare when it is alone."""
        key = next((k for k in (f"{effect}.{name}", name) if k in p), None)
        return None if key is None else (float(p[key][0]), float(err.get(key) or 0.0))

    if "crack_closure" in diagnosis.named and get("crack_closure", "stiffness_crack_open"):
        (k_o, e_o), (k_c, e_c) = (get("crack_closure", f"stiffness_crack_{s}") for s in ("open", "closed"))
        return 1.0 / k_o - 1.0 / k_c, math.hypot(e_o / k_o ** 2, e_c / k_c ** 2), "crack_closure"
    if "compliance_offset" in diagnosis.named and load is not None:
        slope, stderr = midline_compliance(load, response)
        return slope - c0, math.hypot(stderr, u_b * c0), "compliance_offset"
    return None


def size_diagnosis(diagnosis, params, load=None, response=None, *, results: Path | None = None,
                   cache_dir: Path | None = None, progress: Callable[[str], None] = lambda m: None) -> dict | None:
    """The sizing record of a diagnosis (and its recording's load and response): per candidate component of
    its specimen, the depth or why not; a 2x stiffness ripple on the flexspline's breathing-ripple curve
    (breathing_crack.size_ripple)."""
    change = measured_change(diagnosis, load, response)
    if change is None:
        from strainwave.compare.diagnose.breathing_crack import ripple_curve_fea, size_ripple
        return size_ripple(diagnosis, SPECIMEN_COMPONENTS.get(diagnosis.specimen, ()),
                           lambda: ripple_curve_fea(params, cache_dir, progress))
    delta, sigma, effect = change
    curves, missing = [], []
    for component in SPECIMEN_COMPONENTS.get(diagnosis.specimen, ()):
        if component == "shaft":
            curves.append(shaft_curve_fea(params, cache_dir, progress))
        elif results is not None:
            curves.append(curve_from_results(results, component))
        else:
            missing.append(f"{component}: no FEA crack curve (pass a validate results.json with --curves)")
    sizes = size_crack(delta, sigma, curves)
    return {"effect": effect, "delta": delta, "sigma": sigma, "unit": curves[0].unit if curves else "",
            "coverage_k": COVERAGE_K, "sizes": [s.to_dict() for s in sizes], "not_sized": missing,
            "lines": [s.line() for s in sizes] + missing, "_curves": curves, "_sizes": sizes}
