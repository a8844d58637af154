"""Load paths the held-out diagnose benchmarks share (test-rig programmes, no physics of the specimen)."""
from __future__ import annotations

import numpy as np

__all__ = ["ramp_path"]


def ramp_path(points, n):
    """Piecewise-linear path through `points`, n samples, equally spaced in travel (constant rate)."""
    p = np.asarray(points, float)
    seg = np.abs(np.diff(p))
    cum = np.concatenate([[0], np.cumsum(seg)])
    s = np.linspace(0, cum[-1], n)
    return np.interp(s, cum, p)
