"""The cup-type gear as a drive that goes together (geometry/drive_assembly.py), the circular spline and the wave
generator's bearing as built: no overlap where none belongs, contact where the design has it, the teeth engaged at
the major axis and clear at the minor one. A coarse drive (d1 = 48 mm, 60 teeth) keeps OCC's booleans cheap."""
from __future__ import annotations

import math
import warnings

import pytest

from strainwave.errors import InputError
from strainwave.params import ToothProfile, load_params

# A small drive of the default's proportions: w0 = m (the default 0.8 mm), an addendum of 0.6 m on the spline (a tip
# clearance at the minor axis 2 w0 - (1.0 + 0.6) m = 0.32 mm), backlash 0.03 mm a flank: a pair that clears
# everywhere (with 0.8 m and 0.02 mm the rigid teeth collide at +-12, 60, 66 deg: docs/decisions/064-drive48-assembly-as-drawn.md).
SMALL = {"flexspline_cup.pitch_diameter_mm": 48.0, "flexspline_cup.teeth": 60, "flexspline_cup.module_mm": 0.8,
         "flexspline_cup.length_mm": 48.0, "flexspline_cup.wall_thickness_mm": 0.8,
         "wave_generator.bearing_inner_ring_thickness_mm": 2.0, "wave_generator.ball_diameter_mm": 3.0,
         "wave_generator.outer_ring_thickness_mm": 0.8, "wave_generator.contact_semi_axes_mm": [2.0, 1.0],
         "wave_generator.bearing_width_mm": 8.0, "wave_generator.ball_count": 20, "output_shaft.outer_diameter_mm": 20.0,
         "output_shaft.inner_diameter_mm": 12.0, "output_shaft.length_mm": 40.0,
         "circular_spline.outer_diameter_mm": 60.0, "circular_spline.face_width_mm": 9.0,
         "circular_spline.addendum_coefficient": 0.6, "circular_spline.backlash_mm": 0.03}
CONTACT_MM = 1e-6      # two parts in contact: OCC's distance between their surfaces (its precision ~1e-7 mm)
RACE_CONTACT_MM = 1e-5  # a ball on its groove: the groove is OCC's sweep, approximated to ~1e-5 mm
OVERLAP = 1e-6         # no overlap: common volume below this share of the smaller part's volume


@pytest.fixture(scope="module")
def small():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return load_params().with_values(SMALL)


@pytest.fixture(scope="module")
def drive(small):
    from strainwave.geometry.drive_assembly import cup_gear_assembly

    return {item.part.name.value: item for item in cup_gear_assembly(small)}


def _common_mm3(a, b) -> float:
    from build123d import Shape
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Common

    op = BRepAlgoAPI_Common(a.wrapped, b.wrapped)
    op.Build()
    assert op.IsDone()
    return Shape.cast(op.Shape()).volume


def _distance_mm(a, b) -> float:
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape

    d = BRepExtrema_DistShapeShape(a.wrapped, b.wrapped)
    d.Perform()
    assert d.IsDone()
    return d.Value()


def _section(shape):
    """The plane section of a prism along z (the toothed band, the spline, a ring): its top face, moved to z = 0."""
    from build123d import Location

    top = max((f for f in shape.faces() if f.geom_type.name == "PLANE" and abs(f.normal_at().Z) > 0.999),
              key=lambda f: f.center().Z)
    return top.moved(Location((0.0, 0.0, -top.center().Z)))


def _area(shape) -> float:
    return sum(f.area for f in shape.faces()) if shape else 0.0


def _near(face, x_mm: tuple[float, float], y_mm: tuple[float, float]):
    """The part of a z = 0 face inside the rectangle x in x_mm, y in y_mm."""
    from build123d import Compound, Location, Rectangle

    box = Rectangle(x_mm[1] - x_mm[0], y_mm[1] - y_mm[0]).moved(Location((0.5 * sum(x_mm), 0.5 * sum(y_mm), 0.0)))
    cut = face.intersect(box)
    return Compound(list(cut)) if isinstance(cut, list) else cut


