"""Ring under two diametral forces (seed 003, eqs 3, 4, 8, 9): 2D plane-stress FEA against exact answers.

The default EWG ring (Z_R = 72, m = 1, delta = 0.012 d_R) has r_m/delta = 43.7 >= 40, the thin-ring
regime of the issue's 0.5 % delta_CD check. The section is built here from two circles (the FEA is
under test, not the geometry); mesh size delta/2 keeps each solve near one second.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from strainwave.analytic.ring import bending_moment_Nmm, delta_ab_coefficient, delta_cd_coefficient
from strainwave.analytic.ring_arc_load import thin_ring_deflections_mm, thin_ring_moment_Nmm
from strainwave.analytic.study_loads import ring_compression_load
from strainwave.analytic.thick_ring import RingSection, deflections_mm, winkler_bach_stress_MPa
from strainwave.fea.assembly import Lame
from strainwave.fea.convergence import Convergence
from strainwave.fea.ring_compression import contact_load, ring_geometry, run
from strainwave.fea.ring_plane import solve_ring_section
from strainwave.params import load_params

E_MPA, NU = 2.1e5, 0.3


def _annulus(r_in, r_out):
    from build123d import Edge, Face, Wire
    return Face(Wire([Edge.make_circle(r_out)])).cut(Face(Wire([Edge.make_circle(r_in)]))).faces()[0]


@pytest.fixture(scope="module")
def ring():
    params = load_params()
    geo = ring_geometry(params)
    f = ring_compression_load(params)["force_N"]        # the thin-ring force for W0, as the registry passes it
    load = contact_load(geo, f)
    lame = Lame.from_young(E_MPA, NU, plane_stress=True)
    sols = solve_ring_section(_annulus(geo.r_root_mm, geo.r_outer_mm), geo, load, lame,
                              size_mm=geo.thickness_mm / 2, order=2, ewg_w0_mm=1.0)
    ei = E_MPA * geo.width_mm * geo.thickness_mm ** 3 / 12
    return geo, load, ei, sols


def _roark_factor(geo, which: int) -> float:
    """Thick-ring over thin-ring deflection (Roark Table 9.2 case 1: normal force and shear)."""
    sec = RingSection(geo.r_m_mm, geo.thickness_mm, geo.width_mm)
    return deflections_mm(1.0, sec, E_MPA, NU, thick=False)[which] / (
        (delta_cd_coefficient() if which == 0 else delta_ab_coefficient()) * geo.r_m_mm ** 3 / (E_MPA * sec.I_mm4))


def test_thin_ring_delta_cd_within_half_percent(ring):
    geo, load, ei, sols = ring
    assert geo.r_m_mm / geo.thickness_mm >= 40
    exact = delta_cd_coefficient() * load.force_N * geo.r_m_mm ** 3 / ei    # 0.148778 F r^3/EI
    fea = sols["force"].mid.delta_cd_mm
    # The tolerance 0.5 % (issue 4) must cover the physics the thin formula leaves out; Roark's
    # normal-force and shear terms are 2.94 alpha/0.1488 = 0.086 % here and the arc load -0.007 %:
    thick = _roark_factor(geo, 0) - 1.0
    assert 0.0 < thick < 0.001
    assert abs(fea / exact - 1.0) < 0.005
    # and the FEA must see that correction: against thin-ring-for-the-arc x Roark it agrees to 0.03 %
    # (discretization at h = delta/2 is ~1e-4, from the GCI of the study)
    arc_cd, _ = thin_ring_deflections_mm(load.force_N, load.half_angle_rad, geo.r_m_mm, ei)
    assert fea / (arc_cd * (1.0 + thick)) == pytest.approx(1.0, abs=3e-4)


def test_thin_ring_delta_ab(ring):
    geo, load, ei, sols = ring
    exact = 0.136620 * load.force_N * geo.r_m_mm ** 3 / ei
    fea = sols["force"].mid.delta_ab_mm
    # same budget as delta_CD: Roark's D_H correction is +0.025 % here
    assert abs(fea / exact - 1.0) < 0.005
    _, arc_ab = thin_ring_deflections_mm(load.force_N, load.half_angle_rad, geo.r_m_mm, ei)
    assert fea / (arc_ab * _roark_factor(geo, 1)) == pytest.approx(1.0, abs=3e-4)


def test_symmetry_delta_at_C_equals_D(ring):
    _, _, _, sols = ring
    mid = sols["force"].mid
    # C is unconstrained: only the load and mesh symmetry make u_y(C) = -u_y(D); 1e-6 relative is far
    # below discretization error yet far above round-off of the direct solve
    assert mid.u_C_mm[1] == pytest.approx(-mid.u_D_mm[1], rel=1e-6)
    assert abs(mid.u_D_mm[0]) < 1e-6 * abs(mid.u_D_mm[1])
    assert mid.u_B_mm[0] == pytest.approx(-mid.u_A_mm[0], rel=1e-6)


def test_section_stresses_against_eqs_8_9(ring):
    geo, load, ei, sols = ring
    s = sols["force"]
    k = 2.0 / s.mid.delta_cd_mm                         # scale to W0 = 1 mm
    d_m = 2 * geo.r_m_mm
    eq8 = -8.557960 * 1.0 * E_MPA * geo.thickness_mm / d_m ** 2     # outer fibre at D
    eq9 = 4.884852 * 1.0 * E_MPA * geo.thickness_mm / d_m ** 2      # outer fibre at B
    sec = RingSection(geo.r_m_mm, geo.thickness_mm, geo.width_mm)
    # Tolerance from what eqs 8/9 leave out, computed for this ring:
    # - curvature (Winkler-Bach) changes a fibre stress by ~delta/(3 r) = 0.8 %;
    # - the hoop force F/2 at B adds F/(2 B delta) = delta/(2.18 r) = 1.05 % of the bending stress;
    # - the arc load lowers M_D by pi c/(4 r) = 0.9 % (c = delta/2).
    m_arc = thin_ring_moment_Nmm(np.array([0.0, 0.5 * np.pi]), load.force_N, load.half_angle_rad, geo.r_m_mm)
    c = geo.thickness_mm / 2
    budget_B = abs(winkler_bach_stress_MPa(m_arc[0], -load.force_N / 2, geo.r_outer_mm, sec)
                   / (m_arc[0] * c / sec.I_mm4) - 1.0) + 0.01
    # + 1 % discretization of a fibre stress at h = delta/2 (measured: 0.67 % at delta/2, 0.12 % at
    # delta/4, 0.03 % at delta/8 against Winkler-Bach at B)
    budget_D = abs(m_arc[1] / bending_moment_Nmm(0.5 * np.pi, load.force_N, geo.r_m_mm) - 1.0) + 0.008 + 0.01
    assert abs(s.sigma_B[0] * k / eq9 - 1.0) < budget_B
    assert abs(s.sigma_D[0] * k / eq8 - 1.0) < budget_D
    # inner fibres: the curved-beam model of the actual load within 1 % (the discretization above; the
    # contact stress under the load decays before the inner fibre)
    for sig, m, n in ((s.sigma_B[1], m_arc[0], -load.force_N / 2), (s.sigma_D[1], m_arc[1], 0.0)):
        wb = winkler_bach_stress_MPa(m, n, geo.r_root_mm, sec)
        assert sig == pytest.approx(wb, rel=0.01)


def test_ewg_prescribed_deformation_reaches_W0(ring):
    _, _, _, sols = ring
    e = sols["ewg"]
    # the rigid strips move the outer surface by W0 = 1 mm; the mid-layer follows within the local
    # through-thickness compression (< 0.1 % of W0 for this load)
    assert e.mid.delta_cd_mm / 2 == pytest.approx(1.0, abs=1e-3)
    assert e.force_N > 0


@pytest.mark.heavy
def test_study_quick_carries_gci(monkeypatch, tmp_path):
    import strainwave.fea.ring_compression as rc
    from strainwave.geometry.involute import ToothSpec, gear_face

    params = load_params().with_value("ewg_drive.flexspline_teeth", 40)   # fewer teeth: fast geometry
    geo = rc.ring_geometry(params)

    def section(p, *, teeth):
        if not teeth:
            return _annulus(geo.r_root_mm, geo.r_outer_mm)
        return gear_face(ToothSpec(40, 1.0, internal=True), outer_radius_mm=geo.r_outer_mm)

    monkeypatch.setattr(rc, "section_face", section)
    res = run(params, quick=True, vtu=tmp_path / "ring.vtu", **ring_compression_load(params))
    for name in ("delta_cd_mm", "delta_ab_mm", "force_for_W0_N", "sigma_B_outer_MPa", "sigma_D_outer_MPa",
                 "sigma_B_inner_MPa", "sigma_D_inner_MPa", "tooth_influence", "stress_concentration"):
        conv = res[name].convergence
        assert isinstance(conv, Convergence) and len(conv.values) == 3
        assert np.isfinite(conv.gci_fine)
    # thin ring at W0 = 1 mm: delta_CD = 2 mm at the thin-ring force within the 0.5 % thin-ring budget
    assert res["delta_cd_mm"].value == pytest.approx(2.0, rel=0.005)
    assert res["delta_cd_mm"].convergence.gci_fine < 0.002
    # teeth make the ring stiffer and the root a notch: both factors exceed 1
    assert res["tooth_influence"].value > 1.0 and res["stress_concentration"].value > 1.0
    # VTU of the smooth and toothed force cases, smooth first (the report samples its mid-layer)
    assert [p.name for p in res.fields] == ["ring_smooth.vtu", "ring_toothed.vtu"]
    import pyvista   # the file is VTK's compressed binary XML: read it as ParaView would
    grid = pyvista.read(res.fields[0])
    assert {"displacement_mm", "von_mises_MPa"} <= set(grid.point_data.keys())
    assert grid.n_points == res.mesh.nodes
    # the typed load: the force passed in, on the named contact arcs, with the arc the allowance needs
    assert res.load.force_N == pytest.approx(ring_compression_load(params)["force_N"], rel=1e-15)
    assert res.load.on == ("contact",) and res.load.parameter("half_angle_rad") > 0 and res.crack is None
    assert {g for s in res.supports for g in s.on} == {"A", "B", "D"}


def test_solid_3d_between_plane_stress_and_plane_strain(ring):
    from strainwave.fea.ring_solid import solve_ring_solid
    geo, load, ei, sols = ring
    lame3 = Lame.from_young(E_MPA, NU)
    coarse, fine = (solve_ring_solid(geo, load, lame3, n_radial=n) for n in (1, 2))
    assert fine.mesh.elements < 5000                        # a coarse 3D mesh: ~1 s
    ratio = fine.delta_cd_mm / sols["force"].mid.delta_cd_mm
    # Derived bounds: the 3D ring's bending stiffness lies between plane stress (E I, the 2D model) and
    # plane strain (E I/(1 - nu^2), width contraction fully suppressed), so 1 - nu^2 <= ratio <= 1.
    # Discretization: 1 -> 2 layers moves delta_CD by 0.6 % and 2 -> 3 by 0.06 % (p ~ 5), far inside
    # the 9 % window; the 2D side's error at delta/2 is ~1e-4.
    assert 1.0 - NU ** 2 < ratio < 1.0
    # B^2/(r delta) = 4.4 here: a moderately wide ring, measured ratio 0.978; a 3D model that lost the
    # Poisson coupling (ratio 1) or its free edges (plane strain, 0.91) would fall outside +/- 1.5 %
    assert ratio == pytest.approx(0.978, abs=0.015)
    assert abs(fine.delta_cd_mm / coarse.delta_cd_mm - 1.0) < 0.01
    # anticlastic curvature: the free edges are softer than the mid-plane; the width average in between
    assert fine.delta_cd_midplane_mm < fine.delta_cd_mm < fine.delta_cd_edge_mm
    ratio_ab = fine.delta_ab_mm / sols["force"].mid.delta_ab_mm
    assert 1.0 - NU ** 2 < ratio_ab < 1.0


def test_facet_traction_on_curved_p2_surface(ring):
    from strainwave.fea.mesh_data import to_skfem
    from strainwave.fea.surface import SurfaceQuadrature
    from strainwave.fea.ring_solid import ring_lattice_mesh
    geo, load, _, _ = ring
    md = ring_lattice_mesh(geo, load, n_radial=1).md
    sk = to_skfem(md)
    n = 3 * (int(sk.node_to_dof.max()) + 1)
    quad = SurfaceQuadrature.of(md, "outer", order=6)     # the order the 3D ring and the bearing load with
    r, half_b = geo.r_outer_mm, geo.width_mm / 2
    ones = quad.load_vector(lambda x: np.stack([np.ones_like(x[0])] * 3), sk.node_to_dof, 3, n)
    # a uniform unit traction: the resultant is the curved surface's area (pi/2) r (B/2); curved P2
    # facets reproduce the cylinder to O(h^4) (1e-8 here), the 1e-6 covers the element chords
    assert ones[2::3].sum() == pytest.approx(0.5 * np.pi * r * half_b, rel=1e-6)
    # a unit radial pressure on the quarter cylinder: x-resultant = r (B/2) (int cos over [0, pi/2])
    radial = quad.load_vector(lambda x: np.stack([x[0], x[1], 0 * x[2]]) / np.hypot(x[0], x[1]), sk.node_to_dof, 3, n)
    assert radial[0::3].sum() == pytest.approx(r * half_b, rel=1e-6)
    assert radial[2::3].sum() == pytest.approx(0.0, abs=1e-12)


def test_one_factorisation_serves_force_and_ewg_cases():
    """ring_plane._solve_cases (one factorisation, the EWG strips held through its Schur complement) against two
    direct solves with the conditions eliminated (solver.solve_elasticity): a clamped-free P2 strip, a load on its
    top edge and, for the EWG case, its top and bottom edges' u_y held at -W0 and +W0."""
    from skfem import Basis, ElementTriP2, MeshTri

    from strainwave.fea.assembly import elasticity_stiffness
    from strainwave.fea.ring_plane import _solve_cases
    from strainwave.fea.solver import solve_elasticity

    sb = Basis(MeshTri.init_tensor(np.linspace(0.0, 8.0, 17), np.linspace(0.0, 1.0, 5)), ElementTriP2())
    K = elasticity_stiffness(sb, Lame.from_young(E_MPA, NU, plane_stress=True), thickness_mm=2.0).tocsr()
    x, y = sb.doflocs
    base = np.concatenate([2 * np.flatnonzero(x < 1e-12), 2 * np.flatnonzero(x < 1e-12) + 1])
    top_dofs, bottom_dofs = np.flatnonzero((y > 1 - 1e-12) & (x > 5.9)), np.flatnonzero((y < 1e-12) & (x > 5.9))
    f = np.zeros(K.shape[0])
    f[2 * top_dofs + 1] = -1.0
    arc_y = np.sort(np.concatenate([2 * top_dofs + 1, 2 * bottom_dofs + 1]))
    top = np.isin(arc_y, 2 * top_dofs + 1)
    w0 = 0.01
    cases, reaction = _solve_cases(K, f, base, arc_y, top, w0)
    u_force, _ = solve_elasticity(K, f, fixed_dofs=base, coords=sb.doflocs, dim=2, method="direct")
    fixed = np.concatenate([base, arc_y])
    values = np.concatenate([np.zeros(base.size), np.where(top, -w0, w0)])
    u_ewg, _ = solve_elasticity(K, np.zeros_like(f), fixed_dofs=fixed, fixed_values=values, coords=sb.doflocs, dim=2,
                                method="direct")
    assert np.abs(cases["force"][1] - u_force).max() <= 1e-9 * np.abs(u_force).max()
    assert np.abs(cases["ewg"][1] - u_ewg).max() <= 1e-9 * np.abs(u_ewg).max()
    direct_reaction = -float((K @ u_ewg)[2 * top_dofs + 1].sum())
    assert reaction == pytest.approx(direct_reaction, rel=1e-9)
    assert abs(reaction) > 0
    assert cases["force"][2].residual < 1e-9 and cases["ewg"][2].residual < 1e-9


