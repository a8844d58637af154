"""Crack-face contact sets by one factorisation: K factorised once, which also gives S, its Schur complement on
the crack face's dofs; every set of held face dofs is then a dense solve of S's free block
(docs/decisions/033-surface-crack-face-schur.md, docs/decisions/039-bearing-crack-face-schur.md).

``FaceSystem`` holds any face dofs (the surface crack's normal dofs on its symmetry plane). ``SeamSystem`` is an
opened seam's node pairs (``crack_contact.CrackPairs``) in opening coordinates: each + copy's dofs replaced by
the pair's opening w = R^T (u_plus - u_minus), R = [n t1 t2]. Holding a pair's w_n is its normal contact; holding
all of w ties the pair, so with every pair held the opened mesh is the seam closed: the uncracked part.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from strainwave.fea.crack_contact import ContactResult, CrackPairs, settle_active_set, tangents

__all__ = ["FaceSystem", "open_compliance", "opening_transformation", "SeamSystem"]


@dataclass
class FaceSystem:
    """K with the base held, factorised once with its Schur complement S on the face dofs: every set of held
    face dofs is then a dense solve of S's free block."""

    K: object                   # the full stiffness
    base: np.ndarray            # held in every solve
    face_z: np.ndarray          # the face dofs (increasing), held where shut
    free: np.ndarray            # dofs not in base
    factor: object              # solver.SchurFactor of K[free][:, free] onto face_z

    @classmethod
    def of(cls, K, base, face_z, study: str) -> "FaceSystem":
        from strainwave.fea.solver import condense, schur_factor
        face_z = np.asarray(face_z, np.int64)
        if np.any(np.diff(face_z) <= 0):   # PARDISO returns S in the dofs' own order
            raise ValueError("FaceSystem: the face dofs must be strictly increasing")
        keep = np.ones(K.shape[0], bool)
        keep[base] = False
        free = np.flatnonzero(keep)
        # the base must hold K with the face free: PARDISO refuses a singular K here (StageError)
        factor = schur_factor(condense(K.tocsr(), keep), np.searchsorted(free, face_z), study)
        return cls(K, base, face_z, free, factor)

    def face_loads(self, f: np.ndarray) -> np.ndarray:
        """The loads (columns of f) condensed on the face dofs, S u0_F (u0: the face free)."""
        return self.condensed(self.free_solution(f))

    def free_solution(self, f: np.ndarray) -> np.ndarray:
        """u0 under f (columns) with the face free and the base held: one back-substitution."""
        u0 = np.zeros_like(f, dtype=float)
        u0[self.free] = self.factor.solve(f[self.free])
        return u0

    def condensed(self, u0: np.ndarray) -> np.ndarray:
        """The load whose face-free solution is u0, condensed on the face dofs: S u0_F."""
        return self.factor.S @ u0[self.face_z]

    def held(self, f: np.ndarray, r: np.ndarray, active: np.ndarray, values: np.ndarray | float = 0.0) -> np.ndarray:
        """The solution under f (face loads r) with the face dofs ``active`` held at ``values`` (per face dof, or
        one number): the open ones from S's free block, then one solve under f plus the held dofs' reactions."""
        from strainwave.fea.solver import tail_solve
        u_face = tail_solve(self.factor.S, r, active, values)
        reaction = self.factor.S[active] @ u_face - r[active]
        b = f[self.free].copy()
        b[np.searchsorted(self.free, self.face_z[active])] += reaction
        u = np.zeros_like(f)
        u[self.free] = self.factor.solve(b)
        u[self.face_z[active]] = u_face[active]
        return u


def open_compliance(S: np.ndarray, r: np.ndarray, active: np.ndarray) -> float:
    """f.u with the face dofs ``active`` held minus f.u with the whole face held: r_O . u_O (r the load f
    condensed on the face), exact without the difference of two energies."""
    from strainwave.fea.solver import tail_solve
    return float(r @ tail_solve(S, r, active))


