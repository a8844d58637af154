"""Global-local crack compliance: the crack in a small local model driven by the uncracked global solution.

The global model is solved once, uncracked (no crack-front refinement, so its mesh does not depend on the
crack depth). The local model is a patch of the part around the crack, meshed with the crack as a seam
(``crack_seam``) and refined at its front (a through-wall crack: ``crack_extruded``), its cut faces held at
the global displacement (interpolated on the global curved P2 mesh), every other face as in the global
model (traction free here). Opened, its strain energy falls by dU: the energy the crack releases at fixed
grip on the cut, solved once on the opened mesh by Bueckner's superposition (``local_release``). To first
order in the crack size this is the energy released at fixed load, half the compliance change times the
load squared, so delta lambda = 2 dU / T^2 for the torque T of the global load. The neglected part is the
patch's boundary held rigid: O((a / L)^2) for a patch of half size L.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from strainwave.fea.element_gradients import SKFEM_EDGES
from strainwave.fea.mesh_data import MeshData, group_dofs

# Newton steps of the inverse P2 map; reference coordinates converge quadratically from the straight tet's
NEWTON_STEPS = 8
OUTSIDE_TOL = 0.05      # largest distance outside the nearest element (in its size) still extrapolated


def _p2_shape(lam: np.ndarray) -> np.ndarray:
    """(..., 10 or 6) P2 shape values at barycentric ``lam`` (..., 4 or 3) of a tet or a triangle: vertices,
    then SKFEM_EDGES' edges."""
    vert = lam * (2.0 * lam - 1.0)
    edge = np.stack([4.0 * lam[..., a] * lam[..., b] for a, b in SKFEM_EDGES[lam.shape[-1] - 1]], axis=-1)
    return np.concatenate([vert, edge], axis=-1)


def _p2_shape_grad(lam: np.ndarray) -> np.ndarray:
    """(..., nloc, d) derivatives of ``_p2_shape`` w.r.t. the reference coordinates (lam1 .. lam_d)."""
    d = lam.shape[-1] - 1
    dlam = np.vstack([-np.ones(d), np.eye(d)])
    vert = (4.0 * lam - 1.0)[..., None] * dlam
    edge = np.stack([4.0 * (lam[..., a, None] * dlam[b] + lam[..., b, None] * dlam[a]) for a, b in SKFEM_EDGES[d]],
                    axis=-2)
    return np.concatenate([vert, edge], axis=-2)


def _reference_coords(x: np.ndarray, elem_x: np.ndarray) -> np.ndarray:
    """Barycentric coordinates (n, d + 1) of points ``x`` (n, d) in curved P2 simplices with nodes ``elem_x``
    (n, nloc, d)."""
    d = x.shape[1]
    v = elem_x[:, :d + 1]
    J = np.stack([v[:, k] - v[:, 0] for k in range(1, d + 1)], axis=-1)
    xi = np.linalg.solve(J, (x - v[:, 0])[..., None])[..., 0]      # straight simplex: the start
    for _ in range(NEWTON_STEPS):
        lam = np.concatenate([1.0 - xi.sum(axis=1, keepdims=True), xi], axis=1)
        r = np.einsum("nk,nkd->nd", _p2_shape(lam), elem_x) - x
        Jc = np.einsum("nkd,nke->nde", elem_x, _p2_shape_grad(lam))
        xi -= np.linalg.solve(Jc, r[..., None])[..., 0]
    lam = np.concatenate([1.0 - xi.sum(axis=1, keepdims=True), xi], axis=1)
    miss = np.linalg.norm(np.einsum("nk,nkd->nd", _p2_shape(lam), elem_x) - x, axis=1)
    size = np.linalg.norm(v[:, 1:] - v[:, :1], axis=2).max(axis=1)
    # a Newton run that did not converge (a far candidate's map extrapolated) must not win the choice
    lam[~(miss <= 1e-8 * size)] = -np.inf
    return lam


