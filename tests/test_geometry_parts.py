"""Geometry: volumes and key dimensions against closed forms, named faces where they belong, bad cracks refused."""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from strainwave.errors import InputError
from strainwave.geometry.involute import ToothSpec, polygon_area_mm2, tooth_polyline_mm
from strainwave.geometry.parts import build_part
from strainwave.params import load_params

# Volumes of solids bounded by planes and cylinders are integrated exactly by OCC (round-off only).
EXACT = 1e-9


@pytest.fixture(scope="module")
def params():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return load_params()


@pytest.fixture(scope="module")
def small_cup_params(params):
    # 40 teeth of module 4 on d1 = 160: same cup, 5x fewer teeth, so the test stays fast.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return params.with_values({"flexspline_cup.teeth": 40, "flexspline_cup.module_mm": 4.0})


def _centres(part, key):
    return np.array([f.center_mm for f in part.named_faces[key]])


# ---- output shaft ---------------------------------------------------------------------------

def test_shaft_volume_and_end_faces(params):
    part = build_part("output-shaft", params)
    sh = params.output_shaft
    closed = math.pi / 4 * (sh.outer_diameter_mm ** 2 - sh.inner_diameter_mm ** 2) * sh.length_mm
    assert part.volume_mm3 == pytest.approx(closed, rel=EXACT)
    assert _centres(part, "fixed")[0] == pytest.approx([0, 0, 0], abs=1e-9)
    assert _centres(part, "loaded")[0] == pytest.approx([0, 0, sh.length_mm], abs=1e-9)
    assert part.named_faces["outer"][0].area_mm2 == pytest.approx(math.pi * sh.outer_diameter_mm * sh.length_mm, rel=EXACT)
    assert part.named_faces["bore"][0].area_mm2 == pytest.approx(math.pi * sh.inner_diameter_mm * sh.length_mm, rel=EXACT)


@pytest.mark.parametrize("bore_mm", [45.0, 30.0, 0.0])
def test_bare_shaft_is_the_cad_shaft_without_build123d(params, bore_mm, tmp_path):
    """The FEA meshes ``build_bare``'s TopoDS_Solid: the same BREP file, faces and meta as ``build``'s."""
    from OCP.BRepTools import BRepTools

    from strainwave.geometry.output_shaft import build_bare

    p = params.with_value("output_shaft.inner_diameter_mm", bore_mm)
    cad, bare = build_part("output-shaft", p), build_bare(p)
    assert not hasattr(bare.solid, "wrapped")    # a bare OCC shape, not a build123d one
    BRepTools.Write_s(cad.solid.wrapped, str(tmp_path / "cad.brep"))
    BRepTools.Write_s(bare.solid, str(tmp_path / "bare.brep"))
    assert (tmp_path / "bare.brep").read_text() == (tmp_path / "cad.brep").read_text()
    assert bare.named_faces == cad.named_faces and ("bore" in bare.named_faces) == (bore_mm > 0)
    assert (bare.meta, bare.crack_front_mm, bare.crack_surface) == (cad.meta, cad.crack_front_mm, cad.crack_surface)


@pytest.mark.parametrize("arc_deg", [360.0, 90.0])
def test_shaft_slot_removes_its_own_volume(params, arc_deg):
    p = params.with_value("crack_geometry.shaft_arc_deg", arc_deg)
    a = 2.0
    intact = build_part("output-shaft", p).volume_mm3
    part = build_part("output-shaft", p, crack_depth_mm=a)
    r_o, w = p.output_shaft.outer_diameter_mm / 2, p.crack_geometry.slot_width_mm
    slot = arc_deg / 360 * math.pi * (r_o ** 2 - (r_o - a) ** 2) * w
    # the removed volume is a difference of two 4.5e5 mm3 numbers, so compare it with an absolute
    # tolerance of round-off size (1e-9 of the shaft volume)
    assert intact - part.volume_mm3 == pytest.approx(slot, abs=EXACT * intact)
    z_c = p.crack_geometry.shaft_axial_position_ratio * p.output_shaft.length_mm
    walls = _centres(part, "crack_face")
    assert len(walls) == 2 and sorted(walls[:, 2]) == pytest.approx([z_c - w / 2, z_c + w / 2], abs=1e-9)
    front = np.array(part.crack_front_mm)
    assert np.hypot(front[:, 0], front[:, 1]) == pytest.approx(np.full(len(front), r_o - a), abs=1e-9)
    assert len(part.named_faces["crack_front"]) == (1 if arc_deg == 360 else 3)  # floor (+ two arc ends)


