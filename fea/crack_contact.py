"""Frictionless contact of an opened seam crack's faces: the faces may separate but not pass through.

An opened seam (``crack_seam.open_crack``) gives each crack node i a copy j on the + side. The linear
solve lets the faces interpenetrate where the stress across the crack is compressive (the bearing-ring
crack at the centre of the Hertz patch: hoop stress about -0.87 p0, every duplicated pair with a negative
opening). The physical crack closes there. Non-penetration of pair k: opening g_k = (u_j - u_i) . n >= 0
(n the planar crack's unit normal towards the + side); frictionless: no tangential constraint.

Solved by an active set (node-to-node: the pairs coincide in the reference mesh): an active pair is
tied in the normal direction, u_j = (n . u_i) n + alpha t1 + beta t2, eliminated exactly by a sparse
transformation u = T v (the + copy keeps its two tangential dofs), so K' = T^T K T stays symmetric
positive definite. After each solve a pair is released when its contact force pulls (n . (K u - f)_j < 0,
adhesion) and activated when its opening is negative. With zero initial gap and a proportional load the
converged set does not depend on the load magnitude, so a compliance f.u / F^2 stays well defined.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from strainwave.fea.mesh_data import MeshData

__all__ = ["CrackPairs", "crack_pairs", "tangents", "ContactResult", "settle_active_set", "solve_with_contact"]

MAX_ITERATIONS = 30


@dataclass(frozen=True)
class CrackPairs:
    """Node pairs of an opened crack: ``minus[k]`` (original) and ``plus[k]`` (its copy); unit normal to +."""

    minus: np.ndarray
    plus: np.ndarray
    normal: np.ndarray

    def __post_init__(self):
        if self.minus.shape != self.plus.shape or self.normal.shape not in ((2,), (3,)):
            raise ValueError("CrackPairs: minus and plus must align and the normal must be a 2- or 3-vector")

    @property
    def dim(self) -> int:
        """Displacement components per node: 3 (solid) or 2 (a plane cross-section)."""
        return self.normal.size

    def in_dofs(self, node_to_dof: np.ndarray) -> "CrackPairs":
        """The pairs renumbered from mesh nodes to scalar dofs (scikit-fem's ``node_to_dof``)."""
        return CrackPairs(np.asarray(node_to_dof)[self.minus], np.asarray(node_to_dof)[self.plus], self.normal)


def crack_pairs(opened: MeshData, group: str = "crack") -> CrackPairs:
    """Pairs from the opened mesh's ``<group>_minus`` / ``<group>_plus`` facets (front nodes are shared,
    so they are no pair); the normal is the + side's (``crack_seam``'s orientation of a planar crack)."""
    from strainwave.fea.crack_seam import _oriented_normals

    minus_f, plus_f = opened.groups[f"{group}_minus"], opened.groups[f"{group}_plus"]
    m, p = minus_f.ravel(), plus_f.ravel()
    keep = m != p
    pairs = np.unique(np.stack([m[keep], p[keep]], axis=1), axis=0)
    nrm = _oriented_normals(opened, minus_f)
    n = nrm.mean(axis=0)
    n /= np.linalg.norm(n)
    n[np.abs(n) < 1e-9] = 0.0          # an axis-aligned plane stays exactly axis-aligned (round-off of the facets)
    n /= np.linalg.norm(n)
    # which side is "+": the copies sit on the elements whose centroids lie on the + side of the oriented
    # normal (crack_seam.element_sides), so n as oriented there points from the minus to the plus faces
    return CrackPairs(pairs[:, 0], pairs[:, 1], n)


def tangents(n: np.ndarray) -> tuple[np.ndarray, ...]:
    """Unit tangents completing the unit normal n to a right-handed frame (one in 2D, two in 3D)."""
    if n.size == 2:
        return (np.array([-n[1], n[0]]),)
    a = np.eye(3)[np.argmin(np.abs(n))]
    t1 = np.cross(n, a)
    t1 /= np.linalg.norm(t1)
    return t1, np.cross(n, t1)


def _transformation(N: int, pairs: CrackPairs, active: np.ndarray) -> tuple[sp.csr_matrix, np.ndarray]:
    """T (N x M) with u = T v, and the reduced index of every kept original dof (-1 for eliminated ones)."""
    n, dim = pairs.normal, pairs.dim
    frame = tangents(n)
    j_act, i_act = pairs.plus[active], pairs.minus[active]
    removed = np.zeros(N, bool)
    removed[(dim * j_act[:, None] + np.arange(dim)).ravel()] = True
    kept = np.flatnonzero(~removed)
    col = np.full(N, -1, dtype=np.int64)
    col[kept] = np.arange(kept.size)
    M = kept.size + (dim - 1) * j_act.size
    rows, cols, vals = [kept], [col[kept]], [np.ones(kept.size)]
    tang_col = kept.size + (dim - 1) * np.arange(j_act.size)
    for c in range(dim):
        r = dim * j_act + c
        for d in range(dim):                     # (n . u_i) n
            rows.append(r), cols.append(col[dim * i_act + d]), vals.append(np.full(j_act.size, n[c] * n[d]))
        for k, t in enumerate(frame):
            rows.append(r), cols.append(tang_col + k), vals.append(np.full(j_act.size, t[c]))
    T = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(N, M))
    T.eliminate_zeros()
    return T, col


