"""STEP with names that other tools read back: parts named and coloured, named faces as STEP face names.

build123d's ``export_step`` names products but writes every face as ``ADVANCED_FACE('')``. Here the OCC
XCAF document is built directly (each part a coloured, named shape label; an assembly its components),
written, and each face of ``Part.named_faces`` gets its name on its STEP face entity
(``ADVANCED_FACE('fixed', ...)``), which OCC's STEP reader returns (``read_step_face_names``). gmsh
4.15 reads the part names and colours, not face names. Units: mm.
"""
from __future__ import annotations

from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

__all__ = ["Placed", "PART_COLOURS_RGB", "named_refs", "write_named_step", "read_step_face_names",
           "import_step_named"]

# One colour per part so an assembly reads at a glance (sRGB 0..1; steel greys with a hue per role).
PART_COLOURS_RGB: dict[str, tuple[float, float, float]] = {
    "flexspline-cup": (0.70, 0.72, 0.78),
    "ewg-flexspline-ring": (0.70, 0.72, 0.78),
    "wg-bearing-ring": (0.85, 0.62, 0.30),
    "output-shaft": (0.45, 0.55, 0.70),
    "ewg": (0.55, 0.75, 0.50),
    "wg-cam": (0.55, 0.75, 0.50),     # a wave generator, like the EWG
    "circular-spline": (0.50, 0.50, 0.55),
    "wg-bearing-balls": (0.80, 0.80, 0.82),
    "wg-bearing-outer-ring": (0.85, 0.62, 0.30),   # a bearing ring, like the inner one
}


@dataclass(frozen=True)
class Placed:
    """A part and where it sits in the file: ``at`` (a build123d Location) moves ``part.solid``
    rigidly; None leaves it where it was built."""

    part: object                 # geometry.part.Part
    at: object | None = None     # build123d Location

    @property
    def shape(self):
        return self.part.solid if self.at is None else self.part.solid.moved(self.at)

    def point_mm(self, p: tuple[float, float, float]) -> tuple[float, float, float]:
        """A point of the part's own frame in the file's frame."""
        if self.at is None:
            return tuple(p)
        from build123d import Location
        q = (self.at * Location(tuple(p))).position
        return (q.X, q.Y, q.Z)


def named_refs(placed: list[Placed]) -> list[tuple[str, tuple[float, float, float], float]]:
    """(name, centre in the file's frame, area) of every named face of the placed parts. A face in two
    sets of one part gets both names joined by '+', in the order of ``part.named_faces``."""
    out: list[tuple[str, tuple[float, float, float], float]] = []
    for item in placed:
        merged: dict[tuple, list[str]] = {}
        for name, refs in item.part.named_faces.items():
            for ref in refs:
                key = (tuple(round(c, 9) for c in ref.center_mm), round(ref.area_mm2, 9))
                merged.setdefault(key, [])
                if name not in merged[key]:
                    merged[key].append(name)
        for (centre, area), names in merged.items():
            out.append(("+".join(names), item.point_mm(centre), area))
    return out


def _name(label, text: str) -> None:
    from OCP.TCollection import TCollection_ExtendedString
    from OCP.TDataStd import TDataStd_Name
    TDataStd_Name.Set_s(label, TCollection_ExtendedString(text))


def _colour(color_tool, label, rgb) -> None:
    from OCP.Quantity import Quantity_Color, Quantity_TypeOfColor
    from OCP.XCAFDoc import XCAFDoc_ColorType
    color_tool.SetColor(label, Quantity_Color(*rgb, Quantity_TypeOfColor.Quantity_TOC_sRGB),
                        XCAFDoc_ColorType.XCAFDoc_ColorSurf)


def _document():
    from OCP.TCollection import TCollection_ExtendedString
    from OCP.TDocStd import TDocStd_Document
    from OCP.XCAFApp import XCAFApp_Application
    from OCP.XCAFDoc import XCAFDoc_DocumentTool

    doc = TDocStd_Document(TCollection_ExtendedString("MDTV-XCAF"))
    app = XCAFApp_Application.GetApplication_s()
    app.NewDocument(TCollection_ExtendedString("MDTV-XCAF"), doc)
    app.InitDocument(doc)
    XCAFDoc_DocumentTool.SetLengthUnit_s(doc, 0.001)      # mm
    shapes = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
    shapes.SetAutoNaming_s(False)                          # only our names, no generated ones
    return doc, shapes, XCAFDoc_DocumentTool.ColorTool_s(doc.Main())


