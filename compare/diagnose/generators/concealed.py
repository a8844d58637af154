"""What a concealed benchmark recording carries next to its file text, and how its signal-to-noise is defined.

Both generator families (`generate_recordings`, family 1; `generate_family2`, family 2) return a
``Concealed``: the recording text the diagnosis sees, and the truth it never sees (effect ids, or an
out-of-catalogue label, the noise colour, the signal-to-noise ratio, the true hysteresis loss, the
true catalogue stiffnesses for the CHA table).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import lsq_linear

PRIOR_SIGMAS = 4.5
NOISE_KINDS = ("white", "ar1", "lowpass", "random_walk")
KINDS = ("torsion", "ring_compression")


@dataclass(frozen=True)
class Concealed:
    name: str                          # the class, e.g. "hysteresis" or "f2:viscoelastic"
    text: str                          # the recording file (docs/recordings.md)
    truth: tuple[str, ...]             # catalogue effect ids; () when clean or out of catalogue
    snr: float                         # peak of the visible (weakest, if several) effect / noise std (0 for clean)
    kind: str                          # torsion | ring_compression
    family: int = 1
    noise: str = "white"               # measurement-noise colour, see NOISE_KINDS
    out_of_catalogue: str = ""         # label of physics outside the catalogue ("" when in it or clean)
    loss_arcmin: float | None = None   # true loop width at zero torque of the +/- full-scale cycle
    energy_Nmm_rad: float | None = None  # true dissipated energy per +/- full-scale cycle
    stiffness_Nmm_per_rad: tuple[float, float, float] | None = None   # CHA table K1, K2, K3

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"kind = {self.kind!r}: must be one of {KINDS}")
        if self.noise not in NOISE_KINDS:
            raise ValueError(f"noise = {self.noise!r}: must be one of {NOISE_KINDS}")
        if self.family not in (1, 2):
            raise ValueError(f"family = {self.family!r}: must be 1 or 2")
        if self.truth and self.out_of_catalogue:
            raise ValueError(f"{self.name}: a recording is either in the catalogue or out of it, not both")
        if not (math.isfinite(self.snr) and self.snr >= 0.0):
            raise ValueError(f"snr = {self.snr!r}: must be a finite number >= 0")
        if self.loss_arcmin is not None and not self.loss_arcmin > 0.0:
            raise ValueError(f"loss_arcmin = {self.loss_arcmin!r}: a dissipative loop has a positive loss")
        if (self.loss_arcmin is not None) != ("hysteresis" in self.truth):
            raise ValueError(f"{self.name}: the true loss is given exactly when the truth holds a hysteresis loop")

    @property
    def clean(self) -> bool:
        return not self.truth and not self.out_of_catalogue


def projected_peak(u: np.ndarray, t: np.ndarray, effect: np.ndarray, uncertainty: float) -> float:
    """Peak of what remains of a noise-free effect after the nuisance fit (offset, linear drift, stiffness
    within +/- PRIOR_SIGMAS uncertainties): the part of the effect a diagnosis can possibly see (units of Y).

    4.5 sigmas because a pure stiffness change must beat the prior by a decision threshold of about
    (d/u)^2 > 10 + ln N, i.e. d > 4.0..4.4 u for N = 200..2000, before it is evidence of anything."""
    A = np.column_stack([np.ones_like(u), t, u])
    b = PRIOR_SIGMAS * uncertainty
    sol = lsq_linear(A, effect, bounds=([-np.inf, -np.inf, -b], [np.inf, np.inf, b]))
    return float(np.max(np.abs(effect - A @ sol.x)))


def weakest_peak(u: np.ndarray, t: np.ndarray, parts: list[np.ndarray], uncertainty: float) -> float:
    """The signal of a recording with several effects, as scored: its WEAKEST effect's projected peak. An
    exact set can only be named when every member stands above the noise; the sum's peak would score a pair
    whose second effect is buried in the noise (e.g. a loop of 1.5 noise sigmas beside a strong stiffening)."""
    return min(projected_peak(u, t, p, uncertainty) for p in parts)


__all__ = ["Concealed", "KINDS", "NOISE_KINDS", "PRIOR_SIGMAS", "projected_peak", "weakest_peak"]
