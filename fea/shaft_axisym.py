"""Axisymmetric torsion of the hollow shaft with a full circumferential crack: an exact 2D reduction.

With u_r = u_z = 0 and u_theta = r psi(r, z) (psi = rotation), the only strains are gamma_rtheta =
r d(psi)/dr and gamma_ztheta = r d(psi)/dz, and the strain energy is 1/2 int 2 pi mu r^3 |grad psi|^2
dr dz. A full circumferential crack keeps the problem axisymmetric, so the scalar problem on the
(r, z) section is the 3D problem, not an approximation of it. The section is meshed with the crack
line embedded, solved closed and then opened (nodes on the crack line, except the tip, duplicated for
the elements above it) on the same mesh - the 2D counterpart of ``crack_seam``. Loads and the twist
measure are those of ``shaft_torsion``: the Saint-Venant end shear tau = T r / J on z = L, z = 0
fixed, twist = area-weighted mean rotation of the loaded end. Uncracked, psi = T z / (G J) is in the
P2 space, so the flexibility is exact to round-off.

The point: a 3D seam mesh must resolve the tip along the whole front; here the tip is a point, and a/20
costs a few thousand dofs (docs/decisions/010-shaft-axisymmetric-crack.md).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from strainwave.fea.mesh_data import MeshData


@dataclass(frozen=True)
class Section:
    """The shaft's (r, z) half-section and its crack (depth 0 = uncracked)."""

    r_inner_mm: float
    r_outer_mm: float
    length_mm: float
    crack_z_mm: float
    crack_depth_mm: float

    @classmethod
    def of(cls, params, crack_depth_mm: float | None) -> "Section":
        sh, cg = params.output_shaft, params.crack_geometry
        return cls(sh.inner_diameter_mm / 2, sh.outer_diameter_mm / 2, sh.length_mm,
                   cg.shaft_axial_position_ratio * sh.length_mm, crack_depth_mm or 0.0)

    @property
    def polar_moment_mm4(self) -> float:
        return math.pi / 2 * (self.r_outer_mm ** 4 - self.r_inner_mm ** 4)

    @property
    def tip_mm(self) -> tuple[float, float]:
        return (self.r_outer_mm - self.crack_depth_mm, self.crack_z_mm)


def mesh_section(model, section: Section, *, size_mm: float, tip_size_mm: float, order: int = 2) -> MeshData:
    """Triangles of the (r, z) rectangle (x = r, y = z) with the crack line embedded (group "crack"),
    ends "fixed" (z = 0) and "loaded" (z = L); refined to ``tip_size_mm`` around the crack tip."""
    from strainwave.fea.meshing import Refine, extract, generate

    s = section
    rect = model.occ.addRectangle(s.r_inner_mm, 0.0, 0.0, s.r_outer_mm - s.r_inner_mm, s.length_mm)
    tools = []
    if s.crack_depth_mm > 0:
        tip = model.occ.addPoint(*s.tip_mm, 0.0)
        mouth = model.occ.addPoint(s.r_outer_mm, s.crack_z_mm, 0.0)
        tools = [(1, model.occ.addLine(tip, mouth))]
    model.occ.fragment([(2, rect)], tools)
    model.occ.synchronize()
    groups = {}
    for name, pick in (("fixed", lambda c: abs(c[1]) < 1e-9 and abs(c[0] - 0.5 * (s.r_inner_mm + s.r_outer_mm)) < 1e-6),
                       ("loaded", lambda c: abs(c[1] - s.length_mm) < 1e-9),
                       ("crack", lambda c: abs(c[1] - s.crack_z_mm) < 1e-9 and c[0] > s.tip_mm[0] - 1e-9
                        and s.crack_depth_mm > 0)):
        tags = [t for _, t in model.getEntities(1) if pick(model.occ.getCenterOfMass(1, t))]
        if tags:
            model.addPhysicalGroup(1, tags, name=name)
            groups[name] = (1, tags)
    model.addPhysicalGroup(2, [t for _, t in model.getEntities(2)], name="section")
    refine = [Refine(tip_size_mm, 2 * tip_size_mm, s.crack_depth_mm + 4 * size_mm, points_mm=(s.tip_mm + (0.0,),))
              ] if s.crack_depth_mm > 0 else []
    generate(model, 2, order, size_mm=size_mm, refine=refine)
    return extract(model, 2, order, groups, size_mm)


def open_crack_line(md: MeshData, section: Section) -> MeshData:
    """Duplicate the crack line's nodes (all but the tip) for the elements above z = z_c."""
    import dataclasses
    line = md.groups["crack"]
    nodes = np.unique(line)
    tip = np.linalg.norm(md.nodes_mm[nodes, :2] - np.array(section.tip_mm), axis=1) < 1e-9
    opened = nodes[~tip]
    if opened.size == 0:
        raise ValueError("open_crack_line: the crack line has no node besides its tip")
    new_index = np.full(md.nodes_mm.shape[0], -1, dtype=np.int64)
    new_index[opened] = md.nodes_mm.shape[0] + np.arange(opened.size)
    above = md.nodes_mm[md.cells[:, :3], 1].mean(axis=1) > section.crack_z_mm
    cells = md.cells.copy()
    block = cells[above]
    hit = new_index[block] >= 0
    block[hit] = new_index[block[hit]]
    cells[above] = block
    groups = dict(md.groups)
    groups["crack_plus"] = np.where(new_index[line] >= 0, new_index[line], line)
    groups["crack_minus"] = line
    return dataclasses.replace(md, nodes_mm=np.vstack([md.nodes_mm, md.nodes_mm[opened]]), cells=cells,
                               groups=groups)


