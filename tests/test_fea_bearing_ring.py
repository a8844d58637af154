"""Bearing inner ring (seed 000) radial compliance under the Hertzian contact load, with and without a
surface crack. The ring is built here from build123d primitives (bore 60, race 70 mm: t_i = 10 mm as in
the seed's example) so the FEA is tested independently of geometry/; meshes are coarse on purpose.
One study run (three meshes, uncracked and a 3 mm crack on its patch, VTU output) is shared by the tests; the
whole ring's seam route (no cache folder) and the plain ring run once more each."""
from __future__ import annotations

import math

import numpy as np
import pytest

from strainwave.analytic.study_loads import bearing_ring_load
from strainwave.geometry.part import FaceRef, Part, PartName
from strainwave.params import load_params

R_BORE, R_RACE, WIDTH = 60.0, 70.0, 15.0


def _ring(a_mm=None):
    """The ring; with ``a_mm`` the crack is a seam: the semi-ellipse (depth a, half length 2a on the race)
    as a zero-width surface in y = 0 (the full ellipse: its outer half lies outside and is trimmed)."""
    from build123d import Align, CenterOf, Cylinder, Edge, Face, GeomType, Plane, Wire
    ring = (Cylinder(R_RACE, WIDTH, align=(Align.CENTER, Align.CENTER, Align.MIN))
            - Cylinder(R_BORE, WIDTH, align=(Align.CENTER, Align.CENTER, Align.MIN)))
    front, face = (), None
    if a_mm:
        plane = Plane(origin=(R_RACE, 0.0, WIDTH / 2), x_dir=(1, 0, 0), z_dir=(0, 1, 0))
        face = Face(Wire([Edge.make_ellipse(a_mm, 2 * a_mm, plane)]))
        t = np.linspace(0.0, np.pi, 7)
        front = tuple((R_RACE - a_mm * np.sin(s), 0.0, WIDTH / 2 + 2 * a_mm * np.cos(s)) for s in t)
    cyl = lambda r: tuple(FaceRef(tuple(f.center(CenterOf.MASS)), f.area) for f in ring.faces()    # noqa: E731
                          if f.geom_type == GeomType.CYLINDER and abs(f.radius - r) < 1e-6)
    return Part(PartName.WG_BEARING_RING, ring, {"bore": cyl(R_BORE), "race": cyl(R_RACE)}, front,
                crack_surface=face, crack_plane=((R_RACE, 0.0, WIDTH / 2), (0.0, 1.0, 0.0)) if a_mm else None)


A_MM = 3.0          # a deep crack: its effect must stand far above the coarse-mesh error
H_MM = 12.0         # global size; the contact and crack-front sizes (1 mm at the finest) scale with it


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    import strainwave.fea.bearing_ring as br
    vtu = tmp_path_factory.mktemp("bearing") / "ring.vtu"
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(br, "build_seam_part", lambda params, a: _ring(a))
        mp.setattr(br, "build_plain_part", lambda params: _ring(None))      # the uncracked ring the patch reads
        # a cache folder, as validate's full plan passes: the crack on a patch of the uncracked ring
        return br.run(load_params(), mesh_size_mm=H_MM, order=2, crack_depth_mm=A_MM, vtu=vtu,
                      cache_dir=vtu.parent / "cache", **bearing_ring_load(load_params()))


def test_radial_force_is_seed_000_and_the_study_states_it(study):
    # F_r = 1.15 k_r T / d1 = 1.15 * 0.35 * 1000 / 160, computed in analytic/ and passed to fea/ as a number;
    # the result states it as its typed load, on the face it loaded (the stand-in names only its 'race'; the
    # real part's contact patch is 'contact')
    assert bearing_ring_load(load_params())["force_N"] == pytest.approx(2.515625, rel=1e-12)
    assert study.load.force_N == pytest.approx(2.515625, rel=1e-12) and study.load.unit == "N"
    assert study.load.on == ("race",) and [s.on for s in study.supports] == [("bore",)]
    assert study.crack.depth_mm == A_MM


def test_uncracked_compliance_positive_and_converging(study):
    q = study["radial_compliance_mm_per_N"]
    c = q.convergence.values                                  # fine, medium, coarse
    # a contact compliance scale: a load spread over a' b' on a 10 mm wall, 1/(E * sqrt(a'b')) ~ 1e-6 mm/N
    assert 1e-7 < q.value < 1e-5
    # a displacement-based FE model is too stiff and softens monotonically as every size shrinks
    assert c[0] > c[1] > c[2]
    assert q.convergence.monotone
    # GCI of the coarse test meshes was ~4 % at refinement ratio 1.5 with a bound of 8 % (room for gmsh
    # version differences in the unstructured meshes). At the one ratio 1.4 of every study the same error
    # gives a GCI larger by (1.5^p - 1)/(1.4^p - 1) = 1.23 at the contact field's order p ~ 1/2 (measured
    # 0.47): the bound scales with it, and still fails on any non-converging series.
    ratio_factor = (1.5 ** 0.5 - 1.0) / (1.4 ** 0.5 - 1.0)
    # GCI by the book: outside the asymptotic band the safety factor is 3, not the 1.25 the bound was set for
    fs_factor = q.convergence.safety_factor / 1.25
    assert 0.0 < q.convergence.gci_fine < 0.08 * ratio_factor * fs_factor
    assert q.convergence.extrapolated > q.value