def _band(drive):
    """The cup's toothed band (the second of its two solids) and its z range."""
    band = drive["flexspline-cup"].shape.solids()[1]
    bb = band.bounding_box()
    return band, (bb.min.Z, bb.max.Z)


# parts the drive has touching, checked in 3D (cheap booleans); the toothed prisms are checked on their sections,
# the balls by their centres' distances to the races (a sphere clear of a solid touches it iff that is D_w/2)
NEIGHBOURS_3D = [("wg-bearing-ring", "wg-cam"), ("flexspline-cup", "output-shaft")]
CONTACTS = [("wg-bearing-ring", "wg-cam"), ("flexspline-cup", "output-shaft")]


def test_every_part_of_the_drive_is_placed(drive):
    assert set(drive) == {"flexspline-cup", "circular-spline", "wg-cam", "wg-bearing-ring", "wg-bearing-balls",
                          "wg-bearing-outer-ring", "output-shaft"}


@pytest.mark.parametrize("a,b", NEIGHBOURS_3D)
def test_no_overlap_where_none_belongs(drive, a, b):
    sa, sb = drive[a].shape, drive[b].shape
    assert _common_mm3(sa, sb) < OVERLAP * min(sa.volume, sb.volume), (a, b)


@pytest.mark.parametrize("name", ["circular-spline", "wg-bearing-outer-ring"])
def test_band_neighbours_do_not_overlap_it(drive, name):
    """The spline around the band's teeth and the outer ring in its bore lie within the band's z range, and
    their sections do not overlap the band's (the three are prisms along z: the section decides)."""
    band, (z0, z1) = _band(drive)
    other = drive[name].shape
    bb = other.bounding_box()
    assert z0 - 1e-9 <= bb.min.Z and bb.max.Z <= z1 + 1e-9
    a, b = _section(band), _section(other)
    assert _area(a.intersect(b)) < OVERLAP * min(a.area, b.area)


@pytest.mark.parametrize("a,b", CONTACTS)
def test_contact_where_the_design_has_it(drive, a, b):
    assert _distance_mm(drive[a].shape, drive[b].shape) < CONTACT_MM, (a, b)


def test_outer_ring_sits_in_the_cups_bore(drive):
    """Points all round the outer ring's outside lie on the band's bore curve (the same parallel curve of the cam)."""
    from OCP.BRep import BRep_Tool
    from OCP.GeomAPI import GeomAPI_ProjectPointOnCurve
    from OCP.gp import gp_Pnt

    band, _ = _band(drive)
    bore_edges = _section(band).inner_wires()[0].edges()
    assert len(bore_edges) == 1                                  # one closed curve
    bore = bore_edges[0]
    ring = _section(drive["wg-bearing-outer-ring"].shape).outer_wire()
    curve = BRep_Tool.Curve_s(bore.wrapped, 0.0, 1.0)
    gaps = [GeomAPI_ProjectPointOnCurve(gp_Pnt(p.X, p.Y, p.Z), curve).LowerDistance()
            for p in (ring.position_at(u) for u in [k / 97 for k in range(97)])]
    assert max(gaps) < CONTACT_MM


@pytest.mark.parametrize("race", ["wg-bearing-ring", "wg-bearing-outer-ring"])
def test_each_ball_touches_its_race_without_overlap(drive, race):
    """Every ball, not only the nearest: its centre lies D_w/2 from the race (the groove's bottom: the groove is
    wider than the ball, f > 0.5) and outside the ring."""
    from build123d import Vertex

    d_w = SMALL["wave_generator.ball_diameter_mm"]
    item = drive["wg-bearing-balls"]
    centres = [item.point_mm(c) for c in item.part.meta["centres_mm"]]
    assert len(centres) == SMALL["wave_generator.ball_count"]
    ring = drive[race].shape
    gaps = [_distance_mm(Vertex(*c), ring) for c in centres]
    assert max(abs(g - 0.5 * d_w) for g in gaps) < RACE_CONTACT_MM
    assert not any(ring.is_inside(c) for c in centres)


