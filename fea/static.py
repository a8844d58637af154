"""One linear static elasticity solve on a MeshData: the glue every study shares.

mesh -> scikit-fem numbering (curved P2) -> element geometry -> vectorised stiffness -> traction loads
-> Dirichlet solve, with the time of each phase recorded and reported through ``progress``. No
scikit-fem CellBasis is built on the way (``StaticSolution.basis`` makes one on first use).
The assembly phase is timed per size by ``benchmarks/bench_fea.py`` (``assembly_s``, ``peak_GB``); systems that
take the fused p-multigrid (and so load numba) are assembled and condensed by numba kernels
(``assembly_kernels``; docs/decisions/004-assembly-kernels.md).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from functools import cached_property
from typing import Callable, Mapping

import numpy as np

from strainwave.fea import fused_sweeps
from strainwave.fea.assembly import (Lame, ThermalStrain, compiled_stiffness, facet_vector_basis, scalar_basis, stiffness,
                                     thermal_load)
from strainwave.fea.element_gradients import default_intorder, element_geometry
from strainwave.fea.mesh_data import MeshData, SkfemMesh, facet_indices, group_dofs, to_skfem
from strainwave.errors import StageError
from strainwave.fea.solver import SolverInfo, solve_elasticity
from strainwave.fea.surface import SurfaceQuadrature

Traction = Callable[[np.ndarray], np.ndarray]     # x (dim, nf, nq) mm -> t (dim, nf, nq) MPa


@dataclass(frozen=True)
class StaticSolution:
    md: MeshData
    sk: SkfemMesh
    u: np.ndarray                 # interleaved displacement, mm
    lame: Lame
    solver: SolverInfo
    timings_s: dict = field(default_factory=dict)

    @cached_property
    def basis(self):
        """Scalar scikit-fem CellBasis on the solution's mesh (built on first use: assembly needs none)."""
        return scalar_basis(self.sk.mesh, self.sk.element)

    def surface(self, group: str) -> SurfaceQuadrature:
        """Quadrature on a named group's own facets (robust on any element shape)."""
        return SurfaceQuadrature.of(self.md, group)

    def nodal_u(self) -> np.ndarray:
        """(N, dim) displacement at MeshData nodes."""
        d = self.md.dim
        return np.stack([self.u[d * self.sk.node_to_dof + c] for c in range(d)], axis=1)

    def facet_basis(self, group: str, *, intorder: int = 4):
        """Vector FacetBasis on a named boundary group (integrals over a loaded face)."""
        return facet_vector_basis(self.sk.mesh, self.sk.element, facet_indices(self.sk, self.md, group),
                                  intorder=intorder)


def _assemble(md, lame, fixed, fixed_dofs, fixed_values, tractions, point_loads, thickness_mm, study, progress,
              compiled=False, thermal=None):
    sk = to_skfem(md)
    d = md.dim
    progress(f"{study}: assembling {sk.doflocs.shape[1] * d} dofs (P{md.order}, {md.cells.shape[0]} elements)")
    # node blocks: solve_elasticity condenses them and reuses them for the AMG (no BSR -> CSR -> BSR)
    if compiled:
        load_assembly_kernels()
        fused_sweeps.warm_up()    # the sweeps' kernels load while the assembly's run (those release the lock)
        K = compiled_stiffness(sk.doflocs, sk.element_dofs, md.order, lame)
    else:
        K = stiffness(element_geometry(sk.doflocs, sk.element_dofs, md.order), lame, thickness_mm=thickness_mm,
                      fmt="bsr")
    f = np.zeros(K.shape[0])
    for group, trac in (tractions or {}).items():
        # facet-own quadrature (no element inversion): robust on curved and sliver P2 elements
        f += (thickness_mm if d == 2 else 1.0) * SurfaceQuadrature.of(md, group).load_vector(
            trac, sk.node_to_dof, d, K.shape[0])
    if point_loads is not None:
        f += point_loads
    if thermal is not None:
        f += thermal_load(sk.doflocs, sk.element_dofs, md.order, lame, thermal, thickness_mm=thickness_mm)
    dofs, vals = [], []
    for group, value in (fixed or {}).items():
        nodes = group_dofs(sk, md, group)
        v = np.broadcast_to(np.asarray(value, float), (d,))
        dofs.append((d * nodes[:, None] + np.arange(d)).ravel())
        vals.append(np.tile(v, nodes.size))
    if fixed_dofs is not None:
        dofs.append(np.asarray(fixed_dofs, np.int64))
        vals.append(np.broadcast_to(np.asarray(fixed_values, float), np.shape(fixed_dofs)))
    all_dofs = np.concatenate(dofs) if dofs else np.zeros(0, np.int64)
    all_vals = np.concatenate(vals) if vals else np.zeros(0)
    return sk, K, f, all_dofs, all_vals


