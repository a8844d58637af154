"""FEA core: meshing to plain data, node ordering, vectorised assembly, patch tests, solver, VTU."""
from __future__ import annotations

import numpy as np
import pytest

from strainwave.errors import StageError
from strainwave.fea.assembly import Lame, elasticity_stiffness, scalar_basis
from strainwave.fea.fields import nodal_displacement, nodal_stress, von_mises, write_vtu
from strainwave.fea.mesh_data import GMSH_EDGES, facet_indices, to_skfem
from strainwave.fea.meshing import mesh_part, mesh_section
from strainwave.fea.session import gmsh_session
from strainwave.fea.solver import solve_elasticity
from strainwave.fea.static import solve_static
from strainwave.geometry.part import FaceRef, Part, PartName

E, NU = 2.1e5, 0.3


def _box_part(lx=2.0, ly=1.0, lz=1.5) -> Part:
    import build123d as bd
    box = bd.Box(lx, ly, lz, align=(bd.Align.MIN, bd.Align.MIN, bd.Align.MIN))
    faces = {}
    for f in box.faces():
        c = f.center()
        if abs(c.X) < 1e-9:
            faces["xmin"] = (FaceRef((c.X, c.Y, c.Z), f.area),)
        if abs(c.X - lx) < 1e-9:
            faces["xmax"] = (FaceRef((c.X, c.Y, c.Z), f.area),)
    return Part(PartName.OUTPUT_SHAFT, box, faces)


@pytest.fixture(scope="module")
def box_meshes():
    out = {}
    for order in (1, 2):
        with gmsh_session() as model:
            out[order] = mesh_part(model, _box_part(), size_mm=0.5, order=order)
    return out


def test_mesh_data_is_plain_and_groups_are_found(box_meshes):
    md = box_meshes[2]
    assert md.cells.shape[1] == 10 and md.dim == 3 and md.order == 2
    assert set(md.groups) == {"xmin", "xmax"}
    # every xmin facet node lies on x = 0 (to round-off of the BREP coordinates)
    assert np.abs(md.nodes_mm[md.group_nodes("xmin"), 0]).max() < 1e-12
    # the group covers the 1 x 1.5 face: sum of facet areas (vertex triangles, planar face)
    tri = md.nodes_mm[md.groups["xmin"][:, :3]]
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1).sum()
    assert area == pytest.approx(1.5, rel=1e-12)   # exact: planar face, round-off only
    assert md.quality.elements == md.cells.shape[0] and 0 < md.quality.min_quality <= md.quality.mean_quality <= 1


def test_gmsh_mid_node_order_matches_table(box_meshes):
    md = box_meshes[2]
    # a box has no curved faces: every mid node is the midpoint of its edge, so the table must match exactly
    for j, (a, b) in enumerate(GMSH_EDGES[3]):
        mid = 0.5 * (md.nodes_mm[md.cells[:, a]] + md.nodes_mm[md.cells[:, b]])
        assert np.abs(md.nodes_mm[md.cells[:, 4 + j]] - mid).max() < 1e-12


def test_skfem_conversion_and_facets(box_meshes):
    md = box_meshes[2]
    sk = to_skfem(md)
    # skfem P2 doflocs are exactly the MeshData nodes, in the node_to_dof order
    assert np.abs(sk.mesh.doflocs.T[sk.node_to_dof] - md.nodes_mm).max() < 1e-14   # round-off only
    assert facet_indices(sk, md, "xmax").size == md.groups["xmax"].shape[0]