def test_crack_at_the_hertz_centre_closes(study):
    # the crack lies in the compressed patch (hoop stress ~ -0.87 p0): with frictionless face contact it stays
    # shut and adds ~no compliance, while the linear solve let the faces pass through each other (issue 13:
    # 19 % of the uncracked compliance at a = 3 mm)
    d = study["delta_radial_compliance_mm_per_N"]
    c0 = study["radial_compliance_mm_per_N"].value
    assert all(abs(v) < 1e-4 * c0 for v in d.convergence.values)
    solver = study.solver
    assert solver["compliance_without_contact_mm_per_N"] - c0 > 0.05 * c0
    assert solver["contact_closed_pairs"] > 0.8 * solver["contact_pairs"]
    assert solver["contact_min_opening_mm"] > -1e-12
    c_cr = study["cracked_radial_compliance_mm_per_N"].value
    assert c_cr == pytest.approx(c0 + d.value, rel=1e-12)


def test_fea_crack_compliance_against_the_seed_forms(study):
    from strainwave.analytic.cracks import bearing_displacement_mm
    from strainwave.analytic.variant import Variant
    f_r = study.load.force_N
    p, wg = load_params(), load_params().wave_generator
    an = {v.value: {"delta_u_H_mm": bearing_displacement_mm(f_r, wg.bearing_inner_ring_thickness_mm, wg.beta,
                                                           tuple(wg.contact_semi_axes_mm), A_MM,
                                                           p.material.youngs_modulus_MPa,
                                                           p.cracks.surface_crack_shape_factor, v)} for v in Variant}
    for v in an.values():
        v["delta_compliance_mm_per_N"] = v["delta_u_H_mm"] / f_r
    pub, cor = an["published"]["delta_u_H_mm"], an["corrected"]["delta_u_H_mm"]
    # seed 000 du_H as published carries F_r^2 (and the rounded 0.217) where the corrected form has F_r
    from strainwave.analytic.cracks import hertz_mode_i_constant
    assert pub / cor == pytest.approx(f_r * 0.217 / hertz_mode_i_constant(), rel=1e-9)
    assert an["corrected"]["delta_compliance_mm_per_N"] == pytest.approx(cor / f_r, rel=1e-12)
    # the seed's form assumes a tensile beta p0/2 across the crack; at the Hertz centre the crack is compressed
    # and shut, so the FEA adds less than 1 % of what the seed predicts (a finding, not an agreement)
    ratio = study["delta_radial_compliance_mm_per_N"].value / an["corrected"]["delta_compliance_mm_per_N"]
    assert abs(ratio) < 0.01


def test_vtu_fields_written(study):
    import pyvista as pv
    cracked, uncracked = study.fields
    assert cracked.name == "ring_cracked.vtu" and uncracked.name == "ring_uncracked.vtu"
    grid = pv.read(str(cracked))
    assert {"displacement_mm", "von_mises_MPa", "stress_MPa"} <= set(grid.point_data.keys())
    npts = grid.n_points
    # the uncracked file holds the uncracked ring's finest mesh, every node (P2 cells keep their mid nodes); the
    # cracked file the crack's patch of the seam mesh, opened: each crack pair's two nodes at one point
    n_unc = pv.read(str(uncracked)).n_points
    assert n_unc == study.solver["uncracked_nodes"] and npts < n_unc
    _, counts = np.unique(np.round(np.asarray(grid.points, float), 9), axis=0, return_counts=True)
    assert (counts == 2).sum() == study.solver["contact_pairs"] and counts.max() == 2
    radius = study.solver["patch_radius_mm"]
    assert np.linalg.norm(np.asarray(grid.points) - [R_RACE, 0.0, WIDTH / 2], axis=1).max() < 1.5 * radius
    # the arrays are zlib-compressed binary (fea/fields.py): read them as ParaView would
    import pyvista as pv
    vm = np.asarray(pv.read(str(cracked)).point_data["von_mises_MPa"], dtype=np.float64)
    # von Mises is non-negative everywhere and peaks under the Hertz pressure (p0 = 3F/(2 pi a'b') = 0.08 MPa)
    assert vm.size == npts and vm.min() >= 0.0 and 0.01 < vm.max() < 10.0