def _add_part(colours, label, part) -> None:
    _name(label, part.name.value)
    _colour(colours, label, PART_COLOURS_RGB.get(part.name.value, (0.7, 0.7, 0.7)))


def _faces_read_back(path: Path, wanted=None) -> list[tuple[int, str, tuple[float, float, float], float]]:
    """(entity number, name, centre, area) of every face of a STEP file as OCC's STEP reader transfers it.
    The number is the face's ``#N``: OCC's writer numbers entities #1, #2, ... in file order.

    ``wanted(centres (F, 3), areas (F,)) -> (F,) bool``: only those faces get their entity looked up, the
    others come back with number 0 and no name. The lookup is a search through the transfer's results,
    costly on the toothed cup's many faces (docs/decisions/015-cad-build-speed.md)."""
    import numpy as np

    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps
    from OCP.IFSelect import IFSelect_ReturnStatus
    from OCP.STEPControl import STEPControl_Reader
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer

    reader = STEPControl_Reader()
    with _quiet_occ():
        if reader.ReadFile(str(path)) != IFSelect_ReturnStatus.IFSelect_RetDone:
            raise RuntimeError(f"OCC could not read {path}")
        reader.TransferRoots()
    transfer, model = reader.WS().TransferReader(), reader.Model()
    shapes, centres, areas = [], [], []
    explorer = TopExp_Explorer(reader.OneShape(), TopAbs_FACE)
    while explorer.More():
        face = explorer.Current()
        explorer.Next()
        props = GProp_GProps()
        BRepGProp.SurfaceProperties_s(face, props)
        c = props.CentreOfMass()
        shapes.append(face)
        centres.append((c.X(), c.Y(), c.Z()))
        areas.append(props.Mass())
    look_up = (np.ones(len(shapes), bool) if wanted is None or not shapes
               else np.asarray(wanted(np.asarray(centres), np.asarray(areas)), bool))
    faces = []
    for face, centre, area, find in zip(shapes, centres, areas, look_up):
        # mode 1 finds a face as transferred; a face of an assembly component carries the component's
        # location on top, which only mode -1 (any location) resolves
        entity = (transfer.EntityFromShapeResult(face, 1) or transfer.EntityFromShapeResult(face, -1)) if find else None
        faces.append([entity, centre, area, _entity_name(entity)])
    # The entity's file number: model.Number() does not find the handles OCP returns, so each face
    # entity is tagged in memory and the model's entities are scanned for the tags.
    from OCP.TCollection import TCollection_HAsciiString
    for k, face in enumerate(faces):
        if face[0] is not None:
            face[0].SetName(TCollection_HAsciiString(f"strainwave-face-{k}"))
    number = {}
    for i in range(1, model.NbEntities() + 1):
        name = _entity_name(model.Value(i))
        if name.startswith("strainwave-face-"):
            number[int(name.rpartition("-")[2])] = i
    return [(number.get(k, 0), name, centre, area) for k, (_, centre, area, name) in enumerate(faces)]


def _entity_name(entity) -> str:
    """The name of a STEP representation item ('' for anything else, e.g. units whose Name is an enum)."""
    name = entity.Name() if entity is not None and hasattr(entity, "Name") else None
    return name.ToCString() if hasattr(name, "ToCString") else ""


def _face_matches(ref_centres, ref_areas, centres, areas):
    """(refs, faces) bool: same area, same centre (within the file's size). One array operation,
    not a Python loop over refs x faces, slow on the toothed cup (docs/decisions/015-cad-build-speed.md)."""
    import numpy as np

    scale = max(1.0, float(np.linalg.norm(centres, axis=1).max(initial=1.0)))
    near = np.linalg.norm(ref_centres[:, None, :] - centres[None, :, :], axis=2) <= 1e-5 * scale
    return near & (np.abs(areas[None, :] - ref_areas[:, None]) <= 1e-6 * np.maximum(1.0, ref_areas)[:, None])