def test_a_misplaced_part_is_found(drive):
    """The overlap tests can fail: the spline moved 0.1 mm towards the major axis cuts into the teeth there, and
    the cam moved 0.05 mm sideways cuts into the inner ring."""
    from build123d import Location

    band, _ = _band(drive)
    a, b = _section(band), _section(drive["circular-spline"].shape).moved(Location((0.1, 0.0, 0.0)))
    assert _area(a.intersect(b)) > OVERLAP * b.area
    cam = drive["wg-cam"].shape.moved(Location((0.05, 0.0, 0.0)))
    assert _common_mm3(cam, drive["wg-bearing-ring"].shape) > OVERLAP * drive["wg-bearing-ring"].shape.volume


def test_teeth_engaged_at_the_major_axis_clear_at_the_minor(small, drive):
    """At the major axis (+x) the cup's tooth tips reach past the spline's by the working depth (the teeth
    interleave without overlap: tests above); at the minor axis (+y) the tips stand the design's clearance apart:
    2 w0 - (h_a,f + h_a,c) m, a closed form of the tooth data, not of the drawing."""
    from strainwave.geometry.involute import CUP_ADDENDUM_COEF

    m, w0 = SMALL["flexspline_cup.module_mm"], small.gear.radial_deformation_mm
    band, _ = _band(drive)
    cup, spline = _section(band), _section(drive["circular-spline"].shape)
    r_tip_cup = 0.5 * SMALL["flexspline_cup.pitch_diameter_mm"] + (CUP_ADDENDUM_COEF + 1.35) * m   # root at d1/2
    pitch = 2 * math.pi * r_tip_cup / SMALL["flexspline_cup.teeth"]
    x_far, across = (0.0, 100.0), (-1.5 * pitch, 1.5 * pitch)
    cup_major = _near(cup, x_far, across).bounding_box().max.X
    spline_major = _near(spline, x_far, across).bounding_box().min.X
    assert cup_major == pytest.approx(r_tip_cup + w0, abs=1e-6)
    assert cup_major - spline_major > 0.5 * m          # engaged: the tips pass each other radially
    near_minor = (-0.5 * pitch, 0.5 * pitch)
    gap_minor = _distance_mm(_near(cup, near_minor, x_far), _near(spline, near_minor, x_far))
    expected = 2 * w0 - (CUP_ADDENDUM_COEF + SMALL["circular_spline.addendum_coefficient"]) * m
    assert gap_minor == pytest.approx(expected, abs=1e-4)


def test_flank_gap_at_the_major_axis_is_the_backlash(drive):
    """The tooth on the major axis sits in its space with the design's backlash on each flank: the normal gap of
    involute flanks with a circumferential gap j at the pitch circle is j cos(alpha) (ISO 21771's j_n = j_t cos
    alpha), to within the gap's variation along the flank (the two parts' base circles differ)."""
    j = SMALL["circular_spline.backlash_mm"]
    band, _ = _band(drive)
    window = ((0.0, 100.0), (-1.0, 1.0))
    gap = _distance_mm(_near(_section(band), *window), _near(_section(drive["circular-spline"].shape), *window))
    assert gap == pytest.approx(j * math.cos(math.radians(20.0)), rel=0.25)


def test_bearing_volumes_match_closed_forms(drive):
    """Rings as parallel curves of the cam's ellipse: area P_in w + pi w^2 (Steiner) less the groove's circular
    segment swept along its centroid's curve (Pappus); balls pi D^3/6 each. 1e-5: OCC's volume of the swept groove
    (1.7e-6 off); a groove 1 % too deep moves the ring's volume by ~7e-4."""
    for name in ("wg-bearing-ring", "wg-bearing-outer-ring", "wg-bearing-balls", "wg-cam"):
        part = drive[name].part
        assert part.volume_mm3 == pytest.approx(part.meta["volume_closed_form_mm3"], rel=1e-5), name