def interpolate_p2(doflocs: np.ndarray, element_dofs: np.ndarray, u: np.ndarray, points_mm: np.ndarray,
                   components: int = 3) -> np.ndarray:
    """(n, components) values at ``points_mm`` (n, d) of the interleaved P2 field ``u`` on a curved tet10
    (d = 3) or triangle6 (d = 2) mesh (scikit-fem numbering: ``doflocs`` (d, N), ``element_dofs`` (nloc,
    nel)). Each point takes the element that holds it most deeply (largest smallest barycentric coordinate)
    among those whose bounding box holds it: a point of a curved surface may lie a hair outside every
    element, and then the nearest one extrapolates its polynomial."""
    pts = np.asarray(points_mm, float)
    d = pts.shape[1]
    elem = doflocs[:, element_dofs].transpose(2, 1, 0)                # (nel, nloc, d)
    centroids = elem[:, :d + 1].mean(axis=1)
    reach = np.linalg.norm(elem - centroids[:, None], axis=2).max(axis=1)
    # an element whose padded box misses the points' box holds none: a patch's points need not search the part
    pad = OUTSIDE_TOL * reach[:, None]
    keep = np.all((elem.min(axis=1) - pad <= pts.max(axis=0)) & (elem.max(axis=1) + pad >= pts.min(axis=0)), axis=1)
    if not keep.any():
        raise ValueError(f"interpolate_p2: {pts.shape[0]} points lie outside the mesh")
    element_dofs, elem, centroids, reach = element_dofs[:, keep], elem[keep], centroids[keep], reach[keep]
    # every element whose node ball can hold the point (flat wall elements: the holder's centroid may be far)
    near = cKDTree(centroids).query_ball_point(pts, r=float(reach.max()) * (1.0 + OUTSIDE_TOL))
    pi = np.repeat(np.arange(pts.shape[0]), [len(c) for c in near])
    el = np.fromiter((e for c in near for e in c), np.int64, count=pi.size)
    pad = OUTSIDE_TOL * reach[el, None]
    keep = np.all((pts[pi] >= elem[el].min(axis=1) - pad) & (pts[pi] <= elem[el].max(axis=1) + pad), axis=1)
    pi, el = pi[keep], el[keep]
    if np.unique(pi).size < pts.shape[0]:
        raise ValueError(f"interpolate_p2: {pts.shape[0] - np.unique(pi).size} points lie outside the mesh")
    lam = _reference_coords(pts[pi], elem[el])
    order = np.lexsort((-lam.min(axis=1), pi))                        # per point, deepest first
    first = order[np.r_[True, pi[order][1:] != pi[order][:-1]]]
    best_lam, best_el = lam[first], el[first]
    elem_x = doflocs[:, element_dofs[:, best_el]].transpose(2, 1, 0)
    inside = np.clip(best_lam, 0.0, None)
    inside /= inside.sum(axis=1, keepdims=True)
    gap = np.linalg.norm(np.einsum("nk,nkd->nd", _p2_shape(inside), elem_x) - pts, axis=1)
    size = np.linalg.norm(elem_x[:, 1:d + 1] - elem_x[:, :1], axis=2).max(axis=1)
    # points of the patch's curved faces may lie a hair outside the global P2 surface: extrapolated
    far = ~(gap <= OUTSIDE_TOL * size)
    if far.any():
        raise ValueError(f"interpolate_p2: {int(far.sum())} points lie outside the mesh (up to "
                         f"{float(np.nanmax(np.where(far, gap, 0.0))):.3g} mm)")
    phi = _p2_shape(best_lam)                                          # (n, nloc)
    dofs = element_dofs[:, best_el].T                                  # (n, nloc) scalar dofs
    return np.stack([np.einsum("nk,nk->n", phi, u[components * dofs + c]) for c in range(components)], axis=1)


@dataclass(frozen=True)
class LocalEnergy:
    released_Nmm: float     # strain energy the opened crack releases at fixed grip on the patch's cut
    dofs: int               # of the opened patch
    solve_s: float
    field: tuple = ()       # (opened mesh, skfem mesh, displacement of the opened patch) when asked for


def patch_energy(md: MeshData, lame, global_u, *, group: str = "cut", study: str = "fea",
                 plane_strain_faces: str | None = None, method: str = "direct") -> tuple[float, int, float]:
    """(strain energy, dofs, solve s) of ``md`` with the nodes of ``group`` held at ``global_u(points)``
    (n, 3) mm and every other face free; ``plane_strain_faces``: a group whose other nodes keep u_z = 0
    (the faces of a slab in plane strain); ``method``: "direct", or "amg" (p-multigrid CG on a P2 mesh),
    faster on a chunky patch and slower on a thin plate-like one (``patch_solver``)."""
    from strainwave.fea.static import assemble
    sk, K, f, _, _ = assemble(md, lame, study=study)
    dofs = _held_dofs(sk, md, group, plane_strain_faces)
    cut = group_dofs(sk, md, group)          # _held_dofs lists the cut's 3 components first
    values = np.zeros(dofs.size)
    values[: 3 * cut.size] = np.asarray(global_u(sk.doflocs[:, cut].T), float).ravel()
    u, info = _solve(K, f, sk, md, dofs, values, method, study)
    return 0.5 * float(u @ (K @ u)), info.dofs, info.time_s


