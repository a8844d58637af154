"""A stiffness ripple at twice the input angle read as a flexspline tooth-root crack breathing.

The wave generator's major axis passes every point of the flexspline twice per input turn. A crack at a tooth
root opens as the major axis passes it and closes between: the gear's torsional compliance ripples at twice the
input angle, and the twist it adds grows with the torque (unlike the kinematic error, a ripple at any load).
The catalogue names that ripple `stiffness_ripple` (a model linear in the torque); its 2x amplitude in % of the
gear's mean compliance is, to first order, the stiffness ripple in % of K_HD (K = 1/(c0 s (1 + r cos 2 theta))
swings by +/- r about the stiffness midway between its extremes).

Given the FEA's breathing-crack ripple against the crack depth (a crack_sizing.DeltaCurve in % of K_HD, the GCI
of each point as its uncertainty), the measured ripple is sized as any compliance change is
(crack_sizing.size_crack): the depth whose FEA ripple equals it, a k = 2 interval, or why the flexspline cannot
hold it (a ripple beyond the curve's deepest crack).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from strainwave.compare.diagnose.crack_sizing import COVERAGE_K, CrackSize, DeltaCurve, size_crack

RIPPLE = "compliance_ripple_2x_percent"
SIGNIFICANT = 2.0          # standard errors: a ripple smaller than this is no evidence of a crack
RIPPLE_UNIT = "% of K_HD"
TOOTH_ROOT = "flexspline tooth root"
OPEN_STATE, SHUT_STATE = "major", "minor"     # fea/surface_crack's states: the crack open, the crack shut
# components whose crack cannot ripple with the wave generator's angle, and why
NO_RIPPLE = {"shaft": "its compliance does not turn with the wave generator, so a shaft crack adds no stiffness "
                      "ripple at twice the input angle"}


@dataclass(frozen=True)
class RippleReading:
    ripple_percent: float            # the 2x stiffness ripple, % of K_HD
    std_error_percent: float
    resolved: bool                   # the ripple stands SIGNIFICANT standard errors above zero
    size: CrackSize | None           # the flexspline crack it implies (None without an FEA ripple curve)

    def line(self) -> str:
        head = (f"stiffness ripple at twice the input angle {self.ripple_percent:.3g} +/- "
                f"{self.std_error_percent:.2g} % of K_HD, growing with the torque: ")
        if not self.resolved:
            return head + f"not resolved (under {SIGNIFICANT:g} standard errors), no evidence of a breathing crack"
        fits = "what a flexspline tooth-root crack breathing as the major axis passes it draws (so does the mesh " \
               "stiffness variation)"
        return head + fits + ("" if self.size is None else f"; {self.size.line()}")

    def to_dict(self) -> dict:
        return {"ripple_percent_of_K": self.ripple_percent, "std_error_percent": self.std_error_percent,
                "resolved": self.resolved, "coverage_k": COVERAGE_K,
                "flexspline_crack": None if self.size is None else self.size.to_dict(), "line": self.line()}


def ripple_reading(diagnosis, curve: DeltaCurve | None = None) -> RippleReading | None:
    """The breathing-crack reading of a diagnosis whose named model holds the 2x stiffness ripple (None
    otherwise); ``curve``: the FEA's flexspline ripple (% of K_HD) against the tooth-root crack depth."""
    if not diagnosis.named or not diagnosis.effects:
        return None
    top = diagnosis.effects[0]
    key = next((k for k in top.parameters if k == RIPPLE or k.endswith("." + RIPPLE)), None)
    if key is None:
        return None
    ripple, se = float(top.parameters[key][0]), float(top.errors.get(key) or 0.0)
    resolved = ripple > SIGNIFICANT * se
    size = size_crack(ripple, se, [curve])[0] if curve is not None and resolved else None
    return RippleReading(ripple, se, resolved, size)


def ripple_curve(depths_mm, open_, shut, lambda_total: float, wall_mm: float, source: str) -> DeltaCurve:
    """The flexspline's 2x ripple against the tooth-root crack depth, in the diagnosis's terms: the amplitude, half
    the peak-to-peak stiffness swing between the open and the shut axis (analytic.surface_crack.ripple_percent),
    in % of K_HD. ``open_``, ``shut``: per depth (delta lambda_f, its GCI uncertainty), rad/(N*mm); the ripple's
    uncertainty is theirs, propagated (d ripple / d delta = 100 lambda / (lambda + delta)^2, halved)."""
    from strainwave.analytic.surface_crack import ripple_percent
    amp, unc = [], []
    for (d_o, u_o), (d_s, u_s) in zip(open_, shut):
        amp.append(0.5 * ripple_percent(d_o, d_s, lambda_total))
        unc.append(0.5 * 100.0 * lambda_total * math.hypot(u_o / (lambda_total + d_o) ** 2,
                                                            u_s / (lambda_total + d_s) ** 2))
    return DeltaCurve(TOOTH_ROOT, RIPPLE_UNIT, tuple(depths_mm), tuple(amp), tuple(unc), wall_mm, source)


