"""A rig check on the load channel before any physics: a load reading stuck at its extreme while the
response keeps moving.

The torque or force reading constant at its largest (or smallest) value for several samples while the
response changes: the load channel saturated (amplifier or ADC at full scale), a stop in the load train, or
creep under a hold. Whatever it is, the load that produced the response there is not the load recorded, so
no effect fitted against that load can be trusted.

A plateau is a run of at least MIN_RUN consecutive samples within PLATEAU_SIGMAS noise sigmas of the load's
extreme (the channel's own white noise, from its second differences, ~1e-4 of full scale on a rig); it counts
when the response moves by more than MOVE_SIGMAS of its noise during the run. A triangular test passes its
peak in one or two samples (a sample's load step is far above the load noise), so a sampled peak is no plateau.

The response channel is not checked the same way: near the peak of a stiffening curve, and when the response
is quantised, the twist legitimately stays within a few noise sigmas for several samples while the torque
moves (such a check flagged in-catalogue stiffening and compliance recordings of both benchmark families); a
clipped twist shows in the residual's structure instead.
"""
from __future__ import annotations

import numpy as np

from .noise import noise_std

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


def stuck_channel(load: np.ndarray, response: np.ndarray, sigma_response: float, load_name: str,
                  response_name: str) -> str:
    """A sentence describing a load channel stuck at its extreme while the response moves, or "" when none is."""
    for a, b in _plateaus(load):
        moved = float(np.ptp(response[a:b]))
        if moved > MOVE_SIGMAS * sigma_response:
            return (f"the {load_name} reading stays at its extreme {load[a]:.4g} for {b - a} samples "
                    f"(samples {a + 1}-{b}) while {response_name} moves by {moved / sigma_response:.0f} noise sigmas: a "
                    f"saturated load channel, a stop in the load train, or creep under a hold; the load that "
                    f"produced the response there is not the load recorded")
    return ""


__all__ = ["MIN_RUN", "MOVE_SIGMAS", "PLATEAU_SIGMAS", "stuck_channel"]