# ---- bearing inner ring -----------------------------------------------------------------------

def test_bearing_ring_volume_contact_and_crack(params):
    intact = build_part("wg-bearing-ring", params)
    m = intact.meta
    assert intact.volume_mm3 == pytest.approx(math.pi * (m["race_radius_mm"] ** 2 - m["bore_radius_mm"] ** 2)
                                              * m["width_mm"], rel=EXACT)
    a_c, b_c = params.wave_generator.contact_semi_axes_mm
    contact = intact.named_faces["contact"]
    assert len(contact) == 1
    # the patch has the contact ellipse's area and sits on the race at +x, mid-width
    assert contact[0].area_mm2 == pytest.approx(math.pi * a_c * b_c, rel=1e-9)
    cx, cy, cz = contact[0].center_mm
    assert cx > 0.99 * m["race_radius_mm"] and abs(cy) < 1e-6 and cz == pytest.approx(m["width_mm"] / 2)

    a = 0.5
    cracked = build_part("wg-bearing-ring", params, crack_depth_mm=a)
    q = params.cracks.surface_crack_shape_factor
    c = cracked.meta["crack_half_length_mm"]
    assert 1 + 1.464 * (a / c) ** 1.65 == pytest.approx(q, rel=1e-12)
    half_ellipse = 0.5 * math.pi * a * c * params.crack_geometry.slot_width_mm
    # the slot's mouth is flat while the race is curved: the sliver y^2/(2R) over |y| < w/2 is ~1e-7 mm
    # deep, i.e. < 1e-5 of the slot volume; the rest is round-off on a 7e4 mm3 difference
    assert intact.volume_mm3 - cracked.volume_mm3 == pytest.approx(half_ellipse, rel=1e-4)
    front = np.array(cracked.crack_front_mm)
    assert front[:, 0].min() == pytest.approx(m["race_radius_mm"] - a, abs=1e-9)
    assert np.ptp(front[:, 2]) == pytest.approx(2 * c)
    assert len(cracked.named_faces["crack_face"]) == 2 and cracked.named_faces["crack_front"]


# ---- EWG ring and EWG ---------------------------------------------------------------------------

def test_ewg_ring_radii_follow_seed_003_eq_1(params):
    e = params.ewg_drive
    part = build_part("ewg-flexspline-ring", params, teeth=False)
    d_r, delta = e.module_mm * e.flexspline_teeth, 0.012 * e.module_mm * e.flexspline_teeth
    r_m = 0.5 * d_r + 1.35 * e.module_mm + 0.5 * delta
    assert part.meta["r_m_mm"] == pytest.approx(r_m, rel=1e-12)
    r_o, r_i = r_m + delta / 2, r_m - delta / 2
    assert part.volume_mm3 == pytest.approx(math.pi * (r_o ** 2 - r_i ** 2) * e.face_width_mm, rel=EXACT)


def test_ewg_ring_teeth_contact_and_section(params):
    e = params.ewg_drive
    part = build_part("ewg-flexspline-ring", params, teeth=True)
    assert len(part.named_faces["tooth_flank"]) == 2 * e.flexspline_teeth
    # B-spline flanks: OCC integrates the prism volume numerically (Gauss), good to ~1e-6
    assert part.volume_mm3 == pytest.approx(part.section.area * e.face_width_mm, rel=1e-5)
    r_o = part.meta["outer_radius_mm"]
    contact = _centres(part, "contact")
    assert len(contact) == 2
    assert sorted(contact[:, 1] / r_o) == pytest.approx([-1, 1], abs=1e-3)   # on the minor axis, +/- y
    strip = 2 * math.radians(2.0) * r_o * e.face_width_mm
    assert [f.area_mm2 for f in part.named_faces["contact"]] == pytest.approx([strip, strip], rel=1e-9)
    # the section carries the contact arcs as separate edges: outer circle in four arcs
    arcs = [ed for ed in part.section.outer_wire().edges()]
    assert len(arcs) == 4
    assert sorted(ed.length for ed in arcs)[:2] == pytest.approx([strip / e.face_width_mm] * 2, rel=1e-9)


