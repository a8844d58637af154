"""The smooth cup's torsional flexibility on its (r, z) section: an exact 2D reduction of the 3D study.

The toothless cup, its clamp (the hub face z = 0) and its load (a uniform tangential shear on the band)
are all axisymmetric, so torsion keeps u_r = u_z = 0 and u_theta = r psi(r, z): the scalar problem of
``shaft_axisym.solve_torsion_section`` on the cup's half section is the 3D problem, not an approximation.
A 2D mesh resolves the hub's re-entrant corner and the band's edge at a cost of seconds, so the uncracked
lambda_f carries a GCI far below the 3D whole-cup mesh's (docs/decisions/031-cup-section-flexibility.md).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Callable

import numpy as np

from strainwave.fea.mesh_data import MeshData
from strainwave.fea.skeleton import MeshSolve

__all__ = ["SectionField", "section_fine_mm", "mesh_cup_section", "solve_cup_section", "section_flexibility",
           "section_displacement"]

# Section size wall/6 (quick wall/4); the hub's corner (r^2/3 field) refined to a tenth of it, the band's
# edge (a traction step, log field) to a quarter: finer cells at r = d1/2 defeat skfem's facet inversion
WALL_OVER_H = {False: 6.0, True: 4.0}
CORNER_OVER_H, EDGE_OVER_H = 10.0, 4.0
FLEX = "flexibility_rad_per_Nmm"


def section_fine_mm(params, quick: bool) -> float:
    """Finest global size of the cup's section series."""
    return params.flexspline_cup.wall_thickness_mm / WALL_OVER_H[quick]


def mesh_cup_section(model, section, *, size_mm: float, wall_mm: float, order: int = 2) -> MeshData:
    """P2 triangles of the half section (x = r, y = z): "fixed" on z = 0, "loaded" on the band's outer
    edge; refined at the re-entrant corners and at the band's start."""
    from strainwave.fea.meshing import Refine, import_shape, extract, generate

    import_shape(model, section.face)
    model.occ.rotate(model.occ.getEntities(), 0, 0, 0, 1, 0, 0, -math.pi / 2)   # (x, 0, z) -> (x, z, 0)
    model.occ.synchronize()
    tol = 1e-6 * section.length_mm
    picks = {"fixed": lambda lo, hi: abs(lo[1]) < tol and abs(hi[1]) < tol,
             "loaded": lambda lo, hi: abs(lo[0] - section.outer_radius_mm) < tol
             and abs(hi[0] - section.outer_radius_mm) < tol and lo[1] > section.band_z_mm - tol}
    groups = {}
    for name, pick in picks.items():
        tags = [t for _, t in model.getEntities(1) if pick(model.getBoundingBox(1, t)[:3], model.getBoundingBox(1, t)[3:])]
        if not tags:
            raise ValueError(f"cup section: no edge found for group {name!r}")
        model.addPhysicalGroup(1, tags, name=name)
        groups[name] = (1, tags)
    model.addPhysicalGroup(2, [t for _, t in model.getEntities(2)], name="section")
    corners = tuple((r, z, 0.0) for r, z in section.corners_mm)
    edge = ((section.outer_radius_mm, section.band_z_mm, 0.0),)
    refine = [Refine(size_mm / over, 0.5 * wall_mm, 2.0 * wall_mm, points_mm=pts, along_curves=False)
              for over, pts in ((CORNER_OVER_H, corners), (EDGE_OVER_H, edge)) if pts]
    generate(model, 2, order, size_mm=size_mm, refine=refine)
    return extract(model, 2, order, groups, size_mm)


def solve_cup_section(params, h_mm: float, *, keep_fields: bool = False,
                      progress: Callable[[str], None] = lambda m: None, cache_dir: Path | None = None) -> MeshSolve:
    """lambda_f of the smooth cup on its section meshed at global size ``h_mm``; with ``keep_fields`` its
    ``SectionField`` too. ``cache_dir``: the solution is kept there and read back by every later call with the
    same parameters but the crack's depth (the smooth section carries no crack) and size."""
    from strainwave.cache import shared_entry
    solved = shared_entry(None if cache_dir is None else _cache_file(params, h_mm, cache_dir),
                          lambda path: _read_section(path, h_mm, True), lambda: _solve_section(params, h_mm, progress),
                          _write_section)
    return solved if keep_fields else replace(solved, fields={})


