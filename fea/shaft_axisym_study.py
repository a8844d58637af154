"""shaft-torsion with a full circumferential crack: the crack's added flexibility on the (r, z) section.

The skeleton (``fea/skeleton.py``) runs this as the shaft study's second series beside the 3D uncracked
one (``shaft_torsion.ShaftTorsion``): each refinement meshes the section once with the crack line embedded
and solves it closed and opened (``shaft_axisym``), refining the global size and the tip size together so
the GCI sees the tip converge, at a small fraction of the 3D seam's cost (docs/decisions/010-shaft-axisymmetric-crack.md).
"""
from __future__ import annotations

import time
from pathlib import Path
from typing import Callable

from strainwave.fea.fields import field_info, write_vtu
from strainwave.fea.session import mesh_in_child
from strainwave.fea.shaft_axisym import Section, mesh_section, open_crack_line, section_fields, solve_section
from strainwave.fea.refinement import CRACK_FORMAL_ORDER, refinement_sizes
from strainwave.fea.result import Quantity
from strainwave.fea.skeleton import MeshSolve, Series

# Section wall/8, tip a/80 (quick wall/5, a/40): the tip error is first order (docs/decisions/010-shaft-axisymmetric-crack.md).
WALL_OVER_H = {False: 8.0, True: 5.0}
A_OVER_TIP = {False: 80.0, True: 40.0}


def section_fine_mm(params, quick: bool) -> float:
    """Finest global size of the section series."""
    return params.output_shaft.wall_mm / WALL_OVER_H[quick]


def solve_section_refinement(params, depth_mm: float, h_mm: float, h_fine_mm: float, *, quick: bool,
                             keep_fields: bool, progress: Callable[[str], None] = lambda m: None) -> MeshSolve:
    """One refinement of the section series: delta lambda (opened - closed on one mesh) at global size h and
    tip size (a / A_OVER_TIP) h / h_fine; the opened solution is kept for the fields when asked."""
    t0 = time.perf_counter()
    section = Section.of(params, depth_mm)
    G = params.material.implied_shear_modulus_MPa
    tip = depth_mm / A_OVER_TIP[quick] * h_mm / h_fine_mm
    md = mesh_in_child(lambda model: mesh_section(model, section, size_mm=h_mm, tip_size_mm=tip))
    closed = solve_section(md, section, G)
    opened = solve_section(open_crack_line(md, section), section, G)
    delta = opened.flexibility_rad_per_Nmm - closed.flexibility_rad_per_Nmm
    progress(f"shaft-torsion (axisymmetric): h = {h_mm:.3g} mm, tip {tip:.3g} mm, {md.nodes_mm.shape[0]} nodes, "
             f"delta lambda {delta:.4e}")
    return MeshSolve(h_mm, {"delta_flexibility_rad_per_Nmm": delta, "tip_size_mm": tip}, md.quality,
                     {"axisymmetric": time.perf_counter() - t0}, fields={"opened": opened} if keep_fields else {})


def section_delta(params, depth_mm: float, *, density: float,
                  progress: Callable[[str], None] = lambda m: None) -> Quantity:
    """delta lambda with its GCI on three sections ``density`` times finer than the full run's (global size and
    crack-tip size alike): for a curve whose GCI enters every depth read off it (crack sizing)."""
    h_full = section_fine_mm(params, quick=False)
    solves = tuple(solve_section_refinement(params, depth_mm, h, h_full, quick=False, keep_fields=False,
                                            progress=progress) for h in refinement_sizes(h_full / density))
    return Series("section", solves).converged("delta_flexibility_rad_per_Nmm", "rad/(N*mm)", order=CRACK_FORMAL_ORDER)


def write_section_fields(params, finest: MeshSolve, path: Path) -> Path:
    """The finest opened section's fields (torque T, rotation, tau) as VTU: x = r, y = z."""
    opened = finest.fields["opened"]
    T = params.gear.output_torque_Nmm
    return write_vtu(path, opened.md, section_fields(opened, params.material.implied_shear_modulus_MPa, T),
                     info=field_info("shaft-torsion", f"torque T = {T:g} N*mm, axisymmetric (r, z) section with "
                                     "the crack opened", params.material))
