"""A rig check on the load channel before any physics: a load reading stuck at its extreme while the
response keeps moving.

The torque or force reading constant at its largest (or smallest) value for several samples while the
response changes: the load channel saturated (amplifier or ADC at full scale), a stop in the load train, or
creep under a hold. Whatever it is, the load that produced the response there is not the load recorded, so
no effect fitted against that load can be trusted.

A plateau is a run of at least MIN_RUN consecutive samples within PLATEAU_SIGMAS noise sigmas of the load's
extreme (the channel's own white noise, from its second differences, ~1e-4 of full scale on a rig); it counts
when the response moves by more than MOVE_SIGMAS of what its noise moves over as many samples: a low-pass or
wandering sensor's reading drifts over a few samples by many times its sample-to-sample noise (family 2: a
sine test's flat peak, 7 samples long, under low-pass noise, moved 14 white-noise sigmas and read "a
saturated load channel"). A triangular test passes its
peak in one or two samples (a sample's load step is far above the load noise), so a sampled peak is no plateau.

The response channel is not checked the same way: near the peak of a stiffening curve, and when the response
is quantised, the twist legitimately stays within a few noise sigmas for several samples while the torque
moves (such a check flagged in-catalogue stiffening and compliance recordings of both benchmark families); a
clipped twist shows in the residual's structure instead.
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np

from strainwave.compare.diagnose.noise import noise_std

MIN_RUN = 5
PLATEAU_SIGMAS = 3.0
MOVE_SIGMAS = 10.0


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """(start, stop) of the runs of True in mask, at least MIN_RUN long."""
    edges = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    return [(a, b) for a, b in zip(starts, stops) if b - a >= MIN_RUN]


def _plateaus(x: np.ndarray) -> list[tuple[int, int]]:
    tol = PLATEAU_SIGMAS * max(noise_std(x), 1e-12 * float(np.max(np.abs(x)) or 1.0))
    out = []
    for extreme in (float(np.max(x)), float(np.min(x))):
        out += _runs(np.abs(x - extreme) <= tol)
    return out


def _change_scale(residual: np.ndarray, plateaus: list[tuple[int, int]], lag: int, stride: int) -> float:
    """sqrt of the residual's semivariogram at ``lag`` samples of the recording (0.5 mean (r_(t+lag) - r_t)^2),
    read outside every plateau: what the noise, white or coloured, moves by over as many samples elsewhere.
    ``residual`` is on every stride-th row of the recording."""
    k = max(math.ceil(lag / stride), 1)
    if len(residual) <= k + 1:
        return 0.0
    off = np.ones(len(residual), dtype=bool)
    for a, b in plateaus:
        off[a // stride:(b - 1) // stride + 1] = False
    pair = off[k:] & off[:-k]
    if not np.any(pair):
        return 0.0
    d = (residual[k:] - residual[:-k])[pair]
    return math.sqrt(0.5 * float(np.mean(d * d)))


def stuck_channel(load: np.ndarray, response: np.ndarray, sigma_response: float, load_name: str,
                  response_name: str, residual: np.ndarray | None = None, stride: int = 1,
                  explained: Callable[[], np.ndarray] | None = None) -> str:
    """A sentence describing a load channel stuck at its extreme while the response moves, or "" when none is.

    ``residual``: the response's residual after the best model (physical units, on every ``stride``-th row),
    from which a coloured noise's change over a plateau's length is read (white noise: sigma_response).
    ``explained``: the fitted model's response on every row (called only where a plateau exists); the response
    moves on a plateau only by what that model leaves: a wave generator turning under a held torque moves the
    twist by its kinematic error, which the model draws (a kinematic-error recording fitted at the noise read
    "a saturated load channel")."""
    plateaus = _plateaus(load)
    if plateaus and explained is not None:
        response = response - explained()
    for a, b in plateaus:
        moved = float(np.ptp(response[a:b]))
        scale = sigma_response if residual is None else \
            max(sigma_response, _change_scale(residual, plateaus, b - a - 1, stride))
        if moved > MOVE_SIGMAS * scale:
            return (f"the {load_name} reading stays at its extreme {load[a]:.4g} for {b - a} samples "
                    f"(samples {a + 1}-{b}) while {response_name} moves by {moved / scale:.0f} noise sigmas: a "
                    f"saturated load channel, a stop in the load train, or creep under a hold; the load that "
                    f"produced the response there is not the load recorded")
    return ""


__all__ = ["MIN_RUN", "MOVE_SIGMAS", "PLATEAU_SIGMAS", "stuck_channel"]
