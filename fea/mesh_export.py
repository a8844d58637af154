"""A study's finest mesh for other solvers: gmsh ``.msh`` and CalculiX/Abaqus ``.inp`` with named sets, through meshio.

The mesh is read back from the VTU pair the study wrote (``NAME.vtu`` cells and ``NAME.boundary.vtu`` named
facets), so every study exports the mesh it solved without a hook of its own. Each named face becomes a gmsh
physical group (its facets, triangle6 or triangle) and, in the ``.inp``, a node set ``N<NAME>``; the cells are
``EALL``. The ``.inp`` is a complete CalculiX deck (material, clamp, consistent nodal forces, a static step
that prints the loaded face's displacements) where the study's load is a surface traction on ``loaded`` with
``fixed`` clamped (the torsion studies, ``TRACTION_DECKS``); for the others it carries the mesh, the sets and
the material, and says in a comment why the load is left to the user (a contact, a prescribed shape).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from strainwave.fea.fields import VOLUME_GROUP, VOLUME_POINT_ID, boundary_path, field_text
from strainwave.fea.mesh_data import MeshData
from strainwave.io_atomic import atomic_path

__all__ = ["mesh_of_vtu", "write_msh", "write_inp", "TRACTION_DECKS"]

# VTK order -> gmsh order of the cells (VTK tet10 = Abaqus C3D10: edges 01 12 20 03 13 23; gmsh's last two swap)
_VTK_TO_GMSH = {10: np.array([0, 1, 2, 3, 4, 5, 6, 7, 9, 8])}
_VOLUME_TYPES = {24: 10, 10: 4, 22: 6, 5: 3}         # VTK cell type -> nodes per cell (3D tets, 2D triangles)
_MESHIO_CELL = {(3, 10): "tetra10", (3, 4): "tetra", (2, 6): "triangle6", (2, 3): "triangle"}
_MESHIO_FACET = {(3, 6): "triangle6", (3, 3): "triangle", (2, 3): "line3", (2, 2): "line", (3, 1): "vertex",
                 (2, 1): "vertex"}
# CalculiX reads at most 20 characters a number: 14 significant digits (benchmarks/calculix_job.py)
REAL = "%.13e"


def _read_grid(path: Path):
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
    import pyvista as pv
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    return pv.wrap(reader.GetOutput())


def mesh_of_vtu(vtu: Path) -> MeshData:
    """The MeshData a study's VTU pair holds: cells in gmsh order, every named boundary group's facets."""
    volume, boundary = _read_grid(Path(vtu)), _read_grid(boundary_path(vtu))
    dim = 2 if np.ptp(np.asarray(volume.points)[:, 2]) == 0.0 else 3
    (cells,) = (c for t, c in volume.cells_dict.items() if t in _VOLUME_TYPES)
    perm = _VTK_TO_GMSH.get(cells.shape[1]) if dim == 3 else None
    cells = cells if perm is None else cells[:, perm]
    names = field_text(boundary, "physical_group_names")
    ids = np.asarray(boundary.point_data[VOLUME_POINT_ID], np.int64)
    group_of = np.asarray(boundary.cell_data["physical_group"], np.int64)
    connectivity, offsets = np.asarray(boundary.cell_connectivity), np.asarray(boundary.offset)
    sizes = np.diff(offsets)
    groups = {}
    for tag in np.unique(group_of):
        rows = np.flatnonzero(group_of == tag)
        k = int(sizes[rows[0]])   # one facet kind per group (triangle6 faces, or points)
        local = connectivity[offsets[rows][:, None] + np.arange(k)]
        groups[names[tag - 1]] = ids[local]
    order = 2 if cells.shape[1] in (10, 6) else 1
    return MeshData(np.asarray(volume.points, float), np.asarray(cells, np.int64), dim, order, groups)


def _meshio(md: MeshData, *, facets: bool):
    import meshio
    vtk_cells = md.cells if md.dim == 2 or md.order == 1 else md.cells[:, _VTK_TO_GMSH[10]]   # meshio: VTK order
    blocks = [(_MESHIO_CELL[(md.dim, md.cells.shape[1])], vtk_cells)]
    physical = [np.ones(md.cells.shape[0], np.int64)]
    field_data = {VOLUME_GROUP[md.dim]: np.array([1, md.dim])}
    for tag, name in enumerate(sorted(md.groups), start=2):
        rows = md.groups[name]
        field_data[name] = np.array([tag, md.dim - 1 if rows.shape[1] > 1 else 0])
        if facets:
            blocks.append((_MESHIO_FACET[(md.dim, rows.shape[1])], rows))
            physical.append(np.full(rows.shape[0], tag, np.int64))
    point_sets = {f"N{name.upper()}": md.group_nodes(name) for name in sorted(md.groups)}
    cell_data = {"gmsh:physical": physical, "gmsh:geometrical": physical} if facets else {}
    return meshio.Mesh(md.nodes_mm, blocks, cell_data=cell_data, field_data=field_data if facets else None,
                       point_sets=point_sets, cell_sets=None if facets else {"EALL": [np.arange(md.cells.shape[0])]})


def write_msh(md: MeshData, path: Path) -> Path:
    """gmsh 2.2 ASCII (which meshio, gmsh and most solvers' importers read): cells and named facet groups as
    physical groups with their names. Written atomically."""
    import meshio
    with atomic_path(Path(path)) as tmp:
        meshio.write(tmp, _meshio(md, facets=True), file_format="gmsh22", binary=False)
    return Path(path)


def torsion_forces(md: MeshData, study: str, params) -> np.ndarray:
    """(N, 3) consistent nodal forces of the torsion study's traction on ``loaded`` at its torque T: the shaft's
    Saint-Venant shear T r / J, the cup's uniform tangential shear of moment T (as the studies load them)."""
    from strainwave.fea.surface import SurfaceQuadrature
    from strainwave.fea.torsion_load import saint_venant_traction, uniform_tangential_traction
    T = params.gear.output_torque_Nmm
    q = SurfaceQuadrature.of(md, "loaded")
    if study == "shaft-torsion":
        sh = params.output_shaft
        traction = saint_venant_traction(T, math.pi / 32.0 * (sh.outer_diameter_mm ** 4 - sh.inner_diameter_mm ** 4))
    else:
        arm = q.integrate(np.hypot(q.x[..., 0], q.x[..., 1]))   # int r dA on the curved facets
        traction = uniform_tangential_traction(T, arm)
    n = md.nodes_mm.shape[0]
    return q.load_vector(traction, np.arange(n), 3, 3 * n).reshape(n, 3)


TRACTION_DECKS = {"shaft-torsion": torsion_forces, "cup-torsion": torsion_forces}


def _model_lines(md: MeshData, study: str, params, load_text: str) -> list[str]:
    mat = params.material
    lines = ["*MATERIAL, NAME=STEEL", "*ELASTIC", f"{mat.youngs_modulus_MPa:.13e},{mat.poisson_ratio:.13e}",
             "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL"]
    forces = TRACTION_DECKS.get(study)
    if forces is None:
        return lines + [f"** load of {study}: {load_text}", "** not written: not a nodal load on a named face "
                        "(contact or a prescribed shape); apply it to the node sets above"]
    f = forces(md, study, params)
    lines += ["*BOUNDARY", "NFIXED,1,3,0.", "*STEP", "*STATIC", "*CLOAD",
              f"** {load_text}: consistent nodal forces of the study's traction on 'loaded' (N)"]
    node, comp = np.nonzero(f)
    lines += [f"{n + 1},{c + 1},{f[n, c]:.13e}" for n, c in zip(node.tolist(), comp.tolist())]
    return lines + ["*NODE PRINT, NSET=NLOADED", "U", "*NODE FILE", "U", "*END STEP"]


# meshio names tetra10 C3D10MH (hybrid, modified), which CalculiX does not know: the plain elements the study used
_ELEMENT = {10: "C3D10", 4: "C3D4"}


def _calculix_elements(text: str, md: MeshData) -> str:
    """meshio's deck with strainwave's heading and the element type CalculiX reads (C3D10 / C3D4)."""
    import re
    head, sep, rest = text.partition("*NODE")
    text = f"*HEADING\nstrainwave: the finest mesh the study solved, a node set per named face\n{sep}{rest}"
    return re.sub(r"^\*ELEMENT, TYPE=\w+", f"*ELEMENT, TYPE={_ELEMENT[md.cells.shape[1]]}", text, flags=re.M)


def write_inp(md: MeshData, path: Path, *, study: str, params, load_text: str) -> Path:
    """CalculiX/Abaqus deck: nodes (id = index + 1), C3D10/C3D4 cells (set EALL), a node set per named face,
    then the material and, for a traction study, the clamp, the loads and a static step. Written atomically."""
    import meshio
    if md.dim != 3:
        raise ValueError(f"{study}: a CalculiX deck needs a 3D mesh; this study's mesh is plane (use --msh)")
    with atomic_path(Path(path)) as tmp:
        meshio.write(tmp, _meshio(md, facets=False), file_format="abaqus", float_fmt=REAL.lstrip("%"))
        text = _calculix_elements(Path(tmp).read_text(encoding="utf-8"), md)
        deck = "\n".join(_model_lines(md, study, params, load_text))
        Path(tmp).write_text(f"{text}{deck}\n", encoding="utf-8")
    return Path(path)