def _polar_mesh(r_in=9.0, r_out=10.0, n_r=3, n_t=120):
    """A thin ring of straight triangles, cut open at 0.01 rad (its two cut ends are boundary facets too)."""
    from skfem import MeshTri
    m = MeshTri.init_tensor(np.linspace(r_in, r_out, n_r), np.linspace(0.0, 2 * np.pi, n_t + 1)[:-1] + 0.01)
    r, t = m.p
    return MeshTri(np.array([r * np.cos(t), r * np.sin(t)]), m.t)


def test_probes_read_each_point_in_its_own_cell():
    """ring_sections.Probes (one basis for all points, read on its diagonal) against a closed form: P2 holds the
    quadratic field u = (a x^2 + b y, c x y) exactly, so its value and stress at 8 points in 8 cells are known."""
    from skfem import Basis, ElementTriP2, MeshTri

    from strainwave.fea.ring_sections import Probes, hoop
    sb = Basis(MeshTri.init_tensor(np.linspace(-2.0, 2.0, 9), np.linspace(-1.0, 1.0, 5)), ElementTriP2())
    a, b, c = 0.002, -0.001, 0.003
    x, y = sb.doflocs
    u = np.zeros(2 * sb.N)
    u[0::2], u[1::2] = a * x ** 2 + b * y, c * x * y
    pts = np.array([[-1.9, -1.3, -0.7, -0.2, 0.3, 0.9, 1.4, 1.85], [0.9, -0.6, 0.2, -0.95, 0.55, -0.1, 0.8, -0.4]])
    lame = Lame.from_young(E_MPA, NU, plane_stress=True)

    def closed(a, b, c):
        px, py = pts
        grad = np.array([[2 * a * px, np.full_like(px, b)], [c * py, c * px]])     # d u_i / d x_j
        eps = 0.5 * (grad + grad.transpose(1, 0, 2))
        sig = lame.lam_MPa * (eps[0, 0] + eps[1, 1]) * np.eye(2)[:, :, None] + 2 * lame.mu_MPa * eps
        return np.array([a * px ** 2 + b * py, c * px * py]), np.moveaxis(sig, -1, 0)

    probes = Probes.at(sb, pts, vector=True)
    assert np.unique(probes.basis.tind).size == pts.shape[1]          # one cell per point: the diagonal matters
    values, stresses = probes.values(u), probes.stresses(u, lame)
    exact_u, exact_s = closed(a, b, c)
    assert np.abs(values - exact_u).max() < 1e-12
    assert np.abs(stresses - exact_s).max() < 1e-8 * np.abs(exact_s).max()
    assert np.allclose(hoop(stresses, 0.3), hoop(exact_s, 0.3), rtol=1e-10, atol=1e-9)
    # the check can fail: a field 1 % off in one coefficient is told apart
    wrong_u, wrong_s = closed(a, b, 1.01 * c)
    assert np.abs(values - wrong_u).max() > 1e-9
    assert np.abs(stresses - wrong_s).max() > 1e-3 * np.abs(exact_s).max()