def ripple_curve_fea(params, cache_dir: Path | None = None,
                     progress: Callable[[str], None] = lambda m: None) -> DeltaCurve:
    """The flexspline's breathing-ripple curve from study cup-surface-crack (every depth of its sweep, three meshes
    each), solved on demand and cached under ``cache_dir``."""
    from strainwave.analytic.seed000 import seed000_summary
    from strainwave.cache import NUMBER, ResultCache, case_key
    from strainwave.fea.studies import run_study
    from strainwave.fea.surface_crack import STUDY, delta_name

    cache = ResultCache(Path(cache_dir)) if cache_dir is not None else None
    key = case_key("cup-ripple-curve", {"params": params.to_dict()})
    rec = cache.get(key, {"depths_mm": list, "wall_mm": NUMBER, OPEN_STATE: list, SHUT_STATE: list}) if cache else None
    if rec is None:
        progress(f"flexspline ripple curve: study {STUDY} (every depth of its sweep)")
        result = run_study(STUDY, params, progress=progress)
        depths = sorted(float(a) for a in result.meta["cracks"])
        states = {s: [result.quantities[delta_name(s, a)] for a in depths] for s in (OPEN_STATE, SHUT_STATE)}
        rec = {"depths_mm": depths, "wall_mm": float(result.meta["wall_mm"]),
               **{s: [[q.value, q.uncertainty or 0.0] for q in qs] for s, qs in states.items()}}
        if cache:
            cache.put(key, rec)
    lambda_total = 1.0 / seed000_summary(params)["K_HD"]["corrected"]
    return ripple_curve(rec["depths_mm"], rec[OPEN_STATE], rec[SHUT_STATE], lambda_total, rec["wall_mm"],
                        f"FEA: study {STUDY}, the tooth-root crack open ({OPEN_STATE} axis) and shut ({SHUT_STATE})")


def size_ripple(diagnosis, components: tuple[str, ...], curve: Callable[[], DeltaCurve]) -> dict | None:
    """The sizing record (crack_sizing.size_diagnosis's) of a diagnosis that names a 2x stiffness ripple: the
    flexspline tooth-root crack the FEA ``curve`` (called only for a resolved ripple) implies, or why no
    component of ``components`` can hold it; None when the diagnosis names no ripple."""
    reading = ripple_reading(diagnosis)
    if reading is None:
        return None
    sizes, curves, lines = [], [], []
    if reading.resolved:
        try:
            # the tooth root is the flexspline's ("cup" among the specimen's components)
            curves = [curve()] if "cup" in components else []
        except ValueError as exc:       # a curve that does not rise with depth sizes nothing
            lines.append(f"{TOOTH_ROOT}: not sized ({exc})")
        sizes = list(size_crack(reading.ripple_percent, reading.std_error_percent, curves))
        sizes += [CrackSize(c, False, None, None, None, NO_RIPPLE[c], "physics") for c in components if c in NO_RIPPLE]
        lines = [s.line() for s in sizes] + lines
        if any(s.possible for s in sizes):
            lines.append(f"{TOOTH_ROOT}: no remaining life is integrated from a ripple (the FEA curve gives the "
                         "crack's stiffness swing, not the stress intensity of its growth)")
        elif curves:
            c = curves[0]
            lines.append(f"no tooth-root crack in the wall can produce this ripple: the FEA sweep's deepest "
                         f"(a = {c.depths_mm[-1]:g} mm of the {c.wall_mm:g} mm wall) ripples "
                         f"{reading.ripple_percent / c.delta[-1]:.2g}x less; look for the mesh stiffness variation "
                         "(tooth profile, wave generator ovality) instead")
    else:
        lines.append(reading.line())
    return {"effect": "stiffness_ripple", "quantity": "stiffness ripple at twice the input angle (amplitude)",
            "delta": reading.ripple_percent, "sigma": reading.std_error_percent, "unit": RIPPLE_UNIT,
            "coverage_k": COVERAGE_K, "sizes": [s.to_dict() for s in sizes], "not_sized": [], "lines": lines,
            "_curves": curves + [None] * (len(sizes) - len(curves)), "_sizes": sizes}


__all__ = ["NO_RIPPLE", "RIPPLE_UNIT", "RippleReading", "TOOTH_ROOT", "ripple_curve", "ripple_curve_fea",
           "ripple_reading", "size_ripple"]
