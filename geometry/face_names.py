"""The face names of a STEP file as gmsh sees them: a sidecar ``NAME.faces.json`` of gmsh surface tag -> name.

The STEP file carries its face names on its ADVANCED_FACE entities (``step_xcaf``), which OCC's reader (and
so FreeCAD) returns; gmsh 4.15 imports the part names but leaves every face name empty. So, beside each STEP
file, the export writes the mapping gmsh needs: gmsh itself imports the file, every surface is matched to
the named face of the same centre of mass and area (OCC's reader of the same file), and the surface tags are
recorded with their names. ``apply_face_names`` turns the sidecar into gmsh physical groups; a surface whose
centre or area no longer matches (the file changed) is refused, never silently mislabelled.
"""
from __future__ import annotations

import json
import threading
from pathlib import Path

import numpy as np

__all__ = ["sidecar_path", "face_index", "write_face_index", "apply_face_names", "load_step_with_names"]

FORMAT = "strainwave STEP face index 1"
INDEXING = ("gmsh surface tag (dim 2) after gmsh.model.occ.importShapes(STEP) and synchronize, in gmsh "
            "4.x's import order")
REL_TOL = 1e-6      # centre distance / model size and relative area within which two faces are the same


def sidecar_path(step: Path) -> Path:
    """Where the face index of ``step`` (NAME.step) goes: NAME.faces.json."""
    step = Path(step)
    return step.with_name(f"{step.stem}.faces.json")


def _surfaces(gmsh) -> list[tuple[int, np.ndarray, float]]:
    out = []
    for _, tag in gmsh.model.getEntities(2):
        out.append((tag, np.asarray(gmsh.model.occ.getCenterOfMass(2, tag)), float(gmsh.model.occ.getMass(2, tag))))
    return out


def _gmsh_open():
    """gmsh, initialized for this call unless the caller holds a session; returns (gmsh, started)."""
    import gmsh

    from strainwave.fea.session import keep_sigpipe_ignored

    started = not gmsh.isInitialized()
    if started:
        gmsh.initialize(readConfigFiles=False, interruptible=False)
        gmsh.option.setNumber("General.Terminal", 0)
        if threading.current_thread() is threading.main_thread():
            keep_sigpipe_ignored()
    return gmsh, started


def _import_surfaces(step: Path, shapes) -> list[tuple[int, np.ndarray, float]]:
    """gmsh's surfaces (tag, centre, area) after it imports ``step``; with ``shapes``, the very shapes the
    STEP file holds, in its order, imported as a BREP file instead: gmsh binds the same faces in the same
    order (OCC's STEP writer and reader keep each shell's face order) without translating the STEP file."""
    import tempfile

    gmsh, started = _gmsh_open()
    try:
        gmsh.model.add(f"face-index-{Path(step).stem}")
        if shapes is None:
            gmsh.model.occ.importShapes(str(step))
        else:
            from build123d import Compound

            from strainwave.geometry.export import write_brep
            with tempfile.TemporaryDirectory() as tmp:
                brep = write_brep(shapes[0] if len(shapes) == 1 else Compound(list(shapes)), Path(tmp) / "shapes.brep")
                gmsh.model.occ.importShapes(str(brep))
        gmsh.model.occ.synchronize()
        surfaces = _surfaces(gmsh)
        gmsh.model.remove()
    finally:
        if started:
            gmsh.finalize()
    return surfaces


def face_index(step: Path, named: list[tuple[str, tuple[float, float, float], float]] | None = None,
               shapes=None) -> dict:
    """The sidecar record of ``step``: every gmsh surface that carries a STEP face name, with its centre and
    area (so a reader can check the file still matches), and the number of unnamed surfaces.

    ``named``: the (name, centre, area) the writer put on the file (``step_xcaf.named_refs`` of what it
    wrote); None reads them back from the file with OCC's reader, a second translation of the whole file.
    ``shapes``: the shapes the file holds, in its order (see ``_import_surfaces``); None imports the file."""
    from scipy.spatial import cKDTree

    from strainwave.geometry.step_xcaf import read_step_face_names

    if named is None:
        named = read_step_face_names(step)
    surfaces = _import_surfaces(Path(step), shapes)
    centres = np.array([c for _, c, _ in surfaces]) if surfaces else np.zeros((0, 3))
    size = float(np.ptp(centres, axis=0).max()) if len(centres) else 1.0
    tree = cKDTree(centres) if len(centres) else None
    faces = {}
    for name, centre, area in named:
        if tree is None:
            break
        for k in tree.query_ball_point(centre, r=REL_TOL * size + 1e-9):
            tag, _, mass = surfaces[k]
            if abs(mass - area) <= REL_TOL * max(area, 1e-12) + 1e-12:
                faces[tag] = {"name": name, "center_mm": [float(x) for x in centre], "area_mm2": float(area)}
    return {"format": FORMAT, "step": Path(step).name, "indexing": INDEXING, "surfaces": len(surfaces),
            "named": len(faces), "unnamed": len(surfaces) - len(faces),
            "faces": {str(tag): faces[tag] for tag in sorted(faces)}}


def write_face_index(step: Path, named: list[tuple[str, tuple[float, float, float], float]] | None = None,
                     shapes=None) -> Path:
    """Write ``step``'s face index beside it (atomically); returns the sidecar's path. ``named``, ``shapes``:
    see ``face_index``."""
    from strainwave.io_atomic import atomic_write_text

    return atomic_write_text(sidecar_path(step), json.dumps(face_index(step, named, shapes), indent=1) + "\n")


def apply_face_names(gmsh, sidecar: Path) -> dict[str, list[int]]:
    """Physical surface groups named as in ``sidecar``, on the gmsh model that imported its STEP file; returns
    name -> surface tags. Each surface's centre and area are checked against the record first."""
    record = json.loads(Path(sidecar).read_text(encoding="utf-8"))
    if record.get("format") != FORMAT:
        raise ValueError(f"{sidecar}: not a strainwave face index ({record.get('format')!r})")
    present = {tag: (c, m) for tag, c, m in _surfaces(gmsh)}
    size = float(np.ptp(np.array([c for c, _ in present.values()]), axis=0).max()) if present else 1.0
    groups: dict[str, list[int]] = {}
    for key, face in record["faces"].items():
        tag = int(key)
        if tag not in present:
            raise ValueError(f"{sidecar}: surface {tag} ({face['name']}) is not in the gmsh model")
        centre, mass = present[tag]
        if np.linalg.norm(centre - np.asarray(face["center_mm"])) > REL_TOL * size + 1e-9 or \
                abs(mass - face["area_mm2"]) > REL_TOL * max(face["area_mm2"], 1e-12) + 1e-12:
            raise ValueError(f"{sidecar}: surface {tag} no longer matches its face {face['name']!r} "
                             "(centre or area moved): the STEP file changed since the index was written")
        gmsh.model.setEntityName(2, tag, face["name"])   # gmsh.model.getEntityName reads it, as for its own labels
        for name in face["name"].split("+"):     # a face in two named sets carries both (step_xcaf)
            groups.setdefault(name, []).append(tag)
    for name, tags in groups.items():
        gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, tags), name)
    return groups


def load_step_with_names(step: Path, sidecar: Path | None = None) -> dict[str, list[int]]:
    """Import ``step`` into the current gmsh model (gmsh must be initialized) and name its faces as physical
    groups from the sidecar (default: NAME.faces.json beside it); returns name -> surface tags."""
    import gmsh

    gmsh.model.occ.importShapes(str(step))
    gmsh.model.occ.synchronize()
    return apply_face_names(gmsh, sidecar or sidecar_path(step))
