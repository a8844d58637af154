"""The bearing ring's crack by global-local superposition: the uncracked ring solved once per refinement
(shared by every crack depth through the run's cache folder), each depth a small cracked patch.

The patch is the cracked ring's mesh cut down to the elements whose centroid lies within ``radius`` of the
crack's mouth centre. Its cut is held at the uncracked ring's displacement (its P2 field interpolated at the
cut's nodes), its bore is held, and the race pressure acts on its part of the contact patch. One factorisation
of the opened patch with the Schur complement on the crack pairs' openings (``face_schur.SeamSystem``) gives
the patch closed (every pair tied) and cracked (frictionless contact). The crack's term r_O . S_OO^-1 r_O / F^2
is the energy released at fixed grip on the cut; to first order in the crack size that is the compliance added
at fixed load. It is the same expression the whole ring's seam gives (``bearing_ring.crack_compliances_on_mesh``),
and the crack faces see the closed patch's own discrete field, not an interpolated one: the global field's
interpolation error stays on the cut. The neglected part is the cut held rigid: O((crack / radius)^2).
"""
from __future__ import annotations

import dataclasses
import io
import json
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from strainwave.fea.mesh_data import MeshData

__all__ = ["GlobalRing", "PatchRelease", "patch_release", "ring_patch", "read_global", "write_global"]


@dataclass(frozen=True)
class GlobalRing:
    """The uncracked ring on one refinement: its mesh, its P2 field under F_r, and its compliance."""

    md: MeshData                # the ring's mesh (its named facets too: the field's file draws them)
    u: np.ndarray               # interleaved displacement at to_skfem(md)'s scalar dofs
    compliance_mm_per_N: float
    solver: dict                # the solve's facts (method, dofs, residual, ...)
    mesh_s: float = 0.0
    solve_s: float = 0.0

    def field(self):
        """(MeshData, SkfemMesh, u) as the study's field writer reads it."""
        from strainwave.fea.mesh_data import to_skfem
        return self.md, to_skfem(self.md), self.u

    def displacement(self):
        """points (n, 3) mm -> u (n, 3) mm of the uncracked ring (``crack_local.interpolate_p2``)."""
        from strainwave.fea.crack_local import interpolate_p2
        _, sk, u = self.field()
        return lambda points_mm: interpolate_p2(sk.doflocs, sk.element_dofs, u, points_mm)


def write_global(path: Path, ring: GlobalRing) -> None:
    """The ring's mesh, field and facts in one npz, written atomically (cases on two cores may race)."""
    from strainwave.io_atomic import atomic_write_bytes
    meta = {"compliance": ring.compliance_mm_per_N, "solver": ring.solver, "h_mm": ring.md.h_mm,
            "quality": None if ring.md.quality is None else ring.md.quality.to_dict()}
    buffer = io.BytesIO()
    groups = {f"group:{name}": rows for name, rows in ring.md.groups.items()}
    np.savez(buffer, nodes=ring.md.nodes_mm, cells=ring.md.cells, u=ring.u, meta=np.array(json.dumps(meta)), **groups)
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    atomic_write_bytes(Path(path), buffer.getvalue())


def read_global(path: Path) -> GlobalRing:
    from strainwave.fea.result import MeshQuality
    with np.load(path) as data:
        meta = json.loads(str(data["meta"]))
        quality = None if meta["quality"] is None else MeshQuality(**meta["quality"])
        groups = {key.split(":", 1)[1]: data[key] for key in data.files if key.startswith("group:")}
        md = MeshData(data["nodes"], data["cells"], 3, 2, groups, quality=quality, h_mm=float(meta["h_mm"]))
        return GlobalRing(md, data["u"], float(meta["compliance"]), meta["solver"])


