"""Thermal (initial) strain through the solver core: load f = int B^T C eps_th dV and sigma = C (eps - eps_th).

Every expectation is a first-principles closed form of the same problem, exact in the P2 space, so the
FEA must meet it to round-off (tolerances are round-off of the direct solve, scaled by the answer):
- a body free to expand under a uniform rise dT: u = alpha dT x, sigma = 0;
- a body clamped on its whole boundary: u = 0, sigma = -E alpha dT / (1 - 2 nu) I (plane stress: / (1 - nu));
- a free body under a LINEAR temperature field: eps_th = alpha T(x) I is compatible, so sigma = 0 and
  u_i = alpha (T0 x_i + (b.x) x_i - |x|^2 b_i / 2) (quadratic: in the P2 space).
"""
from __future__ import annotations

import numpy as np
import pytest

from strainwave.fea.assembly import Lame, ThermalStrain
from strainwave.fea.fields import cell_stress, nodal_stress
from strainwave.fea.mesh_data import to_skfem
from strainwave.fea.static import solve_static

E_MPa, NU, ALPHA_PER_K, DT_K = 210_000.0, 0.3, 1.2e-5, 80.0
BOX_MM = (20.0, 10.0, 15.0)
# round-off of the direct solve on these few-thousand-dof systems, relative to the answer's scale
ROUND_OFF = 1e-9


@pytest.fixture(scope="module")
def box():
    from strainwave.fea.meshing import extract, generate
    from strainwave.fea.session import gmsh_session
    with gmsh_session() as model:
        model.occ.addBox(0.0, 0.0, 0.0, *BOX_MM)
        model.occ.synchronize()
        generate(model, 3, 2, size_mm=5.0)
        return extract(model, 3, 2, {}, 5.0)


@pytest.fixture(scope="module")
def plate():
    from strainwave.fea.meshing import mesh_section
    from strainwave.fea.session import gmsh_session
    with gmsh_session() as model:
        return mesh_section(model, loops=[np.array([[0, 0], [20, 0], [20, 10], [7, 13], [0, 10]], float)],
                            size_mm=3.0)


def _uniform(dT=DT_K):
    return ThermalStrain(ALPHA_PER_K, lambda x: dT)


def _on(sk, axis, value):
    """Scalar dofs on the plane x_axis = value."""
    return np.flatnonzero(np.abs(sk.doflocs[axis] - value) < 1e-9)


def _lame(dim):
    return Lame.from_young(E_MPa, NU, plane_stress=dim == 2)


def _solve(md, thermal, fixed_dofs, fixed_values=0.0):
    lame = _lame(md.dim)
    sol = solve_static(md, lame, fixed_dofs=fixed_dofs, fixed_values=fixed_values, thermal=thermal, method="direct")
    return sol, nodal_stress(md, sol.sk, sol.u, lame, thermal)


@pytest.mark.parametrize("mesh", ["box", "plate"])
def test_a_free_body_under_a_uniform_rise_expands_stress_free(mesh, request):
    md = request.getfixturevalue(mesh)
    d = md.dim
    sk = to_skfem(md)
    # symmetry planes only (u_a = 0 on x_a = 0): no restraint on the expansion
    fixed = np.concatenate([d * _on(sk, a, 0.0) + a for a in range(d)])
    sol, stress = _solve(md, _uniform(), fixed)
    exact = ALPHA_PER_K * DT_K * md.nodes_mm[:, :d]
    assert np.abs(sol.nodal_u() - exact).max() <= ROUND_OFF * np.abs(exact).max()
    # the far faces moved by alpha dT L
    far = np.argmax(md.nodes_mm[:, 0])
    assert sol.nodal_u()[far, 0] == pytest.approx(ALPHA_PER_K * DT_K * md.nodes_mm[far, 0], rel=ROUND_OFF)
    assert np.abs(stress).max() <= ROUND_OFF * E_MPa * ALPHA_PER_K * DT_K