def _name_faces_in_model(writer, placed: list[Placed]) -> bool:
    """Name each named face's ``ADVANCED_FACE`` in the writer's transferred model, before it is written.

    The writer's finder process binds every face it wrote under the face without its location (a face
    of the toothed cup's teeth, moved into place, is found only so). A face is therefore identified by
    its TShape alone, which is sound only while no two faces of the file share one: the located-copy
    case of ``_name_faces`` (the top of an extruded ring sharing the bottom's TShape) would give both the
    same entity. That case, a face the map does not hold, or a named face not found in the part, returns
    False with the model untouched, and the names are put on the written file as before (read back), a
    read-back that was a large part of the toothed cup's export; here the faces are matched in memory, by
    the same centre and area (docs/decisions/015-cad-build-speed.md)."""
    import numpy as np

    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps
    from OCP.STEPConstruct import STEPConstruct
    from OCP.StepShape import StepShape_AdvancedFace
    from OCP.TCollection import TCollection_HAsciiString
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopLoc import TopLoc_Location

    finder = writer.ChangeWriter().WS().TransferWriter().FinderProcess()
    seen: set[int] = set()
    wanted: list[tuple[object, str]] = []          # (face without location, name)
    for item in placed:
        faces, centres, areas = [], [], []
        explorer = TopExp_Explorer(item.part.solid.wrapped, TopAbs_FACE)
        while explorer.More():
            face = explorer.Current()
            explorer.Next()
            bare = face.Located(TopLoc_Location())
            if hash(bare) in seen:           # a shared TShape (or a face visited twice): not told apart
                return False
            seen.add(hash(bare))
            props = GProp_GProps()
            BRepGProp.SurfaceProperties_s(face, props)
            c = props.CentreOfMass()
            faces.append(bare)
            centres.append((c.X(), c.Y(), c.Z()))
            areas.append(props.Mass())
        refs = named_refs([Placed(item.part)])       # in the part's own frame, as its solid is written
        if not refs:
            continue
        hit = _face_matches(np.asarray([c for _, c, _ in refs], float).reshape(-1, 3),
                            np.asarray([a for _, _, a in refs], float),
                            np.asarray(centres, float).reshape(-1, 3), np.asarray(areas, float))
        for (name, _, _), row in zip(refs, hit):
            found = np.flatnonzero(row)
            if len(found) != 1:
                return False
            wanted.append((faces[found[0]], name))
    entities = []
    for face, name in wanted:
        entity = STEPConstruct.FindEntity_s(finder, face)
        if not isinstance(entity, StepShape_AdvancedFace) or _entity_name(entity):
            return False                     # not mapped, or (defensive) named already
        entities.append(entity)
    # two named faces on one entity: tag each entity, a tag met twice means the map merged them
    tags = []
    for k, entity in enumerate(entities):
        if _entity_name(entity):
            for done in tags:
                done.SetName(TCollection_HAsciiString(""))
            return False
        entity.SetName(TCollection_HAsciiString(f"strainwave-face-{k}"))
        tags.append(entity)
    for entity, (_, name) in zip(entities, wanted):
        entity.SetName(TCollection_HAsciiString(name))
    return True


def _name_faces(path: Path, placed: list[Placed]) -> None:
    """Write each named face's name into its ``ADVANCED_FACE`` entity of the file at ``path``.

    The names are put on the written file, found by reading it back, rather than through XCAF
    sub-shape labels or the writer's finder process: both resolve a face that OCC stores as a located
    copy of another (the top of an extruded ring shares the bottom's TShape) to the other face's
    entity, so the top face lost its name or the bottom got the top's. Matching the read-back faces by
    centre and area (as the mesher matches faces) cannot confuse the two."""
    import re

    import numpy as np

    refs = named_refs(placed)
    ref_centres = np.asarray([c for _, c, _ in refs], float).reshape(-1, 3)
    ref_areas = np.asarray([a for _, _, a in refs], float)

    def matches(centres, areas):
        return _face_matches(ref_centres, ref_areas, centres, areas)

    faces = list(_faces_read_back(path, wanted=lambda c, a: matches(c, a).any(axis=0)))
    hit = matches(np.asarray([c for _, _, c, _ in faces], float).reshape(-1, 3),
                  np.asarray([a for _, _, _, a in faces], float))
    numbers = np.asarray([number for number, _, _, _ in faces], np.int64)
    names: dict[int, str] = {}
    for (name, centre, _), row in zip(refs, hit):
        hits = numbers[row]
        if len(hits) != 1 or hits[0] <= 0:
            raise RuntimeError(f"{Path(path).name}: named face {name!r} at {centre} matches {len(hits)} faces")
        names[int(hits[0])] = name
    text = Path(path).read_text(encoding="ascii")

    def rename(match):
        number = int(match.group(1))
        return f"#{number} = ADVANCED_FACE('{names[number]}'," if number in names else match.group(0)

    named, count = re.subn(r"^#(\d+) = ADVANCED_FACE\('',", rename, text, flags=re.M)
    missing = set(names) - {int(m) for m in re.findall(r"^#(\d+) = ADVANCED_FACE\('(?:[^']+)',", named, flags=re.M)}
    if missing:
        raise RuntimeError(f"{Path(path).name}: entities {sorted(missing)} are not unnamed ADVANCED_FACEs")
    Path(path).write_text(named, encoding="ascii")


