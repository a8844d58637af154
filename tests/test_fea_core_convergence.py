"""Plane sections through mesh_section and the convergence rate of an exact elasticity solution."""
from __future__ import annotations

import numpy as np
import pytest

from strainwave.fea.assembly import Lame, elasticity_stiffness, scalar_basis
from strainwave.fea.mesh_data import to_skfem
from strainwave.fea.meshing import mesh_section
from strainwave.fea.session import gmsh_session
from strainwave.fea.solver import solve_elasticity
from strainwave.geometry.part import FaceRef

E, NU = 2.1e5, 0.3
R_IN, R_OUT = 1.0, 2.0
A_LAME, B_LAME = 1e-3, 2e-3     # u_r = A r + B / r solves Navier's equation for any A, B (Lame cylinder)


def _annulus():
    import build123d as bd
    return (bd.Circle(R_OUT) - bd.Circle(R_IN)).faces()[0]


def _exact(x):
    r2 = x[0] ** 2 + x[1] ** 2
    return (A_LAME + B_LAME / r2) * x   # (A r + B/r) e_r


def _l2_error(h, order):
    import skfem
    with gmsh_session() as model:
        md = mesh_section(model, _annulus(), size_mm=h, order=order)
    sk = to_skfem(md)
    basis = scalar_basis(sk.mesh, sk.element)
    lame = Lame.from_young(E, NU, plane_stress=True)
    K = elasticity_stiffness(basis, lame)
    exact = _exact(basis.doflocs).T.ravel()
    bnd = basis.get_dofs().flatten()
    fixed = (2 * bnd[:, None] + np.arange(2)).ravel()
    u, _ = solve_elasticity(K, np.zeros(K.shape[0]), fixed_dofs=fixed, fixed_values=exact[fixed],
                            coords=basis.doflocs, dim=2, method="direct")
    vb = skfem.Basis(sk.mesh, skfem.ElementVector(sk.element), intorder=8)
    err = skfem.Functional(lambda w: ((w.u - _exact(w.x)) ** 2).sum(axis=0)).assemble(vb, u=vb.interpolate(u))
    return np.sqrt(err)


@pytest.mark.parametrize("order,theory", [(1, 2.0), (2, 3.0)])
def test_l2_convergence_rate_of_lame_cylinder(order, theory):
    hs = np.array([0.4, 0.2, 0.1])
    errs = np.array([_l2_error(h, order) for h in hs])
    slope = np.polyfit(np.log(hs), np.log(errs), 1)[0]
    # L2 displacement error of P_k is O(h^(k+1)); curved (isoparametric) P2 keeps that on the circles.
    # 0.2: the tolerance for an observed slope over three unstructured meshes.
    assert abs(slope - theory) < 0.2, (slope, errs)


def test_section_named_edges_and_points():
    outer_len = 2 * np.pi * R_OUT
    with gmsh_session() as model:
        md = mesh_section(model, _annulus(), size_mm=0.3, order=2,
                          named_edges={"inner": (FaceRef((0.0, 0.0, 0.0), 2 * np.pi * R_IN),),
                                       "outer": lambda pts: bool(np.allclose(np.hypot(pts[:, 0], pts[:, 1]), R_OUT))},
                          named_points={"load": [(0.0, R_OUT), (0.0, -R_OUT)]})
    assert md.dim == 2 and md.cells.shape[1] == 6
    # the two load points are mesh nodes, exactly where asked
    pts = md.nodes_mm[md.groups["load"][:, 0]]
    assert np.allclose(sorted(pts[:, 1]), [-R_OUT, R_OUT], atol=1e-12) and np.allclose(pts[:, 0], 0, atol=1e-12)
    # outer edges (split in two arcs by the points) sum to the circumference: curved P2 edges, so
    # integrate with the mid node (Simpson on the quadratic arc) - within 1e-5 at h/r = 0.15
    e = md.groups["outer"]
    a, b, m = md.nodes_mm[e[:, 0]], md.nodes_mm[e[:, 1]], md.nodes_mm[e[:, 2]]
    length = (np.linalg.norm(m - a, axis=1) + np.linalg.norm(b - m, axis=1)).sum()
    assert length == pytest.approx(outer_len, rel=1e-3)   # chord sum of the half edges: error ~ (h/r)^2/96
    assert np.allclose(np.hypot(*md.nodes_mm[np.unique(e)][:, :2].T), R_OUT, atol=1e-9)  # nodes on the circle
    assert md.groups["inner"].shape[0] > 10
