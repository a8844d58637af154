"""A ring's plane-stress cross-section on a structured polar P2 mesh, with an optional radial edge crack at
phi = 0 running in from the outer surface (the race).

The mesh is graded in r and phi towards the crack tip and the race; its angular columns run from phi = 0 to
2 pi, and the last column is merged into the first below the crack tip only, so the crack is two coincident
faces (the uncracked ring is the same mesh with every node merged). Crack-face node pairs go to
``fea.crack_contact`` (frictionless, active set), each set a dense solve on one factorisation with the Schur
complement on the pairs' openings (``fea.face_schur.SeamSystem``; every pair held: the faces tied). The bore sits on a cam: its radial displacement is
prescribed, its tangential one is free (a frictionless cam), with one tangential condition on the bore at
phi = 0 against the rigid rotation (on the symmetry line, so it carries no force).
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from strainwave.fea.crack_contact import CrackPairs

__all__ = ["graded_nodes", "RingMesh", "ring_mesh", "RingSystem", "assemble", "seam_system", "bore_load", "solve_ring", "crack_work", "mesh_data", "hoop_stress"]


# PARDISO's minimum-degree ordering for the stress projection's mass matrix: METIS costs more than the factors
MASS_IPARM = {1: 1, 2: 0}


def graded_nodes(x0: float, x1: float, size_fn) -> np.ndarray:
    """Nodes from x0 to x1 whose spacing follows ``size_fn(x)`` (marched, then stretched to end on x1)."""
    xs = [x0]
    while xs[-1] < x1:
        xs.append(xs[-1] + size_fn(xs[-1]))
    xs = np.asarray(xs)
    n = max(len(xs) - 1, 1)
    if len(xs) > 2 and (xs[-1] - x1) > 0.5 * (xs[-1] - xs[-2]):
        n -= 1               # the overshooting step is dropped; the others stretch a little
    xs = x0 + (xs[: n + 1] - x0) * (x1 - x0) / (xs[n] - x0)
    return xs


@dataclass(frozen=True)
class RingMesh:
    mesh: object                  # skfem MeshTri
    r_mm: np.ndarray              # radial node positions (bore first)
    phi_rad: np.ndarray           # angular columns, 0 .. 2 pi
    crack_pairs: CrackPairs | None      # scalar node indices (minus: phi = 0+ side, plus: phi = 2pi- side)


def _node_index(n_r: int, n_phi: int, merge_below: int):
    """Index of node (i, j), i radial, j angular 0..n_phi; column n_phi merges into 0 for i <= merge_below."""
    idx = np.arange(n_r * (n_phi + 1)).reshape(n_r, n_phi + 1)
    idx[: merge_below + 1, n_phi] = idx[: merge_below + 1, 0]
    used = np.unique(idx)
    remap = np.full(idx.max() + 1, -1)
    remap[used] = np.arange(used.size)
    return remap[idx]


def ring_mesh(r_mm: np.ndarray, phi_rad: np.ndarray, crack_tip_index: int | None):
    """P1 triangles on the polar grid; ``crack_tip_index``: radial index of the crack tip (None: uncracked).
    Returns (skfem MeshTri, crack nodes (minus, plus, tip) or None)."""
    from skfem import MeshTri

    n_r, n_phi = len(r_mm), len(phi_rad) - 1
    merge = n_r - 1 if crack_tip_index is None else crack_tip_index
    idx = _node_index(n_r, n_phi, merge)
    rr, pp = np.meshgrid(r_mm, phi_rad, indexing="ij")
    pts = np.zeros((2, idx.max() + 1))
    pts[0, idx.ravel()] = (rr * np.cos(pp)).ravel()
    pts[1, idx.ravel()] = (rr * np.sin(pp)).ravel()
    a, b = idx[:-1, :-1], idx[:-1, 1:]
    c, d = idx[1:, :-1], idx[1:, 1:]
    # alternate diagonals so the grid has no preferred direction
    flip = ((np.arange(n_r - 1)[:, None] + np.arange(n_phi)[None, :]) % 2).astype(bool)
    t1 = np.where(flip[..., None], np.stack([a, b, d], -1), np.stack([a, b, c], -1))
    t2 = np.where(flip[..., None], np.stack([a, d, c], -1), np.stack([b, d, c], -1))
    tris = np.concatenate([t1.reshape(-1, 3), t2.reshape(-1, 3)]).T
    pairs = None
    if crack_tip_index is not None:
        rows = np.arange(crack_tip_index + 1, n_r)
        pairs = (idx[rows, 0], idx[rows, n_phi], int(idx[crack_tip_index, 0]))
    pts[1, idx[:, 0]] = 0.0                  # phi = 0 exactly (the merged nodes were written at 2 pi last)
    return MeshTri(np.ascontiguousarray(pts), np.ascontiguousarray(tris)), pairs


@dataclass(frozen=True)
class RingSystem:
    """Assembled plane-stress system in nodal (r, phi) coordinates at the bore, global (x, y) elsewhere."""

    K_global: sp.csr_matrix        # the stiffness in global (x, y) at every node
    R: sp.csr_matrix               # u_global = R u_local
    scalar: object                 # scalar P2 basis
    bore_dofs: np.ndarray          # scalar dofs on the bore
    pairs: CrackPairs | None       # crack dof pairs (scalar dof numbers)
    width_mm: float

    @cached_property
    def K(self) -> sp.csr_matrix:
        """The stiffness in the nodal frames, R^T K R (made when read: the crack's seam takes R into its own)."""
        return (self.R.T @ self.K_global @ self.R).tocsr()


def _edge_dofs(mesh, scalar, a_nodes: np.ndarray, b_nodes: np.ndarray) -> np.ndarray:
    """Scalar P2 dofs of the mesh edges (a_k, b_k) (their mid-side dofs)."""
    n = np.int64(mesh.p.shape[1])
    facets = np.sort(mesh.facets, axis=0).astype(np.int64)
    keys = facets[0] * n + facets[1]
    a, b = np.asarray(a_nodes, np.int64), np.asarray(b_nodes, np.int64)
    want = np.minimum(a, b) * n + np.maximum(a, b)
    order = np.argsort(keys)
    ids = order[np.minimum(np.searchsorted(keys[order], want), keys.size - 1)]
    if not np.array_equal(keys[ids], want):
        raise ValueError("ring2d: a crack edge is not an edge of the mesh")
    return scalar.facet_dofs[0, ids]


def assemble(mesh, pairs_nodes, *, E_MPa: float, nu: float, width_mm: float, r_bore_mm: float) -> RingSystem:
    """Plane stress (thickness = ring width B) P2 stiffness, rotated to (r, phi) at the bore nodes."""
    from skfem import Basis, ElementTriP2

    from strainwave.fea.assembly import Lame, elasticity_stiffness

    scalar = Basis(mesh, ElementTriP2())
    K = elasticity_stiffness(scalar, Lame.from_young(E_MPa, nu, plane_stress=True), thickness_mm=width_mm)
    xy = scalar.doflocs
    bore = np.flatnonzero(np.hypot(*xy) < r_bore_mm * (1.0 + 1e-9))     # nodes and chord midpoints
    R = _bore_rotation(2 * scalar.N, bore, np.arctan2(xy[1, bore], xy[0, bore]))
    pairs = None
    if pairs_nodes is not None:
        minus, plus, tip = pairs_nodes
        m_edges = _edge_dofs(mesh, scalar, np.r_[tip, minus[:-1]], minus)
        p_edges = _edge_dofs(mesh, scalar, np.r_[tip, plus[:-1]], plus)
        # sides: minus = phi = 0+ (y > 0 elements), plus = 2pi- (y < 0); n points from minus to plus
        pairs = CrackPairs(np.concatenate([minus, m_edges]), np.concatenate([plus, p_edges]), np.array([0.0, -1.0]))
    return RingSystem(K.tocsr(), R, scalar, bore, pairs, width_mm)


def _bore_rotation(n: int, bore: np.ndarray, phi: np.ndarray) -> sp.csr_matrix:
    """R with u_global = R u_local: identity, and at the bore dofs (u_x, u_y) = rot(phi) (u_r, u_phi)."""
    keep = np.ones(n, bool)
    keep[2 * bore] = False
    keep[2 * bore + 1] = False
    keep = np.flatnonzero(keep)
    c, s = np.cos(phi), np.sin(phi)
    rows = np.concatenate([keep, 2 * bore, 2 * bore, 2 * bore + 1, 2 * bore + 1])
    cols = np.concatenate([keep, 2 * bore, 2 * bore + 1, 2 * bore, 2 * bore + 1])
    vals = np.concatenate([np.ones(keep.size), c, -s, s, c])
    return sp.csr_matrix((vals, (rows, cols)), shape=(n, n))


def _direct(K, f, fixed):
    """Zero Dirichlet ``fixed``; the project's sparse direct solver (PARDISO when installed, else SuperLU)."""
    from strainwave.fea.solver import _direct as direct

    u = np.zeros(f.shape)
    free = np.setdiff1d(np.arange(K.shape[0]), fixed)
    u[free] = direct(K[free][:, free].tocsr(), np.ascontiguousarray(f[free]), "wg-bearing")[0].reshape(u[free].shape)
    return u


def _bore_fixed(system: "RingSystem") -> np.ndarray:
    """The bore's radial dofs and, against the rigid rotation, the tangential dof of the bore at phi = 0."""
    xy = system.scalar.doflocs[:, system.bore_dofs]
    anchor = system.bore_dofs[np.argmin(np.hypot(xy[0] - np.hypot(*xy).max(), xy[1]))]
    return np.concatenate([2 * system.bore_dofs, [2 * anchor + 1]])


def seam_system(system: "RingSystem"):
    """The cracked ring with the bore held, factorised once with its Schur complement on the crack pairs'
    openings (``face_schur.SeamSystem``): the faces tied and every contact set are dense solves on it."""
    from strainwave.fea.face_schur import SeamSystem
    return SeamSystem.of(system.K_global, _bore_fixed(system), system.pairs, "wg-bearing", frame=system.R)


def _with_seam(system: "RingSystem", seam, job):
    """``job(seam)`` on ``seam``, or on the system's own one made and freed for it when None."""
    if seam is not None:
        return job(seam)
    seam = seam_system(system)
    try:
        return job(seam)
    finally:
        seam.close()


def _bore_displacement(system: RingSystem, bore_radial_mm: np.ndarray | None) -> np.ndarray:
    """The prescribed part of u (nodal frames): the bore's radial dofs at ``bore_radial_mm`` (None = 0)."""
    up = np.zeros(system.R.shape[0])
    if bore_radial_mm is not None:
        up[2 * system.bore_dofs] = bore_radial_mm
    return up


def bore_load(system: RingSystem, bore_radial_mm: np.ndarray | None) -> np.ndarray:
    """The loads (nodal frames) the bore's prescribed radial displacement puts on the other dofs: -K u_p."""
    R = system.R
    return -(R.T @ (system.K_global @ (R @ _bore_displacement(system, bore_radial_mm))))


def solve_ring(system: RingSystem, f_global: np.ndarray, bore_radial_mm: np.ndarray | None, seam=None):
    """Displacements (global x, y interleaved) under the loads ``f_global`` with the bore's radial
    displacement prescribed (``bore_radial_mm`` per bore dof, None = 0). With a crack the faces may separate
    but not interpenetrate (frictionless contact, ``crack_contact``'s active set, each set a dense solve on
    ``seam``: ``seam_system``'s factorisation, made here when None). Returns (u, contact result or None)."""
    up = _bore_displacement(system, bore_radial_mm)
    fixed = _bore_fixed(system)
    f = system.R.T @ f_global + bore_load(system, bore_radial_mm)
    if system.pairs is None:
        return system.R @ (up + _direct(system.K, f, fixed)), None
    res = _with_seam(system, seam, lambda sm: sm.contact(*sm.loads(f)))
    return system.R @ (up + res.u), res


def crack_work(seam, r_f: np.ndarray, force_base: np.ndarray, force_loaded: np.ndarray) -> float:
    """f.(u(base + f) - u(base)) on the cracked mesh minus f.u on it tied, from the Schur complement alone: r_f
    the loads f condensed on the openings (``seam.loads``), ``force_base`` and ``force_loaded`` the held normal
    openings' reactions (contact forces) of a state without and with f. w_f . (lambda_loaded - lambda_base + r_f)
    with w_f = S^-1 r_f, without the difference of the full solutions' energies."""
    from strainwave.fea.solver import tail_solve
    w = tail_solve(seam.faces.factor.S, r_f, np.zeros(r_f.size, bool))
    return float(r_f @ w + w[seam.normal] @ (force_loaded - force_base))


def race_facets(mesh, r_race_mm: float) -> np.ndarray:
    """Boundary facets with both ends on the race (outer circle)."""
    bf = mesh.boundary_facets()
    r = np.hypot(*mesh.p[:, mesh.facets[:, bf]])
    return bf[np.all(np.abs(r - r_race_mm) < 1e-7 * r_race_mm, axis=0)]


def patch_load_vectors(system: RingSystem, r_race_mm: float, angles_rad, half_widths_mm) -> np.ndarray:
    """(dofs x balls): ball j's Hertz line patch sqrt(1 - (s/b_j)^2) on the race, pressing radially inward,
    scaled to a unit radial resultant (the polygonal race and the quadrature of the sqrt edge leave it
    slightly off otherwise)."""
    from skfem import ElementTriP2, ElementVector, FacetBasis, LinearForm

    mesh = system.scalar.mesh
    race = race_facets(mesh, r_race_mm)
    ends = mesh.p[:, mesh.facets[:, race]]
    length, angle = np.hypot(*(ends[:, 1] - ends[:, 0])), np.arctan2(ends[1], ends[0])
    # the facets a patch touches: elsewhere every pressure is exactly zero
    touched = np.zeros(race.size, bool)
    for psi, b in zip(angles_rad, half_widths_mm):
        touched |= r_race_mm * np.abs(np.angle(np.exp(1j * (angle - psi)))).min(axis=0) < b + length
    fb = FacetBasis(mesh, ElementVector(ElementTriP2()), facets=race[touched], intorder=10)
    out = np.zeros((system.R.shape[0], len(angles_rad)))
    for j, (psi, b) in enumerate(zip(angles_rad, half_widths_mm)):
        @LinearForm
        def patch(v, w, psi=psi, b=b):
            x, y = w.x
            r = np.sqrt(x ** 2 + y ** 2)
            s = r_race_mm * np.angle(np.exp(1j * (np.arctan2(y, x) - psi)))
            p = np.sqrt(np.clip(1.0 - (s / b) ** 2, 0.0, None))
            return -p * (v[0] * x + v[1] * y) / r
        f = patch.assemble(fb)
        resultant = -(f[0::2].sum() * np.cos(psi) + f[1::2].sum() * np.sin(psi))
        out[:, j] = f / resultant
    return out


def solve_many(system: RingSystem, F_global: np.ndarray, *, tied: bool = False, seam=None,
               bore_radial_mm: np.ndarray | None = None) -> np.ndarray:
    """Columns of displacements under the load columns ``F_global``, the bore held radially; ``tied``: a
    cracked mesh solved with its crack faces joined (the uncracked ring on the same mesh: every pair's opening
    held on ``seam``, ``seam_system``'s factorisation, made here when None). Without ``tied`` no crack contact
    is imposed (the uncracked ring, or an open crack), and ``bore_radial_mm`` adds a first column: the bore's
    radial displacement prescribed without loads (``solve_ring``'s, from the same factorisation)."""
    fixed = _bore_fixed(system)
    F = system.R.T @ F_global
    if not tied or system.pairs is None:
        if bore_radial_mm is None:
            return system.R @ _direct(system.K, F, fixed)
        up = _bore_displacement(system, bore_radial_mm)
        U = _direct(system.K, np.column_stack([-(system.K @ up), F]), fixed)
        U[:, 0] += up
        return system.R @ U

    def tied_columns(sm):
        held = np.ones(sm.faces.face_z.size, bool)
        return np.column_stack([sm.solution(*sm.loads(F[:, k]), held) for k in range(F.shape[1])])
    return system.R @ _with_seam(system, seam, tied_columns)


def nodal_stress(system: RingSystem, u: np.ndarray, E_MPa: float, nu: float) -> np.ndarray:
    """(3, scalar dofs): plane-stress sigma_xx, sigma_yy, sigma_xy L2-projected onto the P2 space; for columns
    of displacements u (dofs, k), (k, 3, scalar dofs) from one factorisation of the mass matrix."""
    from skfem import BilinearForm, LinearForm

    from strainwave.fea.solver import _direct as direct

    c = E_MPa / (1.0 - nu ** 2)
    rhs = LinearForm(lambda v, w: w["s"] * v)
    b = []
    for column in np.reshape(u, (u.shape[0], -1)).T:
        gx, gy = (system.scalar.interpolate(column[k::2]).grad for k in (0, 1))
        exx, eyy, exy = gx[0], gy[1], 0.5 * (gx[1] + gy[0])
        comps = (c * (exx + nu * eyy), c * (eyy + nu * exx), E_MPa / (1.0 + nu) * exy)
        b += [rhs.assemble(system.scalar, s=s) for s in comps]
    b = np.column_stack(b)
    mass = BilinearForm(lambda a, b, w: a * b).assemble(system.scalar).tocsr()
    stress = direct(mass, b, "wg-bearing", iparm=MASS_IPARM)[0].reshape(b.shape).T
    return stress if np.ndim(u) == 1 else stress.reshape(-1, 3, stress.shape[1])


def hoop_stress_at(system: RingSystem, stress: np.ndarray, points_xy: np.ndarray) -> np.ndarray:
    """sigma_phiphi at the points (2, n) from the projected nodal stress."""
    P = system.scalar.probes(points_xy)
    return hoop_stress(points_xy, np.stack([P @ s for s in stress]))


def triangle_quality(mesh) -> tuple[float, float]:
    """(min, mean) of 4 sqrt(3) area / sum of squared edges: 1 for an equilateral triangle."""
    p = mesh.p[:, mesh.t]
    e = [p[:, 1] - p[:, 0], p[:, 2] - p[:, 1], p[:, 0] - p[:, 2]]
    area = 0.5 * np.abs(e[0][0] * e[1][1] - e[0][1] * e[1][0])
    q = 4.0 * np.sqrt(3.0) * area / sum((v ** 2).sum(axis=0) for v in e)
    return float(q.min()), float(q.mean())


def mesh_data(system: RingSystem, r_bore_mm: float, r_race_mm: float):
    """The P2 ring as ``MeshData`` (6-node triangles on the scalar dofs, z = 0) with the boundary groups
    ``bore`` and ``race`` (3-node edges), for the field writer (fea/fields.py)."""
    from strainwave.fea.mesh_data import MeshData

    mesh, scalar = system.scalar.mesh, system.scalar
    xy = scalar.doflocs
    groups = {}
    bf = mesh.boundary_facets()
    r = np.hypot(*mesh.p[:, mesh.facets[:, bf]])
    for name, radius in (("bore", r_bore_mm), ("race", r_race_mm)):
        on = bf[np.all(np.abs(r - radius) < 1e-7 * radius, axis=0)]
        # skfem numbers a P2 basis's vertex dofs as the mesh's vertices, its edge dofs after them
        groups[name] = np.column_stack([mesh.facets[0, on], mesh.facets[1, on], scalar.facet_dofs[0, on]])
    nodes = np.column_stack([xy[0], xy[1], np.zeros(xy.shape[1])])
    return MeshData(nodes, np.ascontiguousarray(scalar.element_dofs.T), 2, 2, groups)


def hoop_stress(points_xy: np.ndarray, stress: np.ndarray) -> np.ndarray:
    """sigma_phiphi at points (2, n) from (sigma_xx, sigma_yy, sigma_xy) (3, n) there."""
    phi = np.arctan2(points_xy[1], points_xy[0])
    c, s = np.cos(phi), np.sin(phi)
    return stress[0] * s * s - 2.0 * stress[2] * s * c + stress[1] * c * c