@pytest.mark.parametrize("generator", ["rollers", "cam_ring"])
def test_ewg_imposes_w0(params, generator):
    from build123d import Edge

    p = params.with_value("ewg_drive.generator", generator)
    e = p.ewg_drive
    gen = build_part("ewg", p)
    ring = build_part("ewg-flexspline-ring", p)
    axis = Edge.make_line((0, 0, -1), (0, 0, e.face_width_mm + 1))
    r_contact = min(s.distance_to(axis) for s in gen.solid.solids())
    w0 = ring.meta["outer_radius_mm"] - r_contact
    # seed 003, eq 7: W0 = 0.5 m dZ; distances are exact geometry (round-off only)
    assert w0 == pytest.approx(0.5 * e.module_mm * e.tooth_difference, rel=1e-9)
    assert gen.meta["W0_mm"] == pytest.approx(w0, rel=1e-9)
    assert gen.volume_mm3 == pytest.approx(gen.meta["volume_closed_form_mm3"], rel=EXACT)
    assert len(gen.solid.solids()) == (2 if generator == "rollers" else 1)


def test_wave_generator_cam_is_the_rings_bore_plus_minus_w0(params):
    """The cam's outline reaches the bearing ring's bore radius + w0 on x and - w0 on y (the shape the ring and
    the cup are forced onto); its volume is the ellipse minus the hub bore times the ring's width."""
    from build123d import Edge

    cam = build_part("wg-cam", params)
    ring = build_part("wg-bearing-ring", params)
    w0, r_b, width = params.gear.radial_deformation_mm, ring.meta["bore_radius_mm"], ring.meta["width_mm"]
    z = 0.5 * width
    # distance from a short axial segment at 2 r_b on each axis: 2 r_b minus the cam's reach there
    for (x, y), reach in (((2 * r_b, 0.0), r_b + w0), ((0.0, 2 * r_b), r_b - w0)):
        probe = Edge.make_line((x, y, z), (x, y, z + 1e-3))
        assert 2 * r_b - cam.solid.distance_to(probe) == pytest.approx(reach, rel=1e-9)
    assert cam.meta["width_mm"] == pytest.approx(width, rel=1e-12)
    assert cam.volume_mm3 == pytest.approx(cam.meta["volume_closed_form_mm3"], rel=EXACT)
    assert {k: len(v) for k, v in cam.named_faces.items()} == {"contact": 1, "bore": 1}


# ---- involute and flexspline cup --------------------------------------------------------------

@pytest.mark.parametrize("internal", [False, True])
def test_involute_outline_area_matches_dense_polyline(internal):
    spec = ToothSpec(30, 2.0, internal=internal, root_fillet_coef=0.0)
    from strainwave.geometry.involute import gear_wire
    from build123d import Face
    area = Face(gear_wire(spec)).area
    # the CAD flank is a spline through 9 involute points: measured area error 1-2e-6 at Z = 30
    # (a profile deviation of ~10 nm); the dense polyline (1000 points per flank) is ~1e-8 accurate
    assert area == pytest.approx(polygon_area_mm2(tooth_polyline_mm(spec, 1000, 200)), rel=1e-5)


def test_cup_smooth_volume_and_faces(params):
    part = build_part("flexspline-cup", params, teeth=False)
    fc = params.flexspline_cup
    m = part.meta
    assert m["mid_radius_mm"] == pytest.approx((fc.pitch_diameter_mm - fc.wall_thickness_mm) / 2)
    # the wall alone (z from the diaphragm top to L) is a lower bound, wall + full bottom disc an upper one
    wall = math.pi * (m["outer_radius_mm"] ** 2 - m["bore_radius_mm"] ** 2)
    assert wall * (fc.length_mm - 4 * fc.wall_thickness_mm) < part.volume_mm3 < wall * fc.length_mm + \
        math.pi * m["outer_radius_mm"] ** 2 * 4 * fc.wall_thickness_mm
    loaded = part.named_faces["loaded"]
    z0, z1 = m["band_z_mm"]
    assert len(loaded) == 1 and loaded[0].area_mm2 == pytest.approx(2 * math.pi * m["outer_radius_mm"] * (z1 - z0))
    assert part.named_faces["fixed"][0].center_mm[2] == pytest.approx(0.0, abs=1e-9)
    assert part.named_faces["fixed"][0].area_mm2 == pytest.approx(
        math.pi * (m["hub_radius_mm"] ** 2 - m["hub_bore_radius_mm"] ** 2))