@dataclass(frozen=True)
class SectionSolution:
    md: MeshData
    psi: np.ndarray                 # rotation at the scikit-fem dofs, rad
    sk: object                      # SkfemMesh
    basis: object                   # scalar CellBasis
    flexibility_rad_per_Nmm: float  # mean end rotation / T


def solve_torsion_section(md: MeshData, shear_modulus_MPa: float, shear_per_torque, torque_Nmm: float = 1.0,
                          *, loaded: str = "loaded", fixed: str = "fixed") -> SectionSolution:
    """The scalar axisymmetric torsion problem on ``md`` (x = r, y = z): psi = 0 on ``fixed``, a tangential
    shear tau = T ``shear_per_torque(r)`` on ``loaded``; flexibility = the area-weighted mean rotation of
    ``loaded`` / T. Shared by every axisymmetric part (shaft, smooth cup)."""
    from skfem import BilinearForm, FacetBasis, Functional, LinearForm, MeshTri, solve, condense
    from skfem.mapping import MappingAffine
    from skfem.helpers import dot, grad

    from strainwave.fea.assembly import scalar_basis
    from strainwave.fea.mesh_data import facet_indices, group_dofs, to_skfem

    sk = to_skfem(md)
    basis = scalar_basis(sk.mesh, sk.element, intorder=6)    # r^3 weight: quadrature exact for P2 on lines

    @BilinearForm
    def stiffness(u, v, w):
        return 2 * np.pi * shear_modulus_MPa * w.x[0] ** 3 * dot(grad(u), grad(v))

    K = stiffness.assemble(basis)
    # the loaded edge is straight: the vertices' affine map is exact there, and skfem's isoparametric facet
    # inversion (Newton to 1e-12) stalls on small cells far from the origin
    affine = MappingAffine(MeshTri(sk.mesh.p, sk.mesh.t, sort_t=False))   # same local vertex order as sk
    end = FacetBasis(sk.mesh, sk.element, mapping=affine, facets=facet_indices(sk, md, loaded), intorder=6)

    @LinearForm
    def shear(v, w):                # int tau u_theta dA, u_theta = r psi, dA = 2 pi r ds
        return 2 * np.pi * torque_Nmm * shear_per_torque(w.x[0]) * w.x[0] ** 2 * v

    f = shear.assemble(end)
    psi = solve(*condense(K, f, D=group_dofs(sk, md, fixed)))

    @Functional
    def rotation_area(w):
        return 2 * np.pi * w.x[0] * w["psi"]

    @Functional
    def area(w):
        return 2 * np.pi * w.x[0]

    twist = rotation_area.assemble(end, psi=end.interpolate(psi)) / area.assemble(end)
    return SectionSolution(md, psi, sk, basis, float(twist / torque_Nmm))


def solve_section(md: MeshData, section: Section, shear_modulus_MPa: float,
                  torque_Nmm: float = 1.0) -> SectionSolution:
    """The shaft's section: Saint-Venant end shear tau = T r / J on z = L."""
    J = section.polar_moment_mm4
    return solve_torsion_section(md, shear_modulus_MPa, lambda r: r / J, torque_Nmm)


def flexibility_rad_per_Nmm(md: MeshData, section: Section, shear_modulus_MPa: float,
                            torque_Nmm: float = 1.0) -> float:
    """Mean end rotation / T of the scalar axisymmetric torsion problem on ``md``."""
    return solve_section(md, section, shear_modulus_MPa, torque_Nmm).flexibility_rad_per_Nmm


def section_fields(sol: SectionSolution, shear_modulus_MPa: float, torque_Nmm: float) -> dict[str, np.ndarray]:
    """Nodal fields for VTU: rotation, u_theta (as the out-of-plane component) and the shear stress
    tau = mu r |grad psi| with its von Mises equivalent sqrt(3) tau (L2-projected gradients)."""
    g = sol.basis.project(sol.basis.interpolate(sol.psi).grad[0]), sol.basis.project(
        sol.basis.interpolate(sol.psi).grad[1])
    n2d = sol.sk.node_to_dof
    r = sol.md.nodes_mm[:, 0]
    psi = torque_Nmm * sol.psi[n2d]
    tau = shear_modulus_MPa * r * torque_Nmm * np.hypot(g[0][n2d], g[1][n2d])
    disp = np.zeros((r.size, 3))
    disp[:, 2] = r * psi
    return {"rotation_rad": psi, "displacement_mm": disp, "shear_stress_MPa": tau, "von_mises_MPa": np.sqrt(3) * tau}