@pytest.mark.parametrize("mesh", ["box", "plate"])
def test_a_clamped_body_under_a_uniform_rise_carries_the_hydrostatic_stress(mesh, request):
    md = request.getfixturevalue(mesh)
    d = md.dim
    sk = to_skfem(md)
    from strainwave.fea.assembly import scalar_basis
    walls = scalar_basis(sk.mesh, sk.element).get_dofs().flatten()          # every boundary node
    fixed = (d * walls[:, None] + np.arange(d)).ravel()
    sol, stress = _solve(md, _uniform(), fixed)
    sigma = -E_MPa * ALPHA_PER_K * DT_K / ((1.0 - 2.0 * NU) if d == 3 else (1.0 - NU))
    expected = np.array([sigma, sigma, sigma if d == 3 else 0.0, 0.0, 0.0, 0.0])
    assert np.abs(sol.u).max() <= ROUND_OFF * ALPHA_PER_K * DT_K * BOX_MM[0]
    assert np.abs(stress - expected).max() <= ROUND_OFF * abs(sigma)
    assert np.abs(cell_stress(md, sol.sk, sol.u, _lame(d), _uniform()) - expected).max() <= ROUND_OFF * abs(sigma)
    if d == 3:
        assert sigma == pytest.approx(-(3 * _lame(3).lam_MPa + 2 * _lame(3).mu_MPa) * ALPHA_PER_K * DT_K)


def _linear_field(T0_K=30.0, b_K_per_mm=(1.5, -0.8, 2.0)):
    b = np.array(b_K_per_mm)

    def rise(x):
        return T0_K + np.tensordot(b[:x.shape[0]], x, axes=1)

    def displacement(x):                      # x (n, d) -> u (n, d), compatible with eps = alpha T I
        bx = x @ b[:x.shape[1]]
        return ALPHA_PER_K * (T0_K * x + bx[:, None] * x - 0.5 * (x * x).sum(1)[:, None] * b[:x.shape[1]])

    return ThermalStrain(ALPHA_PER_K, rise), displacement


def test_a_free_body_under_a_linear_temperature_field_is_stress_free(box):
    sk = to_skfem(box)
    thermal, displacement = _linear_field()
    exact = displacement(sk.doflocs.T)                       # per scalar dof
    base = _on(sk, 2, 0.0)                                    # the exact field held on one face, the rest free
    fixed = (3 * base[:, None] + np.arange(3)).ravel()
    sol, stress = _solve(box, thermal, fixed, exact[base].ravel())
    u = sol.u.reshape(-1, 3)
    assert np.abs(u - exact).max() <= ROUND_OFF * np.abs(exact).max()
    scale = E_MPa * ALPHA_PER_K * np.abs(thermal.rise_at(box.nodes_mm.T)).max()
    assert np.abs(stress).max() <= ROUND_OFF * scale
    # without the thermal strain in the recovery, the same field reads as the stress of a clamped body
    assert np.abs(nodal_stress(box, sol.sk, sol.u, _lame(3))).max() > 0.1 * scale


def test_the_load_is_consistent_with_the_stiffness():
    import skfem
    from strainwave.fea.assembly import elasticity_stiffness, scalar_basis, thermal_load
    from strainwave.fea.element_gradients import default_intorder
    mesh = skfem.MeshTet2.init_ball(1)
    basis = scalar_basis(mesh, skfem.ElementTetP2(), intorder=default_intorder(2))
    lame = _lame(3)
    K = elasticity_stiffness(basis, lame)
    f = thermal_load(basis.doflocs, basis.element_dofs, 2, lame, _uniform(), chunk=5)
    # f = K u for u = alpha dT x on the curved mesh (the isoparametric map reproduces a linear field)
    u = (ALPHA_PER_K * DT_K * basis.doflocs).T.ravel()
    Ku = K @ u
    assert np.abs(f - Ku).max() <= ROUND_OFF * np.abs(Ku).max()