def _held_dofs(sk, md: MeshData, group: str, plane_strain_faces: str | None) -> np.ndarray:
    """The dofs a patch holds: every component on ``group`` (the cut), u_z on a plane-strain slab's faces."""
    nodes = group_dofs(sk, md, group)
    dofs = (3 * nodes[:, None] + np.arange(3)).ravel()
    if plane_strain_faces is None:
        return dofs
    return np.concatenate([dofs, 3 * np.setdiff1d(group_dofs(sk, md, plane_strain_faces), nodes) + 2])


def _solve(K, f, sk, md: MeshData, dofs, values, method: str, study: str, rtol: float | None = None):
    from strainwave.fea.solver import DEFAULT_RTOL, solve_elasticity
    pmg = method == "amg" and md.order == 2
    return solve_elasticity(K, f, fixed_dofs=dofs, fixed_values=values, coords=sk.doflocs, dim=3,
                            study=study, method="amg" if pmg else "direct", rtol=rtol or DEFAULT_RTOL,
                            p2_element_dofs=sk.element_dofs if pmg else None)


# Patch span over thickness up to which p-multigrid CG to RELEASE_RTOL beats PARDISO: a chunky block factorises
# with 3D fill, a thin plate-like one with little, while CG's iterations grow with the span (docs/decisions/063)
AMG_MAX_SPAN_OVER_THICKNESS = 16.0
# CG residual for the released energy: CG minimises the energy error, which is quadratic in the residual,
# so 1e-3 leaves under 1e-6 of dU, a ten-thousandth of the patch's GCI (docs/decisions/063)
RELEASE_RTOL = 1e-3


def patch_solver(span_mm: float, thickness_mm: float) -> str:
    """"amg" for a chunky patch (span / thickness up to AMG_MAX_SPAN_OVER_THICKNESS), else "direct"."""
    return "amg" if span_mm <= AMG_MAX_SPAN_OVER_THICKNESS * thickness_mm else "direct"


def local_release(md: MeshData, lame, global_u, *, study: str, plane_strain_faces: str | None = None,
                  method: str = "direct", keep_field: bool = False, rtol: float | None = None) -> LocalEnergy:
    """The energy the crack releases in the patch, by Bueckner's superposition on the opened mesh.

    The uncracked field w = ``global_u`` at the nodes of the opened patch is in equilibrium except across the
    crack, where K w leaves equal and opposite forces r on the two faces' node pairs (their antisymmetric
    part: the symmetric rest is w's interpolation residual). The opened patch is w + v with K v = -r and
    v = 0 where the patch is held, so its energy falls by -v.r / 2: the closed-minus-opened difference of
    two fixed-grip solves, from one solve and without subtracting two large energies. ``rtol``: CG's residual
    with ``method`` "amg" (solver.DEFAULT_RTOL by default; ``RELEASE_RTOL`` suffices for dU)."""
    from strainwave.fea.crack_contact import crack_pairs
    from strainwave.fea.crack_seam import open_crack_for
    from strainwave.fea.static import assemble
    opened = open_crack_for(md, study)
    sk, K, _, _, _ = assemble(opened, lame, study=study)
    pairs = crack_pairs(opened).in_dofs(sk.node_to_dof)
    # K's rows at the faces reach only the nodes of the elements that touch them: w is needed there alone
    near = np.isin(sk.element_dofs, np.concatenate([pairs.plus, pairs.minus])).any(axis=0)
    reach = np.arange(sk.doflocs.shape[1]) if keep_field else np.unique(sk.element_dofs[:, near])
    w = np.zeros((sk.doflocs.shape[1], 3))
    w[reach] = np.asarray(global_u(sk.doflocs[:, reach].T), float)
    faces = (3 * np.concatenate([pairs.plus, pairs.minus])[:, None] + np.arange(3)).ravel()
    kw = np.zeros(K.shape[0])
    kw[faces] = K.tocsr()[faces] @ w.ravel()
    kw = kw.reshape(-1, 3)
    half_jump = 0.5 * (kw[pairs.plus] - kw[pairs.minus])
    r = np.zeros_like(kw)
    r[pairs.plus], r[pairs.minus] = half_jump, -half_jump
    v, info = _solve(K, -r.ravel(), sk, opened, _held_dofs(sk, opened, "cut", plane_strain_faces), 0.0, method,
                     study, rtol)
    field = (opened, sk, w.ravel() + v) if keep_field else ()
    return LocalEnergy(-0.5 * float(v @ r.ravel()), info.dofs, info.time_s, field)


def compliance_from_release(released_Nmm: float, load: float) -> float:
    """delta compliance at fixed load from the energy released at fixed grip: 2 dU / P^2 (first order)."""
    if not (load != 0.0 and math.isfinite(load)):
        raise ValueError(f"compliance_from_release: load must be finite and nonzero, got {load}")
    return 2.0 * released_Nmm / load ** 2
