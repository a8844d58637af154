"""Events a drive's test can hold that no catalogue effect draws: a jump in the twist, and which one it is.

Tooth ratcheting: under a torque beyond its ratcheting torque a harmonic drive's flexspline teeth climb over the
circular spline's, and the output slips by one tooth pitch, 2 pi / Z_f = pi / i of output twist for a drive of
ratio i = Z_f / 2 (two teeth fewer on the flexspline). A jump of that size (within RATCHET_TOLERANCE) at a torque
above RATCHET_LOAD of the largest is named so, with its torque; another jump is a slip (one way: it stays).
The jump is read from the raw channels: the largest first difference of the twist beyond JUMP_SIGMAS robust
sigmas of the others, the load's own slope taken out.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

JUMP_SIGMAS = 30.0          # a step this many robust sigmas of the sample-to-sample twist is no noise
RATCHET_TOLERANCE = 0.2     # a ratcheting step is one tooth pitch within this fraction (the mesh's own twist)
RATCHET_LOAD = 0.5          # ... at a torque above this fraction of the largest
ARCMIN_PER_RAD = 60.0 * 180.0 / math.pi


@dataclass(frozen=True)
class Jump:
    row: int              # 0-based row after which the twist has jumped
    step: float           # response units (rad)
    load: float           # load at the jump (N*mm)
    ratchet: bool         # one tooth pitch at high torque

    def sentence(self, load_name: str = "torque", ratio: float | None = None) -> str:
        where = f"between rows {self.row + 1} and {self.row + 2} at {load_name} {self.load / 1e3:.4g} N*m"
        size = f"{self.step:.4g} rad ({self.step * ARCMIN_PER_RAD:.3g} arcmin)"
        if self.ratchet:
            return (f"tooth ratcheting: the twist jumps by {size}, one tooth pitch (pi/i = {math.pi / ratio:.4g} rad "
                    f"for ratio {ratio:g}), {where}: the flexspline's teeth climbed over the circular spline's "
                    f"(the torque exceeded the ratcheting torque)")
        return f"a one-way slip: the twist jumps by {size} {where} and stays (a joint or clamp slipped)"


def find_jump(load: np.ndarray, response: np.ndarray, ratio: float | None) -> Jump | None:
    """The largest step of the twist between two samples (see the module doc), or None."""
    if len(load) < 20:
        return None
    dl, dr = np.diff(load), np.diff(response)
    ok = np.abs(dl) > 0
    slope = float(np.median(dr[ok] / dl[ok])) if np.any(ok) else 0.0
    d = dr - slope * dl
    scale = 1.4826 * float(np.median(np.abs(d - np.median(d))))
    k = int(np.argmax(np.abs(d)))
    if not scale > 0.0 or abs(d[k]) < JUMP_SIGMAS * scale:
        return None
    step, at = float(d[k]), float(load[k + 1])
    ratchet = bool(ratio and abs(abs(step) / (math.pi / ratio) - 1.0) <= RATCHET_TOLERANCE
                   and abs(at) >= RATCHET_LOAD * float(np.max(np.abs(load))))
    return Jump(k, step, at, ratchet)


def without_jump(response: np.ndarray, jump: Jump) -> np.ndarray:
    """The twist with the jump taken out of every row after it."""
    out = response.copy()
    out[jump.row + 1:] -= jump.step
    return out


__all__ = ["JUMP_SIGMAS", "Jump", "find_jump", "without_jump"]
