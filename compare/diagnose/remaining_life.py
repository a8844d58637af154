"""Remaining life of a sized crack: Paris' law with the stress intensity the FEA's own crack curve implies.

The energy release rate at torque T follows from the same delta-lambda(a) curve that sized the crack
(seed 000 eq 3 read backwards): G = (T^2 / 2) d(delta lambda)/da / L(a), L the crack front's length, and
K = sqrt(E' G) with E' = 2 mu for the mode III of a circumferential shaft crack under torsion (E for mode I).
K is linear in T, so a torque range dT gives dK = k(a) dT. Under a spectrum of ranges dT_i counted n_i times
(constant amplitude, or rainflow-counted from a torque history), crack growth per cycle is
C k(a)^m <dT^m>, without load-interaction effects (no retardation after overloads: conservative).
Growth stops where the specimen's stiffness has fallen by the user's limit, or where the FEA curve ends.
"""
from __future__ import annotations

import math
from pathlib import Path
from dataclasses import dataclass

import numpy as np
from scipy import integrate

from strainwave.compare.diagnose.crack_sizing import CrackSize, DeltaCurve

__all__ = ["ParisLaw", "LoadSpectrum", "LifeEstimate", "remaining_life", "spectrum_from_history", "BS7910_STEEL",
           "life_of_sizing", "life_lines", "plot_life"]


@dataclass(frozen=True)
class ParisLaw:
    """da/dN = C dK^m, da/dN in mm/cycle, dK in N/mm^1.5."""

    C: float
    m: float
    source: str

    def __post_init__(self):
        if not (self.C > 0 and 1.0 <= self.m <= 10.0):
            raise ValueError(f"Paris law C = {self.C!r} must be > 0 and m = {self.m!r} within 1..10")


# BS 7910:2019, simplified law for steels in air (mean + 2 SD), N and mm units.
BS7910_STEEL = ParisLaw(5.21e-13, 3.0, "BS 7910:2019 simplified crack growth law, steels in air (N, mm)")


@dataclass(frozen=True)
class LoadSpectrum:
    """Torque ranges (N mm) and their counts per block; one block is ``cycles_per_block`` cycles."""

    ranges_Nmm: tuple[float, ...]
    counts: tuple[float, ...]
    description: str

    @classmethod
    def constant(cls, range_Nmm: float) -> "LoadSpectrum":
        return cls((float(range_Nmm),), (1.0,), f"constant amplitude, torque range {range_Nmm:g} N mm")

    def mean_range_power(self, m: float) -> float:
        """<dT^m> per cycle."""
        r, n = np.asarray(self.ranges_Nmm), np.asarray(self.counts)
        return float(np.sum(n * r ** m) / np.sum(n))


def spectrum_from_history(torque_Nmm) -> LoadSpectrum:
    """Rainflow-counted ranges of a torque history (ASTM E1049-85, the ``rainflow`` package)."""
    import rainflow

    cycles = rainflow.count_cycles(np.asarray(torque_Nmm, dtype=float))
    if not cycles:
        raise ValueError("the torque history holds no load cycle")
    ranges, counts = zip(*cycles)
    return LoadSpectrum(tuple(ranges), tuple(counts), f"rainflow-counted history: {sum(counts):g} cycles")


@dataclass(frozen=True)
class LifeEstimate:
    cycles: float
    cycles_low: float              # from the deeper end of the crack's interval
    cycles_high: float             # from the shallower end
    stop_depth_mm: float
    stop_reason: str
    hours: float | None
    curve: tuple[tuple[float, float], ...]   # (cycles, stiffness over the uncracked stiffness)

    def to_dict(self) -> dict:
        return {**self.__dict__, "curve": [list(p) for p in self.curve]}


def _k_per_torque(curve: DeltaCurve, a_mm: float, modulus_MPa: float) -> float:
    """K per unit torque (N/mm^1.5 per N mm) at depth a."""
    g_per_T2 = 0.5 * curve.slope_at(a_mm) / curve.front_length_mm(a_mm)
    return math.sqrt(modulus_MPa * g_per_T2)


def _cycles(curve, a0, a1, law, spectrum, modulus_MPa) -> float:
    if a1 <= a0:
        return 0.0
    dT = spectrum.mean_range_power(law.m)
    rate = lambda a: law.C * _k_per_torque(curve, a, modulus_MPa) ** law.m * dT   # noqa: E731
    breaks = [a0] + [a for a in curve.depths_mm if a0 < a < a1] + [a1]
    return sum(integrate.quad(lambda a: 1.0 / rate(a), lo, hi, limit=200)[0] for lo, hi in zip(breaks, breaks[1:]))