def _shares_face_shapes(solid) -> bool:
    """True when two faces of ``solid`` are located copies of one TShape (an extrusion's top and bottom)."""
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopLoc import TopLoc_Location

    seen: set[int] = set()
    explorer = TopExp_Explorer(solid.wrapped, TopAbs_FACE)
    while explorer.More():
        key = hash(explorer.Current().Located(TopLoc_Location()))
        explorer.Next()
        if key in seen:
            return True
        seen.add(key)
    return False


def _unshared(item: Placed) -> Placed:
    """``item`` with its solid copied (same geometry, one TShape per face) if faces share a TShape: then the
    writer's map tells them apart and names them in memory, without reading the written file back."""
    import dataclasses

    from OCP.BRepBuilderAPI import BRepBuilderAPI_Copy
    from build123d import Shape

    if not _shares_face_shapes(item.part.solid):
        return item
    copied = Shape.cast(BRepBuilderAPI_Copy(item.part.solid.wrapped, True, False).Shape())
    return Placed(dataclasses.replace(item.part, solid=copied), item.at)


def write_named_step(placed: list[Placed], path: Path, *, assembly: str | None = None) -> Path:
    """Write one part (``assembly=None``, one entry) or an assembly named ``assembly`` of placed parts
    as STEP AP214 in mm, with part names and colours and named faces. ``path`` is written as given
    (the caller makes it atomic)."""
    from OCP.TDF import TDF_Label
    from OCP.XCAFDoc import XCAFDoc_ShapeTool

    if assembly is None and len(placed) != 1:
        raise ValueError("a single-part STEP takes exactly one placed part")
    placed = [_unshared(item) for item in placed]
    doc, shapes, colours = _document()
    if assembly is None:
        _add_part(colours, shapes.AddShape(placed[0].shape.wrapped, False), placed[0].part)
    else:
        root = shapes.NewShape()
        _name(root, assembly)
        for item in placed:
            component = shapes.AddComponent(root, item.shape.wrapped, False)
            prototype = TDF_Label()
            if component.IsNull() or not XCAFDoc_ShapeTool.GetReferredShape_s(component, prototype):
                raise RuntimeError(f"{assembly}: could not add {item.part.name.value} as a component")
            _name(component, item.part.name.value)
            _add_part(colours, prototype, item.part)
        shapes.UpdateAssemblies()

    with _quiet_occ():
        named = _write(doc, path, lambda writer: _name_faces_in_model(writer, placed))
    if not named:
        _name_faces(Path(path), placed)
    return Path(path)


@contextmanager
def _quiet_occ():
    """OCC's writer prints transfer statistics through its default messenger: keep only failures
    while writing, and give the printers their levels back afterwards."""
    from OCP.Message import Message, Message_Gravity
    printers = list(Message.DefaultMessenger_s().Printers())
    levels = [p.GetTraceLevel() for p in printers]
    for p in printers:
        p.SetTraceLevel(Message_Gravity.Message_Fail)
    try:
        yield
    finally:
        for p, level in zip(printers, levels):
            p.SetTraceLevel(level)


def _write(doc, path, before_write=None) -> bool:
    """Transfer ``doc`` and write it to ``path``; ``before_write(writer) -> bool`` may edit the transferred
    model first (its answer is returned; True without it)."""
    from OCP.IFSelect import IFSelect_ReturnStatus
    from OCP.Interface import Interface_Static
    from OCP.STEPCAFControl import STEPCAFControl_Controller, STEPCAFControl_Writer
    from OCP.STEPControl import STEPControl_StepModelType
    from OCP.XSControl import XSControl_WorkSession

    STEPCAFControl_Controller.Init_s()
    Interface_Static.SetCVal_s("write.step.unit", "MM")
    Interface_Static.SetCVal_s("write.step.schema", "AP214IS")
    writer = STEPCAFControl_Writer(XSControl_WorkSession(), False)
    writer.SetNameMode(True)
    writer.SetColorMode(True)
    if not writer.Transfer(doc, STEPControl_StepModelType.STEPControl_AsIs):
        raise RuntimeError(f"STEP transfer of {Path(path).name} failed")
    done = True if before_write is None else before_write(writer)
    if writer.Write(str(path)) != IFSelect_ReturnStatus.IFSelect_RetDone:
        raise RuntimeError(f"STEP write of {Path(path).name} failed")
    return done