def _reduced_fixed(T: sp.csr_matrix, col: np.ndarray, fixed: np.ndarray) -> np.ndarray:
    """Reduced indices of zero Dirichlet dofs. A fixed dof of an eliminated + copy is allowed when it is one
    of the copy's tangential dofs (an axis-aligned crack normal, e.g. u_z = 0 on a face the crack meets)."""
    out = col[fixed].copy()
    for k in np.flatnonzero(out < 0):
        row = T.getrow(int(fixed[k]))
        if row.nnz != 1 or not np.isclose(abs(row.data[0]), 1.0):
            raise ValueError("solve_with_contact: a Dirichlet condition acts across the crack normal of a "
                             "closed pair; only zero tangential conditions are supported")
        out[k] = row.indices[0]
    return np.unique(out)


@dataclass(frozen=True)
class ContactResult:
    u: np.ndarray
    active: np.ndarray            # pairs in contact (closed) at convergence
    opening_mm: np.ndarray        # (u_plus - u_minus) . n per pair
    contact_force_N: np.ndarray   # normal pressure force on the + copy (> 0 compressive), 0 for open pairs
    iterations: int
    u_unconstrained: np.ndarray   # the linear solve that lets the faces pass through each other


def settle_active_set(state, n_pairs: int, tol_mm: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """The active-set rule, from no pair in contact: a pair is activated when its opening is below -tol_mm and
    released when its contact force pulls. ``state(active) -> (opening, force)`` solves one set (force 0 off
    it). Returns the converged (active, opening, force) and the number of set changes."""
    active = np.zeros(n_pairs, bool)
    gap, force = state(active)
    for it in range(1, MAX_ITERATIONS + 1):
        new = (active & (force >= 0.0)) | (~active & (gap < -tol_mm))
        if np.array_equal(new, active):
            return active, gap, force, it - 1
        active = new
        gap, force = state(active)
    raise RuntimeError(f"crack-face contact: active set did not settle in {MAX_ITERATIONS} iterations")


def solve_with_contact(K: sp.spmatrix, f: np.ndarray, fixed_dofs: np.ndarray, pairs: CrackPairs, solve,
                       *, tol_mm: float | None = None) -> ContactResult:
    """Active-set frictionless contact; ``solve(K, f, fixed_dofs) -> u`` is the linear solver. ``pairs`` index
    scalar dofs (vector dof = dim x scalar + component, interleaved as in ``assembly``; dim = pairs.dim).

    Starts from the unconstrained solve (the pairs it interpenetrates are the first active set); each set is
    a solve of K with the active pairs' normal dofs eliminated."""
    K = K.tocsr()
    N = K.shape[0]
    u0 = solve(K, f, fixed_dofs)
    # penetration threshold: round-off of the solve, relative to the largest displacement
    tol = tol_mm if tol_mm is not None else 1e-9 * float(np.abs(u0).max())
    last = {}

    def state(active):
        u = u0
        if active.any():
            T, col = _transformation(N, pairs, active)
            fixed = _reduced_fixed(T, col, np.asarray(fixed_dofs, dtype=np.int64))
            u = T @ solve((T.T @ K @ T).tocsr(), T.T @ f, fixed)
        force = np.zeros(pairs.minus.size)
        if active.any():
            force[active] = (K @ u - f).reshape(-1, pairs.dim)[pairs.plus[active]] @ pairs.normal
        last["u"] = u
        return (u.reshape(-1, pairs.dim)[pairs.plus] - u.reshape(-1, pairs.dim)[pairs.minus]) @ pairs.normal, force

    active, gap, force, iterations = settle_active_set(state, pairs.minus.size, tol)
    return ContactResult(last["u"], active, gap, force, iterations, u0)