def test_cup_teeth_count_band_and_root_crack(small_cup_params):
    p = small_cup_params
    fc = p.flexspline_cup
    smooth = build_part("flexspline-cup", p, teeth=False)
    toothed = build_part("flexspline-cup", p, teeth=True)
    assert len(toothed.named_faces["tooth_flank"]) == 2 * fc.teeth
    flank_angles = np.arctan2(*_centres(toothed, "tooth_flank")[:, 1::-1].T)
    assert len(np.unique(np.round(flank_angles, 6))) == 2 * fc.teeth
    z0, z1 = toothed.meta["band_z_mm"]
    assert (_centres(toothed, "loaded")[:, 2] > z0).all()
    # the teeth stand on the smooth wall: toothed minus smooth = teeth only, between 0 and the full
    # addendum annulus
    r_o, r_a = toothed.meta["outer_radius_mm"], toothed.meta["tip_radius_mm"]
    extra = toothed.volume_mm3 - smooth.volume_mm3
    assert 0.3 * math.pi * (r_a ** 2 - r_o ** 2) * (z1 - z0) < extra < math.pi * (r_a ** 2 - r_o ** 2) * (z1 - z0)

    a = 0.5
    cracked = build_part("flexspline-cup", p, crack_depth_mm=a)
    beta = math.radians(p.cracks.flexspline_crack_angle_deg)
    c, w = cracked.meta["crack_half_length_mm"], p.crack_geometry.slot_width_mm
    length = cracked.meta["crack_length_along_plane_mm"]
    # on a flat root the plane length would be a / sin(beta); the curved root (r = 80 mm) adds O(a / r)
    assert length == pytest.approx(a / math.sin(beta), rel=a / r_o)
    # slot volume w * 2c * L; the curvature of the root arc (r = 80 mm) changes the mouth by O(w / r) ~ 3e-4
    assert toothed.volume_mm3 - cracked.volume_mm3 == pytest.approx(w * 2 * c * length, rel=1e-3)
    front = np.array(cracked.crack_front_mm)
    assert np.hypot(front[:, 0], front[:, 1]) == pytest.approx(np.full(len(front), r_o - a), abs=1e-9)
    theta = (p.crack_geometry.flexspline_tooth_index + 0.5) * 2 * math.pi / fc.teeth
    root = np.array(cracked.meta["crack_root_point_mm"])
    assert math.atan2(root[1], root[0]) == pytest.approx(theta, abs=1e-12)
    for key in ("crack_face", "crack_front"):
        centres = _centres(cracked, key)
        assert len(centres) >= 2
        assert np.linalg.norm(centres - root, axis=1).max() < 2 * c


# ---- impossible cracks ------------------------------------------------------------------------

@settings(max_examples=15, deadline=None)
@given(excess=st.floats(min_value=1.0, max_value=3.0))
def test_crack_deeper_than_wall_refused(params, excess):
    for name, wall in (("output-shaft", params.output_shaft.wall_mm),
                       ("wg-bearing-ring", params.wave_generator.bearing_inner_ring_thickness_mm)):
        with pytest.raises(InputError) as err:
            build_part(name, params, crack_depth_mm=wall * excess)
        assert err.value.key == "crack_depth_mm"


def test_other_impossible_cracks_refused(params):
    with pytest.raises(InputError) as err:     # slot width 0.02 > a/5 for a = 0.05
        build_part("output-shaft", params, crack_depth_mm=0.05)
    assert err.value.key == "crack_geometry.slot_width_mm"
    with pytest.raises(InputError) as err:     # Q = 1 means an infinitely long surface crack
        build_part("wg-bearing-ring", params.with_value("cracks.surface_crack_shape_factor", 1.0), crack_depth_mm=0.5)
    assert err.value.key == "cracks.surface_crack_shape_factor"
    with pytest.raises(InputError) as err:     # root crack outside the toothed band
        build_part("flexspline-cup", params.with_value("crack_geometry.flexspline_axial_position_ratio", 0.3),
                   crack_depth_mm=0.5, teeth=False)
    assert err.value.key == "crack_geometry.flexspline_axial_position_ratio"
    with pytest.raises(InputError) as err:     # the ring has no seeded crack
        build_part("ewg-flexspline-ring", params, crack_depth_mm=0.1)
    assert err.value.key == "crack_depth_mm"
    with pytest.raises(InputError):            # crack angle outside (0, 90) deg: refused by the schema
        params.with_value("cracks.flexspline_crack_angle_deg", 90.0)
