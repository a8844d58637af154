"""Load sharing of the teeth in mesh on a rigid rim, in closed form (check ``mesh.rigid_rim_sharing``).

On a rigid rim the flank pairs do not load one another: pair i is a single spring of compliance c_i along its
line of action, with an unloaded gap g_i that closes by a_i t under an output twist theta = s t (s the torque's
sign, t >= 0; a_i = |lever_i| for the pairs whose lever has the torque's sign, the others only open). So

    F_i = max(0, a_i t - g_i) / c_i,        |T| = sum_i b_i F_i,      b_i = |lever_i| + mu |slide_i|

(b: the torque arm, with flank friction resisting the twist on a first loading, as fea/mesh_contact.py sums
it). |T|(t) is piecewise linear and increasing, with a break where each pair closes (t_i = g_i / a_i). With the
pairs sorted by t_i, the torque at each break is a cumulative sum, the break below |T| names the pairs in
contact, and t follows from one linear equation: no iteration and no contact solver.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["RigidRimSharing", "rigid_rim_sharing"]


@dataclass(frozen=True)
class RigidRimSharing:
    twist_rad: float
    forces_N: np.ndarray           # (n,) normal force of each flank pair

    @property
    def teeth_in_contact(self) -> int:
        return int(np.count_nonzero(self.forces_N > 0.0))

    @property
    def peak_share(self) -> float:
        """The most loaded pair's share of the sum of the normal forces."""
        return float(self.forces_N.max() / self.forces_N.sum())


def rigid_rim_sharing(clearance_mm, compliance_mm_per_N, lever_mm, slide_mm_per_rad, friction_coefficient: float,
                      torque_Nmm: float) -> RigidRimSharing:
    """The twist and the flank-pair forces at ``torque_Nmm`` (first loading from zero) on a rigid rim."""
    g, c = np.asarray(clearance_mm, float), np.asarray(compliance_mm_per_N, float)
    lever, slide = np.asarray(lever_mm, float), np.asarray(slide_mm_per_rad, float)
    if np.any(c <= 0.0) or np.any(g < 0.0):
        raise ValueError("rigid_rim_sharing: compliances must be > 0 and clearances >= 0")
    s = 1.0 if torque_Nmm >= 0.0 else -1.0
    T = abs(torque_Nmm)
    forces = np.zeros(g.size)
    live = np.flatnonzero(s * lever > 0.0)         # the flanks this torque's twist closes
    if T == 0.0 or live.size == 0:
        return RigidRimSharing(0.0, forces)
    a = np.abs(lever[live])
    b = a + friction_coefficient * np.abs(slide[live])
    order = np.argsort(g[live] / a, kind="stable")
    a, b, gl, cl = a[order], b[order], g[live][order], c[live][order]
    t_break = gl / a
    # |T| = A_k t - B_k while the first k pairs touch: cumulative sums over the sorted pairs
    A = np.concatenate([[0.0], np.cumsum(b * a / cl)])
    B = np.concatenate([[0.0], np.cumsum(b * gl / cl)])
    T_break = A[:-1] * t_break - B[:-1]            # the torque as pair k starts to touch
    k = int(np.searchsorted(T_break, T, side="right"))   # the pairs in contact (T_break[0] = 0 <= T: k >= 1)
    t = (T + B[k]) / A[k]
    on = live[order][:k]
    forces[on] = np.maximum(a[:k] * t - gl[:k], 0.0) / cl[:k]
    return RigidRimSharing(s * t, forces)