def test_isolated_meshing_survives_a_native_abort(monkeypatch):
    import os

    import strainwave.fea.mesh_isolated as mi
    from strainwave.fea.meshing import MeshingFailed, Refine

    def fake_mesh_part(model, part, *, size_mm, order, refine, preload_kernels):
        if size_mm == 2.0:            # the first attempt dies as gmsh's std::terminate does
            os.abort()
        return {"size_mm": size_mm, "refine_mm": refine[0].size_mm, "preload_kernels": preload_kernels}

    monkeypatch.setattr(mi, "mesh_part", fake_mesh_part)
    md, factor = mi.mesh_part_isolated(None, size_mm=2.0, order=2, refine=[Refine(0.5, 1.0, 2.0)])
    # the retry scales the global and the local sizes together, by the first factor after 1
    assert factor == mi.SIZE_FACTORS[1]
    # the child meshes for its parent, which assembles: it loads no assembly kernels of its own
    assert md == {"size_mm": 2.0 * factor, "refine_mm": 0.5 * factor, "preload_kernels": False}
    monkeypatch.setattr(mi, "mesh_part", lambda *a, **k: os.abort())
    with pytest.raises(MeshingFailed, match="exited with code"):
        mi.mesh_part_isolated(None, size_mm=2.0, order=2, refine=[], factors=(1.0, 1.03))


def test_no_crack_means_uncracked_and_is_the_crack_runs_uncracked_ring(study):
    """crack_depth_mm=None is the uncracked ring (as for every study), not the parameter file's crack: only
    the radial compliance, on plain meshes. The crack run reads the same uncracked ring (``global_ring``), so its
    uncracked compliance is this one; its cracked one adds the patch's crack term."""
    import strainwave.fea.bearing_ring as br
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(br, "build_plain_part", lambda params: _ring(None))
        plain = br.run(load_params(), mesh_size_mm=H_MM, order=2, crack_depth_mm=None,
                       **bearing_ring_load(load_params()))
    assert set(plain.quantities) == {"radial_compliance_mm_per_N"} and plain.crack is None
    a, b = plain["radial_compliance_mm_per_N"], study["radial_compliance_mm_per_N"]
    assert b.convergence.values == pytest.approx(a.convergence.values, rel=1e-9)
    cracked, delta = study["cracked_radial_compliance_mm_per_N"], study["delta_radial_compliance_mm_per_N"]
    assert np.allclose(cracked.convergence.values, np.add(a.convergence.values, delta.convergence.values), rtol=1e-12)


def test_the_whole_rings_seam_agrees_with_the_patch(study):
    """Without a cache folder the crack is the whole ring's seam (one factorisation per mesh): its crack term agrees
    with the patch's within the root-sum-square of their uncertainties, and its uncracked compliance (the tied seam
    mesh) with the plain ring's within 3 x both GCIs."""
    import strainwave.fea.bearing_ring as br
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(br, "build_seam_part", lambda params, a: _ring(a))
        whole = br.run(load_params(), mesh_size_mm=H_MM, order=2, crack_depth_mm=A_MM,
                       **bearing_ring_load(load_params()))
    assert whole.solver["method"].endswith("-schur") and study.solver["method"].endswith("-schur-patch")
    a, b = whole["delta_radial_compliance_mm_per_N"], study["delta_radial_compliance_mm_per_N"]
    assert abs(a.value - b.value) <= math.hypot(a.uncertainty, b.uncertainty)
    c, d = whole["radial_compliance_mm_per_N"], study["radial_compliance_mm_per_N"]
    assert abs(c.value - d.value) <= 3.0 * (c.uncertainty + d.uncertainty)
    # the same contact state: the crack at the Hertz centre mostly shut in both
    assert whole.solver["contact_closed_pairs"] > 0.8 * whole.solver["contact_pairs"]


def test_the_uncracked_ring_is_read_back_for_another_depth_and_solved_again_for_another_ring(study, monkeypatch):
    """The study's cache folder holds the uncracked ring per refinement (``global_ring``): a case at another crack
    depth reads it back without meshing; another contact size or another ring is not in it."""
    import strainwave.fea.bearing_ring as br
    params = load_params()
    force = bearing_ring_load(params)["force_N"]
    variant = br.BearingRing(params, 2, H_MM, force, A_MM)
    cache = study.fields[0].parent / "cache"
    contact_mm = variant._local_sizes_mm(0)[0]

    def no_mesh(*args, **kwargs):
        raise AssertionError("meshed again")
    monkeypatch.setattr(br, "mesh_part_isolated", no_mesh)
    monkeypatch.setattr(br, "build_plain_part", lambda p: _ring(None))
    deeper = params.with_value("wave_generator.bearing_crack_depth_mm",
                               2 * params.wave_generator.bearing_crack_depth_mm)
    ring = br.global_ring(deeper, variant.lame, force_N=force, h_mm=H_MM, contact_mm=contact_mm, order=2,
                          cache_dir=cache)
    assert ring.compliance_mm_per_N == study["radial_compliance_mm_per_N"].value
    with pytest.raises(AssertionError, match="meshed again"):
        br.global_ring(params, variant.lame, force_N=force, h_mm=H_MM, contact_mm=1.1 * contact_mm, order=2,
                       cache_dir=cache)
    thicker = params.with_value("wave_generator.bearing_inner_ring_thickness_mm",
                                1.1 * params.wave_generator.bearing_inner_ring_thickness_mm)
    with pytest.raises(AssertionError, match="meshed again"):
        br.global_ring(thicker, variant.lame, force_N=force, h_mm=H_MM, contact_mm=contact_mm, order=2,
                       cache_dir=cache)