def opening_transformation(N: int, pairs: CrackPairs) -> sp.csr_matrix:
    """T (N x N) with u = T v: v is u except at each + copy, whose dofs hold the pair's opening in the crack's
    frame (n, t1, t2): u_plus = u_minus + R w."""
    dim, m = pairs.dim, pairs.minus.size
    R = np.column_stack([pairs.normal, *tangents(pairs.normal)])
    plus = dim * pairs.plus[:, None] + np.arange(dim)
    minus = dim * pairs.minus[:, None] + np.arange(dim)
    kept = np.ones(N, bool)
    kept[plus.ravel()] = False
    kept = np.flatnonzero(kept)
    rows, cols, vals = [kept, plus.ravel()], [kept, minus.ravel()], [np.ones(kept.size), np.ones(plus.size)]
    for c in range(dim):
        for d in range(dim):
            rows.append(plus[:, c]), cols.append(plus[:, d]), vals.append(np.full(m, R[c, d]))
    T = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(N, N))
    T.eliminate_zeros()
    return T


@dataclass
class SeamSystem:
    """An opened seam's K in opening coordinates (``opening_transformation``) with ``fixed`` held, factorised
    once with its Schur complement on every pair's opening (``FaceSystem``): the seam tied (uncracked) and
    every contact set (cracked) are dense solves of its blocks."""

    pairs: CrackPairs
    T: sp.csr_matrix
    faces: FaceSystem
    normal: np.ndarray          # position of each pair's normal opening w_n among faces.face_z

    @classmethod
    def of(cls, K, fixed, pairs: CrackPairs, study: str, frame: sp.spmatrix | None = None) -> "SeamSystem":
        """``frame``: K is in other coordinates, u_K = frame u (one product with T instead of a rotated K)."""
        dim = pairs.dim
        opening = np.sort((dim * pairs.plus[:, None] + np.arange(dim)).ravel())
        if np.isin(np.concatenate([opening, (dim * pairs.minus[:, None] + np.arange(dim)).ravel()]), fixed).any():
            raise ValueError("SeamSystem: a Dirichlet condition on a crack pair's node; the pairs must be free")
        T = opening_transformation(K.shape[0], pairs)
        M = T if frame is None else (frame @ T).tocsr()
        faces = FaceSystem.of((M.T @ K.tocsr() @ M).tocsr(), np.asarray(fixed, np.int64), opening, study)
        return cls(pairs, T, faces, np.searchsorted(opening, dim * pairs.plus))

    def loads(self, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(T^T f: f in opening coordinates, its condensation r on the openings)."""
        ft = self.T.T @ f
        return ft, self.faces.face_loads(ft[:, None])[:, 0]

    def held(self, active: np.ndarray) -> np.ndarray:
        """The openings held when the pairs ``active`` are in contact: their normal openings."""
        mask = np.zeros(self.faces.face_z.size, bool)
        mask[self.normal[active]] = True
        return mask

    def solution(self, ft: np.ndarray, r: np.ndarray, held: np.ndarray) -> np.ndarray:
        """u (original coordinates) with the openings ``held`` shut (all of them: the seam tied)."""
        return self.T @ self.faces.held(ft, r, held)

    def contact(self, ft: np.ndarray, r: np.ndarray, tol_mm: float | None = None) -> ContactResult:
        """``crack_contact.solve_with_contact``'s active set and thresholds, each set a dense solve of S."""
        v0 = np.zeros_like(ft)
        v0[self.faces.free] = self.faces.factor.solve(ft[self.faces.free])
        u0 = self.T @ v0
        tol = tol_mm if tol_mm is not None else 1e-9 * float(np.abs(u0).max())
        active, gap, force, iterations, _ = self.settle(r, tol)
        return ContactResult(self.solution(ft, r, self.held(active)), active, gap, force, iterations, u0)

    def settle(self, r: np.ndarray, tol_mm: float):
        """``contact``'s active set on S alone, without the full solution: (active, normal openings, contact
        forces, set changes, every opening w)."""
        from strainwave.fea.solver import tail_solve
        S = self.faces.factor.S

        def state(active):
            w = tail_solve(S, r, self.held(active))
            return w[self.normal], np.where(active, (S @ w - r)[self.normal], 0.0)

        active, gap, force, iterations = settle_active_set(state, self.pairs.minus.size, tol_mm)
        return active, gap, force, iterations, tail_solve(S, r, self.held(active))

    def close(self) -> None:
        self.faces.factor.close()