@pytest.mark.parametrize("dim,order", [(3, 1), (3, 2), (2, 1), (2, 2)])
def test_vectorised_assembly_equals_stock_skfem(dim, order):
    import skfem
    from skfem.models.elasticity import linear_elasticity
    if dim == 3:
        m1 = skfem.MeshTet1.init_tensor(*(np.linspace(0, 1, 3),) * 3)
        mesh, elem = (m1, skfem.ElementTetP1()) if order == 1 else (skfem.MeshTet2.init_ball(1), skfem.ElementTetP2())
        lame = Lame.from_young(E, NU)
    else:
        mesh, elem = (skfem.MeshTri1.init_circle(2), skfem.ElementTriP1()) if order == 1 else \
            (skfem.MeshTri2.init_circle(2), skfem.ElementTriP2())
        lame = Lame.from_young(E, NU, plane_stress=True)
    intorder = 2 * order
    K = elasticity_stiffness(scalar_basis(mesh, elem, intorder=intorder), lame, chunk=7)   # odd chunk: exercise the loop
    vb = skfem.Basis(mesh, skfem.ElementVector(elem), intorder=intorder)
    K0 = skfem.asm(linear_elasticity(lame.lam_MPa, lame.mu_MPa), vb)
    # same quadrature, same formula: only round-off of summation order may differ
    assert abs(K - K0).max() <= 1e-10 * abs(K0).max()


def _patch_solution(md, lame, thickness=1.0):
    """Impose u = A x + c on every boundary dof; the FE solution must be that field everywhere."""
    sk = to_skfem(md)
    basis = scalar_basis(sk.mesh, sk.element)
    d = md.dim
    rng = np.random.default_rng(7)
    A, c = rng.normal(size=(d, d)) * 1e-3, rng.normal(size=d) * 1e-3
    exact = (A @ basis.doflocs + c[:, None]).T.ravel()          # interleaved
    bnd = basis.get_dofs().flatten()
    fixed = (d * bnd[:, None] + np.arange(d)).ravel()
    K = elasticity_stiffness(basis, lame, thickness_mm=thickness)
    u, info = solve_elasticity(K, np.zeros(K.shape[0]), fixed_dofs=fixed, fixed_values=exact[fixed],
                               coords=basis.doflocs, dim=d, method="direct")
    return u, exact


@pytest.mark.parametrize("order", [1, 2])
def test_patch_test_3d(box_meshes, order):
    u, exact = _patch_solution(box_meshes[order], Lame.from_young(E, NU))
    # a linear field is in the P1 and P2 spaces: reproduced to round-off of the direct solve
    assert np.abs(u - exact).max() < 1e-12 * np.abs(exact).max() * 1e3


@pytest.mark.parametrize("order", [1, 2])
def test_patch_test_plane_stress(order):
    square = [np.array([[0, 0], [2, 0], [2, 1], [0.7, 1.3], [0, 1]], float)]
    with gmsh_session() as model:
        md = mesh_section(model, loops=square, size_mm=0.3, order=order)
    u, exact = _patch_solution(md, Lame.from_young(E, NU, plane_stress=True), thickness=3.0)
    assert np.abs(u - exact).max() < 1e-9 * np.abs(exact).max()   # round-off of the direct solve


def test_amg_matches_direct_and_reports_non_convergence(box_meshes):
    md = box_meshes[2]
    sk = to_skfem(md)
    lame = Lame.from_young(E, NU)
    sol_d = solve_static(md, lame, fixed={"xmin": 0.0}, tractions={"xmax": lambda x: np.stack(
        [np.full_like(x[0], 10.0), 0 * x[0], 0 * x[0]])}, method="direct")
    sol_a = solve_static(md, lame, fixed={"xmin": 0.0}, tractions={"xmax": lambda x: np.stack(
        [np.full_like(x[0], 10.0), 0 * x[0], 0 * x[0]])}, method="amg")
    assert sol_a.solver.method == "amg-cg" and sol_d.solver.method in ("pardiso", "splu")
    # CG stops at relative residual 1e-10; the displacement then agrees to ~cond * 1e-10 << 1e-6
    assert np.abs(sol_a.u - sol_d.u).max() < 1e-6 * np.abs(sol_d.u).max()
    K = elasticity_stiffness(scalar_basis(sk.mesh, sk.element), lame)
    f = np.random.default_rng(1).normal(size=K.shape[0])
    fixed = (3 * np.unique(sk.node_to_dof[md.group_nodes("xmin")])[:, None] + np.arange(3)).ravel()
    with pytest.raises(StageError) as err:
        solve_elasticity(K, f, fixed_dofs=fixed, coords=sol_a.basis.doflocs, dim=3, method="amg", maxiter=2,
                         study="unit")
    assert err.value.stage == "solve" and "did not converge" in str(err.value)