def test_circular_spline_part_named_faces_and_step(small, tmp_path):
    from strainwave.geometry.export import write_step
    from strainwave.geometry.parts import build_part
    from strainwave.geometry.step_xcaf import read_step_face_names

    part = build_part("circular-spline", small)
    z_c = SMALL["flexspline_cup.teeth"] + small.gear.wave_number
    counts = {name: len(refs) for name, refs in part.named_faces.items()}
    assert counts == {"rim": 1, "side_bottom": 1, "side_top": 1, "tooth_flank": 2 * z_c, "tooth_tip": z_c,
                      "tooth_root": z_c, "root_fillet": 2 * z_c}
    assert len(part.solid.faces()) == sum(counts.values())            # every face named
    back = read_step_face_names(write_step(part, tmp_path / "cs.step"))
    assert sorted(name for name, _, _ in back) == sorted(n for n, c in counts.items() for _ in range(c))


def test_profile_dispatch_goes_through_the_vocabulary(small):
    from strainwave.geometry import tooth_profiles
    from strainwave.geometry.involute import circular_spline_tooth_spec, gear_edges

    spec = circular_spline_tooth_spec(small)
    assert set(tooth_profiles.DRAWERS) == set(ToothProfile)     # every profile of the vocabulary can be drawn
    assert len(tooth_profiles.edges(ToothProfile.INVOLUTE, spec)) == len(gear_edges(spec)) == spec.teeth


def test_teeth_that_collide_at_the_minor_axis_are_refused(small):
    from strainwave.geometry.drive_assembly import cup_gear_assembly

    with pytest.raises(InputError, match="circular_spline.addendum_coefficient"):
        cup_gear_assembly(small.with_value("circular_spline.addendum_coefficient", 1.2))


def test_balls_that_do_not_fit_are_refused(small):
    from strainwave.geometry.wg_bearing import bearing_layout

    with pytest.raises(InputError, match="wave_generator.ball_count"):
        bearing_layout(small.with_value("wave_generator.ball_count", 60))


@pytest.mark.heavy
def test_cli_exports_the_full_size_drive(strainwave_cmd, tmp_path):
    """`export-step --part assembly` on the default gear: the drive's seven parts (24 balls) in one STEP assembly,
    every ball on both races of the default's bearing (its layout from the keys)."""
    import subprocess

    from build123d import Vertex, import_step

    out = tmp_path / "drive.step"
    run = subprocess.run([*strainwave_cmd, "export-step", "--part", "assembly", "-o", str(out)],
                         capture_output=True, text=True, timeout=900)
    assert run.returncode == 0, run.stderr
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        params = load_params()
    back = import_step(out)
    text = out.read_text(errors="ignore")
    assert all(name in text for name in ("circular-spline", "wg-bearing-balls", "wg-bearing-outer-ring", "wg-cam"))
    # cup (wall and toothed band), spline, cam, inner ring, balls, outer ring, shaft
    assert len(back.solids()) == 7 + params.wave_generator.ball_count
    from strainwave.geometry.drive_assembly import cup_gear_assembly
    from strainwave.geometry.wg_bearing import bearing_layout

    drive = {item.part.name.value: item for item in cup_gear_assembly(params)}
    d_w = bearing_layout(params).ball_diameter_mm
    balls = drive["wg-bearing-balls"]
    for race in ("wg-bearing-ring", "wg-bearing-outer-ring"):
        gaps = [_distance_mm(Vertex(*balls.point_mm(c)), drive[race].shape) for c in balls.part.meta["centres_mm"]]
        assert max(abs(g - 0.5 * d_w) for g in gaps) < RACE_CONTACT_MM, race