def read_step_face_names(path: Path | str) -> list[tuple[str, tuple[float, float, float], float]]:
    """(name, centre of mass in mm, area in mm^2) of every named face of a STEP file, read back with
    OCC's own STEP reader (the name of the ADVANCED_FACE entity each face was transferred from).
    Lets a test (or a user's script) check that a file carries the names other tools will see."""
    return [(name, centre, area) for _, name, centre, area in _faces_read_back(Path(path)) if name]


def _label_name(label) -> str:
    from OCP.TDataStd import TDataStd_Name
    attribute = TDataStd_Name()
    return attribute.Get().ToExtString() if label.FindAttribute(TDataStd_Name.GetID_s(), attribute) else ""


def _sub_face_names(shape_tool, label, out: dict, prefix: str = "") -> None:
    """name -> [TopoDS_Face] of the named sub-shape labels under ``label``; an assembly's components' faces are
    named 'PART/name' (its parts share face names: each has a 'bore')."""
    from build123d.importers import Sequence_TDF_Label
    from OCP.TDF import TDF_Label
    from OCP.TopAbs import TopAbs_FACE
    subs = Sequence_TDF_Label()
    shape_tool.GetSubShapes_s(label, subs)
    for i in range(1, subs.Length() + 1):
        shape, name = shape_tool.GetShape_s(subs.Value(i)), _label_name(subs.Value(i))
        if name and shape.ShapeType() == TopAbs_FACE:
            for part in name.split("+"):   # a face in two named sets carries both (named_refs)
                out.setdefault(prefix + part, []).append(shape)
    components = Sequence_TDF_Label()
    shape_tool.GetComponents_s(label, components)
    for i in range(1, components.Length() + 1):
        prototype = TDF_Label()
        if shape_tool.GetReferredShape_s(components.Value(i), prototype):
            _sub_face_names(shape_tool, prototype, out, f"{prefix}{_label_name(prototype)}/")


def import_step_named(path: Path | str):
    """``(shape, {name: [Face]})``: a STEP file as build123d shapes, with the named faces as build123d ``Face``s
    whose ``label`` is their name.

    build123d's ``import_step`` labels products and assembly components only (its faces come back unnamed), and
    gmsh 4.15 reads no face names either; OCC's XCAF reader returns the ADVANCED_FACE names this module writes as
    named sub-shape labels once ``read.stepcaf.subshapes.name`` is on, which is what this reads. The shape is
    build123d's own ``import_step`` of the same file (names, colours, placement as build123d gives them); a
    face of a part placed in an assembly is named 'PART/name' and returned in its part's own frame."""
    from build123d import Face, import_step
    from OCP.IFSelect import IFSelect_ReturnStatus
    from OCP.Interface import Interface_Static
    from OCP.STEPCAFControl import STEPCAFControl_Reader
    from OCP.TCollection import TCollection_ExtendedString
    from OCP.TDocStd import TDocStd_Document
    from OCP.XCAFDoc import XCAFDoc_DocumentTool
    from build123d.importers import Sequence_TDF_Label

    reader = STEPCAFControl_Reader()   # its constructor registers the static set next
    saved = Interface_Static.IVal_s("read.stepcaf.subshapes.name")
    Interface_Static.SetIVal_s("read.stepcaf.subshapes.name", 1)
    try:
        reader.SetNameMode(True)
        with _quiet_occ():
            if reader.ReadFile(str(path)) != IFSelect_ReturnStatus.IFSelect_RetDone:
                raise RuntimeError(f"OCC could not read {path}")
            doc = TDocStd_Document(TCollection_ExtendedString("XCAF"))
            reader.Transfer(doc)
    finally:
        Interface_Static.SetIVal_s("read.stepcaf.subshapes.name", saved)
    shape_tool = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
    free, found = Sequence_TDF_Label(), {}
    shape_tool.GetFreeShapes(free)
    for i in range(1, free.Length() + 1):
        _sub_face_names(shape_tool, free.Value(i), found)
    named = {}
    for name, faces in found.items():
        named[name] = [Face(f) for f in faces]
        for face in named[name]:
            face.label = name
    return import_step(str(path)), named