def test_vtu_opens_in_pyvista(box_meshes, tmp_path):
    import pyvista as pv
    md = box_meshes[2]
    lame = Lame.from_young(E, NU)
    sol = solve_static(md, lame, fixed={"xmin": 0.0}, tractions={"xmax": lambda x: np.stack(
        [np.full_like(x[0], 10.0), 0 * x[0], 0 * x[0]])})
    s = nodal_stress(md, sol.sk, sol.u, lame)
    vm = von_mises(s)
    path = write_vtu(tmp_path / "box.vtu", md, {"displacement_mm": nodal_displacement(md, sol.sk, sol.u),
                                                 "von_mises_MPa": vm})
    grid = pv.read(path)
    assert grid.n_points == md.nodes_mm.shape[0] and grid.n_cells == md.cells.shape[0]
    assert set(grid.celltypes) == {24}                          # VTK_QUADRATIC_TETRA
    assert np.allclose(grid.point_data["von_mises_MPa"], vm)
    # uniaxial 10 MPa bar: far from the clamp the von Mises stress is the applied 10 MPa
    far = md.nodes_mm[:, 0] > 1.5
    assert np.median(vm[far]) == pytest.approx(10.0, rel=0.05)   # the clamp's Poisson constraint decays over ~1 width
    assert grid.point_data["displacement_mm"][:, 0].max() > 0
    assert not list(tmp_path.glob(".*tmp"))                      # atomic write left no temporary file


def test_facet_quadrature_load_equals_skfem_facet_basis(box_meshes):
    from strainwave.fea.assembly import facet_vector_basis, traction_load
    from strainwave.fea.surface import SurfaceQuadrature
    md = box_meshes[2]
    sk = to_skfem(md)
    n = 3 * sk.mesh.doflocs.shape[1]

    def trac(x):
        return np.stack([x[1] ** 2, x[0] * x[2], 1.0 + 0 * x[0]])   # quadratic: both rules are exact on P2 x P2

    f_own = SurfaceQuadrature.of(md, "xmax").load_vector(trac, sk.node_to_dof, 3, n)
    f_sk = traction_load(facet_vector_basis(sk.mesh, sk.element, facet_indices(sk, md, "xmax")), trac)
    assert np.abs(f_own - f_sk).max() < 1e-12 * np.abs(f_sk).max()   # same integral, round-off only
    assert SurfaceQuadrature.of(md, "xmax").area == pytest.approx(1.5, rel=1e-12)


def test_cell_and_nodal_stress_of_uniform_field(box_meshes):
    from strainwave.fea.fields import cell_stress
    md = box_meshes[2]
    sk = to_skfem(md)
    lame = Lame.from_young(E, NU)
    eps_xx = 1e-4                      # u = (eps x, 0, 0): sigma_xx = (lam + 2 mu) eps, yy = zz = lam eps
    u = np.zeros(3 * sk.mesh.doflocs.shape[1])
    u[0::3] = eps_xx * sk.mesh.doflocs[0]
    expected = np.array([lame.lam_MPa + 2 * lame.mu_MPa, lame.lam_MPa, lame.lam_MPa, 0, 0, 0]) * eps_xx
    # a linear field has constant stress: every cell and node reproduces it to round-off
    assert np.abs(cell_stress(md, sk, u, lame) - expected).max() < 1e-9 * expected[0]
    assert np.abs(nodal_stress(md, sk, u, lame) - expected).max() < 1e-9 * expected[0]