def test_a_rim_inside_the_tooth_roots_is_refused(small):
    from strainwave.geometry.parts import build_part

    with pytest.raises(InputError, match="circular_spline.outer_diameter_mm"):
        build_part("circular-spline", small.with_value("circular_spline.outer_diameter_mm", 51.0))


# the default gear's tooth proportions (h_a,c = 1.0 as the cup's, backlash 0.01 mm) on the small drive
DEFAULT_PAIR = {"circular_spline.addendum_coefficient": 1.0, "circular_spline.backlash_mm": 0.01}


def _cad_overlaps(band, spline) -> list[tuple[float, float]]:
    """(angle deg, area mm^2) of each piece the drawn sections have in common."""
    common = band.intersect(spline)
    pieces = [f for c in (common if isinstance(common, list) else [common] if common else []) for f in c.faces()]
    return [(math.degrees(math.atan2(f.center().Y, f.center().X)), f.area) for f in pieces]


def test_drawn_teeth_collide_where_the_ring_kinematics_put_them(small, drive):
    """The drawing's teeth stand where the textbook inextensible ring puts them (tooth_interference: first-order
    w, v and section turn, its own involute polygons, no OCC): with the default's tooth proportions the drawn sections
    overlap in the teeth the model finds, by its total area within 15 % (the model drops w0^2/r_m terms: 10 % here),
    and nowhere else (slivers below the model's threshold aside, such as the tips touching at the minor axis, where
    this pair's clearance is 0). Teeth drawn radial (no section turn) fail it: 0.147 against 0.350 mm^2."""
    from strainwave.geometry.parts import build_part
    from strainwave.geometry.tooth_interference import overlap_threshold_mm2, tooth_overlaps

    params = small.with_values(DEFAULT_PAIR)
    band, _ = _band(drive)
    cad = [(phi, a) for phi, a in _cad_overlaps(_section(band), _section(build_part("circular-spline", params).solid))
           if a > overlap_threshold_mm2(params)]
    model = tooth_overlaps(params, quadrant=False)
    pitch_deg = 360.0 / SMALL["flexspline_cup.teeth"]
    zones = [r.phi_deg for r in model if r.area_mm2 > 0.0]
    assert cad and all(min(abs((a - z + 180.0) % 360.0 - 180.0) for z in zones) <= pitch_deg + 1e-9 for a, _ in cad)
    assert sum(a for _, a in cad) == pytest.approx(sum(r.area_mm2 for r in model), rel=0.15)
    def fold(deg: float) -> float:   # the pair is symmetric about both axes: the angle from the major axis, 0..90
        return min(deg % 180.0, 180.0 - deg % 180.0)
    worst_cad, worst_model = fold(max(cad, key=lambda p: p[1])[0]), fold(max(model, key=lambda r: r.area_mm2).phi_deg)
    assert abs(worst_cad - worst_model) <= pitch_deg + 1e-9


def test_the_tests_pair_clears_and_the_default_pair_is_said_to_collide(small):
    """The model agrees with the drawing on the tests' pair (clear: the overlap tests above), and the default gear's
    own pair (w0 = m, h_a = 1 on both) overlaps at 56-124 deg from the major axis: the assembly says so in a warning."""
    from strainwave.geometry.drive_assembly import _warn_tooth_overlap
    from strainwave.geometry.tooth_interference import ToothOverlapWarning, overlap_threshold_mm2, tooth_overlaps

    assert max(r.area_mm2 for r in tooth_overlaps(small)) < overlap_threshold_mm2(small)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ToothOverlapWarning)
        _warn_tooth_overlap(small)
        params = load_params()
        with pytest.raises(ToothOverlapWarning, match="56-88 deg from the major axis"):
            _warn_tooth_overlap(params)
    hits = [r.phi_deg for r in tooth_overlaps(params) if r.area_mm2 > overlap_threshold_mm2(params)]
    assert 50.0 < min(hits) and max(hits) < 90.0