def _stop(curve: DeltaCurve, baseline_compliance: float, stiffness_loss: float) -> tuple[float, str]:
    target = baseline_compliance * stiffness_loss / (1.0 - stiffness_loss)
    a = curve.depth_for(target)
    if a is None:
        return curve.depths_mm[-1], (f"the FEA curve ends at a = {curve.depths_mm[-1]:g} mm before a "
                                     f"{100 * stiffness_loss:g} % stiffness loss: life to that depth")
    return a, f"stiffness loss {100 * stiffness_loss:g} % at a = {a:.3g} mm"


def remaining_life(size: CrackSize, curve: DeltaCurve, baseline_compliance: float, spectrum: LoadSpectrum,
                   *, modulus_MPa: float, law: ParisLaw = BS7910_STEEL, stiffness_loss: float = 0.1,
                   cycles_per_hour: float | None = None) -> LifeEstimate:
    """Cycles (and hours) from the sized crack to the stiffness-loss limit, with the band of the crack's
    interval; ``modulus_MPa`` is E' in K = sqrt(E' G)."""
    if not size.possible or curve.front_length_mm is None:
        raise ValueError(f"{curve.component}: no crack to grow, or no crack-front length for its curve")
    if not 0.0 < stiffness_loss < 1.0:
        raise ValueError(f"stiffness loss {stiffness_loss!r} must lie in (0, 1)")
    a_stop, why = _stop(curve, baseline_compliance, stiffness_loss)
    start = max(size.depth_mm, curve.depths_mm[0] * 1e-3)
    n = _cycles(curve, start, a_stop, law, spectrum, modulus_MPa)
    n_lo = _cycles(curve, max(size.high_mm, start), a_stop, law, spectrum, modulus_MPa)
    n_hi = _cycles(curve, max(size.low_mm, curve.depths_mm[0] * 0.05), a_stop, law, spectrum, modulus_MPa)
    depths = np.geomspace(start, a_stop, 24) if a_stop > start else np.array([start])
    points = [(_cycles(curve, start, a, law, spectrum, modulus_MPa),
               baseline_compliance / (baseline_compliance + curve.delta_at(a))) for a in depths]
    hours = None if cycles_per_hour is None else n / cycles_per_hour
    return LifeEstimate(n, n_lo, n_hi, a_stop, why, hours, tuple(points))


def life_of_sizing(sizing: dict, baseline_compliance: float, params, *, law: ParisLaw = BS7910_STEEL,
                   spectrum: LoadSpectrum | None = None, stiffness_loss: float = 0.1,
                   cycles_per_hour: float | None = None) -> list[dict]:
    """Remaining life of every sized crack of ``crack_sizing.size_diagnosis``'s record whose curve has a front
    length. Default spectrum: 0 -> rated output torque, constant amplitude. E' = 2 mu (mode III, torsion)."""
    mat = params.material
    modulus = mat.youngs_modulus_MPa / (1.0 + mat.poisson_ratio)
    spectrum = spectrum or LoadSpectrum.constant(params.gear.rated_output_torque_Nmm)
    out = []
    for size, curve in zip(sizing["_sizes"], sizing["_curves"]):
        if not size.possible or curve.front_length_mm is None:
            continue
        est = remaining_life(size, curve, baseline_compliance, spectrum, modulus_MPa=modulus, law=law,
                             stiffness_loss=stiffness_loss, cycles_per_hour=cycles_per_hour)
        out.append({"component": size.component, "paris_law": {"C": law.C, "m": law.m, "source": law.source},
                    "spectrum": spectrum.description, **est.to_dict()})
    return out


def life_lines(lives: list[dict]) -> list[str]:
    """One line per component: cycles with their band, hours when a rate is given, and where growth stops."""
    lines = []
    for life in lives:
        hours = "" if life["hours"] is None else f", {life['hours']:.3g} h"
        lines.append(f"{life['component']}: remaining life {life['cycles']:.3g} cycles{hours} (band "
                     f"{life['cycles_low']:.3g}..{life['cycles_high']:.3g} from the crack's interval); "
                     f"{life['stop_reason']}; {life['spectrum']}; {life['paris_law']['source']}")
    return lines


def plot_life(path: Path, lives: list[dict]) -> Path:
    """Stiffness (over the uncracked) against load cycles, one line per component."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from strainwave.io_atomic import atomic_path

    fig = Figure(figsize=(7.0, 4.0), dpi=110)
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    for life in lives:
        n, k = zip(*life["curve"])
        ax.plot(np.maximum(n, 1.0), k, "-", label=f"{life['component']}: to {life['stop_depth_mm']:.3g} mm")
    ax.set_xscale("log")
    ax.set_xlabel("load cycles from today")
    ax.set_ylabel("stiffness / uncracked stiffness")
    ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    with atomic_path(Path(path)) as tmp:
        fig.savefig(tmp, format="png")
    return Path(path)
