"""Rig checks on the two channels before any physics: a reading that sits at its extreme while the other
channel moves.

- The LOAD reading constant at its largest (or smallest) value for several samples while the response keeps
  changing: the torque or force channel saturated (its amplifier or ADC at full scale), a stop in the load
  train, or creep under a hold. Whatever it is, the load that produced the response is not the load recorded,
  so no effect fitted against that load can be trusted.
- The RESPONSE reading constant at its extreme while the load keeps changing: the twist or deflection channel
  clipped at its full scale, or a rigid stop.
A plateau is a run of at least MIN_RUN consecutive samples within PLATEAU_SIGMAS noise sigmas of the
channel's extreme (the channel's own white noise, from its second differences); it counts when the other
channel moves by more than MOVE_SIGMAS of its noise (response) or MOVE_FRACTION of the load range (load)
during the run. A triangular test passes its peak in one or two samples, so a sampled peak is no plateau.
"""
from __future__ import annotations

import numpy as np

from .noise import noise_std

MIN_RUN = 5
PLATEAU_SIGMAS = 3.0
MOVE_SIGMAS = 10.0
MOVE_FRACTION = 0.05


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
    """A sentence describing a channel stuck at its extreme while the other moves, or "" when none is."""
    span = float(np.ptp(load)) or 1.0
    for a, b in _plateaus(load):
        moved = float(np.ptp(response[a:b]))
        if moved > MOVE_SIGMAS * sigma_response:
            return (f"the {load_name} reading stays at its extreme {load[a]:.4g} for {b - a} samples "
                    f"(samples {a + 1}-{b}) while {response_name} moves by {moved / sigma_response:.0f} noise sigmas: a "
                    f"saturated load channel, a stop in the load train, or creep under a hold; the load that "
                    f"produced the response there is not the load recorded")
    for a, b in _plateaus(response):
        moved = float(np.ptp(load[a:b]))
        if moved > MOVE_FRACTION * span:
            return (f"the {response_name} reading stays at its extreme {response[a]:.4g} for {b - a} samples "
                    f"(samples {a + 1}-{b}) while {load_name} moves by {100 * moved / span:.0f} % of its range: a "
                    f"clipped response channel (its full scale) or a rigid stop")
    return ""


__all__ = ["MIN_RUN", "MOVE_FRACTION", "MOVE_SIGMAS", "PLATEAU_SIGMAS", "stuck_channel"]