def assemble(md: MeshData, lame: Lame, *, fixed: Mapping[str, float | np.ndarray] | None = None,
             tractions: Mapping[str, Traction] | None = None, study: str = "fea",
             progress: Callable[[str], None] = lambda m: None):
    """(skfem mesh, K in node blocks, f, fixed dofs, their values) as ``solve_static`` assembles them, for
    callers that need K after the solve (a strain energy 1/2 u.K u); K is never consumed here."""
    return _assemble(md, lame, fixed, None, 0.0, tractions, None, 1.0, study, progress)


def load_assembly_kernels() -> None:
    """numba and the assembly's kernels, loaded in this thread before the sweeps' warm-up thread starts:
    loaded beside it, both held the interpreter lock in turn and numpy's many short calls in to_skfem and
    the geometry waited for it (docs/decisions/004-assembly-kernels.md)."""
    from strainwave.fea import assembly_kernels
    assembly_kernels.load()


def p1_stiffness(sk: SkfemMesh, lame: Lame, *, compiled: bool = False):
    """Stiffness of the P1 field on the curved P2 mesh ``sk`` with the P2 stiffness' quadrature, in node
    blocks over the vertex dofs: the p-multigrid's coarse operator (``solve_elasticity``). ``compiled``:
    by the numba kernels, as the P2 stiffness of the same solve."""
    nv = 4 if sk.element_dofs.shape[0] == 10 else 3
    n_vertices = int(sk.element_dofs[:nv].max()) + 1
    if compiled and nv == 4:
        return compiled_stiffness(sk.doflocs, sk.element_dofs[:nv], 1, lame, intorder=default_intorder(2),
                                  geometry=(sk.element_dofs, 2), n_dofs=n_vertices)
    geom = element_geometry(sk.doflocs, sk.element_dofs[:nv], 1, intorder=default_intorder(2),
                            geometry=(sk.element_dofs, 2), n_dofs=n_vertices)
    return stiffness(geom, lame, fmt="bsr")


def solve_static(md: MeshData, lame: Lame, *, fixed: Mapping[str, float | np.ndarray] | None = None,
                 fixed_dofs: np.ndarray | None = None, fixed_values: np.ndarray | float = 0.0,
                 tractions: Mapping[str, Traction] | None = None, point_loads: np.ndarray | None = None,
                 thickness_mm: float = 1.0, study: str = "fea", progress: Callable[[str], None] = lambda m: None,
                 method: str = "auto", thermal: ThermalStrain | None = None) -> StaticSolution:
    """Assemble and solve; ``fixed`` clamps named groups (all components, value 0 or a (dim,) vector).

    ``fixed_dofs``/``fixed_values`` add explicit Dirichlet dofs (interleaved numbering); ``point_loads``
    is added to the load vector as is; ``thermal`` adds the load of a thermal strain (``assembly.thermal_load``;
    recover its stress with the same ``thermal`` in ``fields.nodal_stress``)."""
    t = {}
    t0 = time.perf_counter()
    # systems that load numba for the fused solve anyway also assemble with its kernels (docs/decisions/004-assembly-kernels.md)
    compiled = md.order == 2 and md.dim == 3 and method != "direct" \
        and md.dim * md.nodes_mm.shape[0] >= fused_sweeps.MIN_DOFS
    try:
        sk, K, f, all_dofs, all_vals = _assemble(md, lame, fixed, fixed_dofs, fixed_values, tractions,
                                                 point_loads, thickness_mm, study, progress, compiled, thermal)
    except (ValueError, KeyError, IndexError) as exc:   # mesh/group mismatch: name the stage, no traceback
        raise StageError("assembly", study, f"{type(exc).__name__}: {exc}") from exc
    d = md.dim
    t["assembly"] = time.perf_counter() - t0
    progress(f"{study}: solving ({K.shape[0]} dofs)")
    u, info = solve_elasticity(K, f, fixed_dofs=all_dofs, fixed_values=all_vals, coords=sk.doflocs, dim=d,
                               study=study, method=method,
                               p2_element_dofs=sk.element_dofs if md.order == 2 else None,
                               p1_stiffness=(lambda: p1_stiffness(sk, lame, compiled=compiled))
                               if md.order == 2 and d == 3 else None, consume_K=compiled)
    t["solve"] = info.time_s
    progress(f"{study}: {info.method} {info.iterations} iterations, residual {info.residual:.1e}, {info.time_s:.1f} s")
    return StaticSolution(md, sk, u, lame, info, t)
