"""STEP face names in gmsh (issue 40): gmsh reads none from STEP, so the export writes NAME.faces.json; applied
in gmsh it names every surface as OCC's reader names it, and a changed file is refused, never mislabelled."""
from __future__ import annotations

import json

import numpy as np
import pytest

from strainwave.geometry.export import export_part
from strainwave.geometry.face_names import apply_face_names, load_step_with_names, sidecar_path
from strainwave.geometry.step_xcaf import read_step_face_names


@pytest.fixture(scope="module")
def shaft_step(params, tmp_path_factory):
    out = tmp_path_factory.mktemp("step") / "shaft.step"
    written = export_part("output-shaft", params, out)
    assert sidecar_path(out) in written
    return out


def test_gmsh_physical_groups_carry_the_step_face_names(shaft_step):
    import gmsh

    gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        groups = load_step_with_names(shaft_step)
        assert set(groups) == {name for name, _, _ in read_step_face_names(shaft_step)}
        # the group 'fixed' is the end face z = 0 and 'loaded' the end z = L, as the part defines them
        for name, z in (("fixed", 0.0), ("loaded", 200.0)):
            (tag,) = groups[name]
            assert gmsh.model.occ.getCenterOfMass(2, tag)[2] == pytest.approx(z, abs=1e-6)
            phys = [t for d, t in gmsh.model.getPhysicalGroups(2) if gmsh.model.getPhysicalName(d, t) == name]
            assert list(gmsh.model.getEntitiesForPhysicalGroup(2, phys[0])) == [tag]
            assert gmsh.model.getEntityName(2, tag) == name   # gmsh's own lookup of an entity's name (issue 52)
    finally:
        gmsh.finalize()


def test_a_sidecar_that_no_longer_matches_is_refused(shaft_step, tmp_path):
    import gmsh

    record = json.loads(sidecar_path(shaft_step).read_text())
    key = next(k for k, f in record["faces"].items() if f["name"] == "fixed")
    record["faces"][key]["center_mm"] = list(np.asarray(record["faces"][key]["center_mm"]) + [0.0, 0.0, 5.0])
    moved = tmp_path / "moved.faces.json"
    moved.write_text(json.dumps(record))
    gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.occ.importShapes(str(shaft_step))
        gmsh.model.occ.synchronize()
        with pytest.raises(ValueError, match="no longer matches its face 'fixed'"):
            apply_face_names(gmsh, moved)
    finally:
        gmsh.finalize()


def test_build123d_reimport_gives_every_named_face_its_name(shaft_step, params):
    """Issue 52: the STEP file read back into build123d: the part's label, and each named face a build123d Face
    labelled with its name, of the area and place the part gave it."""
    from strainwave.geometry.parts import build_part
    from build123d import CenterOf

    from strainwave.geometry.step_xcaf import import_step_named

    shape, named = import_step_named(shaft_step)
    part = build_part("output-shaft", params)
    assert shape.label == "output-shaft" and shape.volume == pytest.approx(part.volume_mm3, rel=1e-9)
    assert set(named) == set(part.named_faces)
    for name, refs in part.named_faces.items():
        faces = named[name]
        assert [f.label for f in faces] == [name] * len(refs)
        assert sorted(f.area for f in faces) == pytest.approx(sorted(r.area_mm2 for r in refs), rel=1e-9)
        centres = sorted(tuple(f.center(CenterOf.MASS)) for f in faces)
        assert np.allclose(centres, sorted(r.center_mm for r in refs), atol=1e-6)