def test_window_facets_hold_every_boundary_point_near_B_and_D():
    """ring_plane._window_facets: every boundary facet with a quadrature point within the window of B (0) or D
    (pi/2) is kept (the peaks read there are the same), and far fewer than all are."""
    from skfem import ElementTriP2, ElementVector, FacetBasis

    from strainwave.fea.ring_plane import _window_facets
    mesh = _polar_mesh()
    boundary = mesh.boundary_facets()
    window = 0.05
    kept = _window_facets(mesh, boundary, window)
    fb = FacetBasis(mesh, ElementVector(ElementTriP2()), facets=boundary, intorder=4)
    x = fb.global_coordinates().value                                    # (2, nfacets, nq)
    ang = np.arctan2(x[1], x[0])
    near = np.zeros(boundary.size, bool)
    for centre in (0.0, 0.5 * np.pi):
        near |= (np.abs(np.angle(np.exp(1j * (ang - centre)))) <= window).any(axis=1)
    assert near.sum() >= 4 and set(boundary[near]) <= set(kept)
    assert kept.size < 0.2 * boundary.size
    # the check can fail: a selection by the facets' first quadrature point alone loses facets at the windows' edges
    first = np.zeros(boundary.size, bool)
    for centre in (0.0, 0.5 * np.pi):
        first |= np.abs(np.angle(np.exp(1j * (ang[:, 0] - centre)))) <= window
    assert not set(boundary[near]) <= set(boundary[first])
