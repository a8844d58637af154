"""The cheaper STEP export builds and names the same part (docs/decisions/040-step-export-speed.md).

The toothed cup is sewn from its revolved body, its toothed band and the tooth ends instead of fused by a
boolean, and the face index takes the names the writer wrote and gmsh's import of a BREP of the written
shapes instead of reading the STEP file back twice. Each is pinned here against the construction it
replaced, on a cup of 40 teeth (5x fewer than the default, same cup otherwise).
"""
from __future__ import annotations

import warnings

import numpy as np
import pytest

from strainwave.geometry import flexspline_cup
from strainwave.geometry.faces import face_infos
from strainwave.params import load_params

EXACT = 1e-9       # relative volume: the same faces bound both solids, OCC's integration differs by round-off


@pytest.fixture(scope="module")
def small_cup_params():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return load_params().with_values({"flexspline_cup.teeth": 40, "flexspline_cup.module_mm": 4.0})


def _same_faces(a: list[tuple], b: list[tuple]) -> bool:
    """``a`` and ``b`` (tag, centre, area) hold the same faces in any order: one to one, the same tag, centre
    within 1e-7 mm and area within 1e-9 relative."""
    from scipy.spatial import cKDTree

    if len(a) != len(b):
        return False
    dist, nearest = cKDTree(np.array([c for _, c, _ in b])).query(np.array([c for _, c, _ in a]))
    return (len(set(nearest)) == len(b) and bool(np.all(dist < 1e-7))
            and all(ta == b[k][0] and abs(aa - b[k][2]) <= 1e-9 * aa for (ta, _, aa), k in zip(a, nearest)))


def _faces(solid) -> list[tuple]:
    """Every face of ``solid`` as (kind, centre, area)."""
    return [(fi.kind, fi.center_mm, fi.area_mm2) for fi in face_infos(solid)]


@pytest.mark.parametrize("variant", [{}, {"flexspline_cup.shape": "bell"}, {"flexspline_cup.cup": False}])
def test_sewn_toothed_cup_is_the_fused_one(small_cup_params, variant):
    fc = small_cup_params.with_values(variant).flexspline_cup
    spec = flexspline_cup.cup_tooth_spec(small_cup_params.with_values(variant))
    sewn = flexspline_cup.toothed_solid(fc, spec, sew=True)
    fused = flexspline_cup.toothed_solid(fc, spec, sew=False)
    assert sewn.is_valid
    assert sewn.volume == pytest.approx(fused.volume, rel=EXACT)
    assert np.allclose(tuple(sewn.bounding_box().min) + tuple(sewn.bounding_box().max),
                       tuple(fused.bounding_box().min) + tuple(fused.bounding_box().max), rtol=0, atol=1e-9)
    assert len(sewn.faces()) == len(fused.faces())
    reference = _faces(fused)
    assert _same_faces(_faces(sewn), reference)
    # the comparison sees one face's area off by 1e-8, or one face missing (another one twice instead)
    kind, centre, area = reference[0]
    assert not _same_faces(_faces(sewn), [(kind, centre, area * (1 + 1e-8)), *reference[1:]])
    assert not _same_faces(_faces(sewn), [reference[1], *reference[1:]])


def test_cup_part_names_the_same_faces_as_the_fused_cup(small_cup_params, monkeypatch):
    """``build`` on the sewn solid gives every named set the faces it gave on the fused one."""
    sewn = flexspline_cup.build(small_cup_params, teeth=True)
    original = flexspline_cup.toothed_solid
    monkeypatch.setattr(flexspline_cup, "toothed_solid", lambda fc, spec, sew=True: original(fc, spec, sew=False))
    fused = flexspline_cup.build(small_cup_params, teeth=True)
    assert sewn.named_faces.keys() == fused.named_faces.keys()
    for name in sewn.named_faces:
        as_tuples = [[(name, ref.center_mm, ref.area_mm2) for ref in part.named_faces[name]] for part in (sewn, fused)]
        assert _same_faces(*as_tuples), name


def test_sew_solid_refuses_an_open_shell(small_cup_params):
    """A missing face (one tooth end) leaves free edges: ``sew_solid`` refuses, it never returns an open
    shell as the part."""
    from build123d import Face, Location

    from strainwave.geometry.involute import gear_edges, tooth_end_faces
    from strainwave.geometry.occ import sew_solid

    fc = small_cup_params.flexspline_cup
    spec = flexspline_cup.cup_tooth_spec(small_cup_params)
    solid = flexspline_cup.toothed_solid(fc, spec)
    ends = tooth_end_faces(gear_edges(spec), spec.root_radius_mm)
    z_b = fc.length_mm - flexspline_cup.BAND_RATIO * fc.pitch_diameter_mm
    end_centres = {tuple(np.round(tuple(f.moved(Location((0, 0, z_b))).center()), 6)) for f in ends}
    kept = [f for f in solid.faces() if tuple(np.round(tuple(f.center()), 6)) not in end_centres]
    assert len(kept) == len(solid.faces()) - spec.teeth
    closed = kept + [Face(f.wrapped.Moved(Location((0, 0, z_b)).wrapped)) for f in ends]
    assert sew_solid(closed, len(closed)) is not None
    assert sew_solid(closed[:-1], len(closed) - 1) is None


@pytest.mark.parametrize("part", ["flexspline-cup", "ewg-flexspline-ring", "assembly"])
def test_face_index_from_the_written_shapes_is_the_step_files(small_cup_params, tmp_path, part):
    """The sidecar made from the writer's names and gmsh's BREP import of the written shapes is the one made
    from OCC's read-back of the STEP file and gmsh's import of it: same surface tags, same names."""
    from strainwave.geometry.export import export_part
    from strainwave.geometry.face_names import face_index
    import json

    written = export_part(part, small_cup_params, tmp_path / f"{part}.step", teeth=part == "flexspline-cup")
    steps = [p for p in written if p.suffix == ".step"]
    for step in steps:
        fast = json.loads(step.with_name(f"{step.stem}.faces.json").read_text())
        slow = face_index(step)
        assert fast["surfaces"] == slow["surfaces"] and fast["named"] == slow["named"] > 0
        assert {k: f["name"] for k, f in fast["faces"].items()} == {k: f["name"] for k, f in slow["faces"].items()}
        for key, face in fast["faces"].items():
            assert np.allclose(face["center_mm"], slow["faces"][key]["center_mm"], rtol=0, atol=1e-6)
            assert face["area_mm2"] == pytest.approx(slow["faces"][key]["area_mm2"], rel=1e-9)