def ring_patch(md: MeshData, centre_mm, radius_mm: float, held_group: str = "bore") -> tuple[MeshData, np.ndarray]:
    """(patch, held nodes): the elements of ``md`` whose vertex centroid lies within ``radius_mm`` of
    ``centre_mm``, renumbered; held are the nodes it shares with the elements left out (the cut) and those of
    ``held_group``. Groups keep the facets whose nodes all lie in the patch; the crack must lie wholly in it."""
    centroid = md.nodes_mm[md.cells[:, :md.dim + 1]].mean(axis=1)
    keep = np.linalg.norm(centroid - np.asarray(centre_mm, float), axis=1) < radius_mm
    used = np.unique(md.cells[keep])
    new = np.full(md.nodes_mm.shape[0], -1, np.int64)
    new[used] = np.arange(used.size)
    groups = {}
    for name, rows in md.groups.items():
        inside = (new[rows] >= 0).all(axis=1)
        if name == "crack" and not inside.all():
            raise ValueError(f"ring_patch: the crack reaches beyond the patch of radius {radius_mm:g} mm")
        groups[name] = new[rows[inside]]
    cut = np.intersect1d(used, np.unique(md.cells[~keep]))
    held = np.union1d(new[cut], np.unique(groups.get(held_group, np.zeros((0, 1), np.int64))))
    patch = dataclasses.replace(md, nodes_mm=md.nodes_mm[used], cells=new[md.cells[keep]], groups=groups,
                                quality=None)
    return patch, held


@dataclass(frozen=True)
class PatchRelease:
    delta_mm_per_N: float       # the compliance the crack adds
    info: dict                  # the solve's facts (as the whole ring's seam reports them)
    field: tuple = ()           # (opened patch, SkfemMesh, its displacement) when asked for


def patch_release(md: MeshData, centre_mm, radius_mm: float, lame, global_u, *, force_N: float, study: str,
                  load=None, keep_field: bool = False, held_group: str = "bore") -> PatchRelease:
    """The crack's compliance from the patch of ``md`` (the cracked ring's seam mesh) within ``radius_mm`` of
    ``centre_mm``, driven by the uncracked field ``global_u`` (points -> u) on its cut and on ``held_group``;
    ``load``: opened patch -> the external load vector on its faces (the race's pressure at the crack's mouth)."""
    from strainwave.fea.assembly import elasticity_stiffness, scalar_basis
    from strainwave.fea.crack_contact import crack_pairs
    from strainwave.fea.crack_seam import open_crack_for
    from strainwave.fea.face_schur import SeamSystem, open_compliance
    from strainwave.fea.mesh_data import to_skfem
    t0 = time.perf_counter()
    patch, held = ring_patch(md, centre_mm, radius_mm, held_group)
    opened = open_crack_for(patch, study)
    sk = to_skfem(opened)
    K = elasticity_stiffness(scalar_basis(sk.mesh, sk.element), lame)
    f = np.zeros(K.shape[0]) if load is None else load(opened)
    pairs = crack_pairs(opened).in_dofs(sk.node_to_dof)
    cut = sk.node_to_dof[held]
    fixed = (3 * cut[:, None] + np.arange(3)).ravel()
    lift = np.zeros(K.shape[0])
    lift[fixed] = np.asarray(global_u(sk.doflocs[:, cut].T), float).ravel()
    seam = SeamSystem.of(K, fixed, pairs, study)
    try:
        ft, r = seam.loads(f - K @ lift)      # the held cut's displacement as a load on the free dofs
        res = seam.contact(ft, r, tol_mm=1e-9 * float(np.abs(lift).max()))
        delta = open_compliance(seam.faces.factor.S, r, seam.held(res.active)) / force_N ** 2
        # the faces free to pass through each other: what the contact prevents
        free = open_compliance(seam.faces.factor.S, r, np.zeros(r.size, bool)) / force_N ** 2
    finally:
        seam.close()
    info = dict(method=f"{seam.faces.factor.method}-schur-patch", dofs=int(seam.faces.free.size),
                iterations=1, time_s=time.perf_counter() - t0, schur_dofs=int(r.size), patch_radius_mm=radius_mm,
                contact_iterations=res.iterations, contact_pairs=int(res.active.size),
                contact_closed_pairs=int(res.active.sum()), contact_min_opening_mm=float(res.opening_mm.min()),
                contact_max_opening_mm=float(res.opening_mm.max()), delta_without_contact_mm_per_N=free)
    return PatchRelease(delta, info, (opened, sk, lift + res.u) if keep_field else ())