def _solve_section(params, h_mm: float, progress: Callable[[str], None]) -> MeshSolve:
    """The section meshed and solved: values, mesh, timings and its ``SectionField``."""
    from strainwave.fea.session import mesh_in_child
    from strainwave.fea.shaft_axisym import solve_torsion_section
    from strainwave.geometry.flexspline_cup import smooth_section

    t0 = time.perf_counter()
    section = smooth_section(params)
    wall = params.flexspline_cup.wall_thickness_mm
    md = mesh_in_child(lambda model: mesh_cup_section(model, section, size_mm=h_mm, wall_mm=wall),
                       what="cup-torsion section")
    t_mesh = time.perf_counter() - t0
    arm = 2.0 * math.pi * section.outer_radius_mm ** 2 * (section.length_mm - section.band_z_mm)
    sol = solve_torsion_section(md, params.material.implied_shear_modulus_MPa, lambda r: 1.0 / arm + 0.0 * r)
    progress(f"cup-torsion (axisymmetric): h = {h_mm:.3g} mm, {md.nodes_mm.shape[0]} nodes, "
             f"lambda_f {sol.flexibility_rad_per_Nmm:.6e}")
    scalar = replace(md.quality, dofs=md.nodes_mm.shape[0])      # psi: one unknown per node
    field = SectionField(sol.basis.doflocs, sol.basis.element_dofs, sol.psi)
    return MeshSolve(h_mm, {FLEX: sol.flexibility_rad_per_Nmm, "nodes": float(md.nodes_mm.shape[0])}, scalar,
                     {"mesh": t_mesh, "axisymmetric": time.perf_counter() - t0 - t_mesh}, fields={"section": field})


@dataclass(frozen=True)
class SectionField:
    """The section's solution as ``section_displacement`` reads it: psi at the P2 dofs (r, z) of its mesh."""

    doflocs: np.ndarray         # (2, N) r, z mm
    element_dofs: np.ndarray    # (6, elements)
    psi: np.ndarray             # (N,) rad per unit torque


def _cache_file(params, h_mm: float, cache_dir: Path) -> Path:
    from strainwave.cache import case_key
    data = params.to_dict()
    data["flexspline_cup"].pop("root_crack_depth_mm", None)     # the smooth section carries no crack
    return Path(cache_dir) / f"cup-section-{case_key('cup-section', {'params': data, 'h_mm': h_mm})}.npz"


def _write_section(path: Path, solved: MeshSolve) -> None:
    import io
    import json

    from strainwave.io_atomic import atomic_write_bytes
    f, buffer = solved.fields["section"], io.BytesIO()
    meta = {"values": dict(solved.values), "mesh": solved.mesh.to_dict()}
    np.savez(buffer, doflocs=f.doflocs, element_dofs=f.element_dofs, psi=f.psi, meta=np.array(json.dumps(meta)))
    atomic_write_bytes(Path(path), buffer.getvalue())


def _read_section(path: Path, h_mm: float, keep_fields: bool) -> MeshSolve:
    import json

    from strainwave.fea.result import MeshQuality
    t0 = time.perf_counter()
    with np.load(path) as data:
        meta = json.loads(str(data["meta"]))
        field = SectionField(data["doflocs"], data["element_dofs"], data["psi"])
    return MeshSolve(h_mm, meta["values"], MeshQuality(**meta["mesh"]), {"axisymmetric": time.perf_counter() - t0},
                     fields={"section": field} if keep_fields else {})


def section_flexibility(params, *, quick: bool = False, unit: str = "rad/(N*mm)"):
    """lambda_f of the smooth cup on three section meshes, with its GCI (``Quantity``): the junction
    calibration's FEA value (compare/validate/torsion_checks.py)."""
    from strainwave.fea.refinement import DEFAULT_RATIO, converged_quantity, on_three_meshes, refinement_sizes
    sizes = refinement_sizes(section_fine_mm(params, quick), DEFAULT_RATIO)
    solves = on_three_meshes(lambda h, k: solve_cup_section(params, h), sizes)
    return converged_quantity(FLEX, unit, [s.h_mm for s in solves], [s.values[FLEX] for s in solves])


def section_displacement(sol: SectionField) -> Callable:
    """The 3D displacement of the smooth cup from its section solution (``SectionField`` at unit torque):
    points (n, 3) mm -> u = psi(r, z) (-y, x, 0), i.e. u_theta = r psi: exact, not an approximation."""
    from strainwave.fea.crack_local import interpolate_p2

    def displacement(points_mm):
        x = np.asarray(points_mm, float)
        rz = np.stack([np.hypot(x[:, 0], x[:, 1]), x[:, 2]], axis=1)
        psi = interpolate_p2(sol.doflocs, sol.element_dofs, sol.psi, rz, components=1)[:, 0]
        return np.stack([-psi * x[:, 1], psi * x[:, 0], np.zeros_like(psi)], axis=1)
    return displacement
