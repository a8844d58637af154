"""STEP / BREP writers (atomic) and ``export_part`` behind ``strainwave export-step``.

A part is written as one STEP product named after the part (unit mm, coloured), its named faces
(fixed, loaded, bore, contact, crack_face, crack_front, ...) as STEP face names (``step_xcaf``).
``assembly`` writes two STEP assemblies: the cup-type gear as a drive (``drive_assembly``: the cup on the wave
generator's cam and bearing, in mesh with the circular spline, the output shaft) to the given path and the EWG
drive (flexspline ring and EWG) next to it as ``<stem>-ewg-drive.step``.
"""
from __future__ import annotations

from pathlib import Path

from strainwave.io_atomic import atomic_path

from strainwave.geometry.drive_assembly import cup_gear_assembly
from strainwave.geometry.parts import build_part, part_name
from strainwave.geometry.part import Part, PartName
from strainwave.geometry.face_names import write_face_index
from strainwave.geometry.step_xcaf import Placed, named_refs, write_named_step

ASSEMBLY = "assembly"
CUP_GEAR = "cup-type-gear"     # STEP assembly names of the two drives ``assembly`` writes
EWG_DRIVE = "ewg-drive"


def write_step(part_or_shape, path: Path | str) -> Path:
    """Write a Part (named, coloured, with its named faces as STEP face names) or a bare build123d
    shape/assembly Compound as STEP in mm, atomically."""
    path = Path(path)
    if isinstance(part_or_shape, Part):
        with atomic_path(path) as tmp:
            write_named_step([Placed(part_or_shape)], tmp)
        return path
    from build123d import Unit, export_step

    with atomic_path(path) as tmp:
        if not export_step(part_or_shape, str(tmp), unit=Unit.MM):
            raise RuntimeError(f"STEP export of {path.name} failed")
    return path


def write_assembly_step(name: str, placed: list[Placed], path: Path | str) -> Path:
    """Write placed parts as one STEP assembly ``name`` (parts named and coloured, faces named), atomically."""
    path = Path(path)
    with atomic_path(path) as tmp:
        write_named_step(placed, tmp, assembly=name)
    return path


def write_brep(part_or_shape, path: Path | str) -> Path:
    """Write the part's solid as an OCC BREP file (exact geometry, no translation), atomically."""
    from build123d import export_brep

    shape = part_or_shape.solid if isinstance(part_or_shape, Part) else part_or_shape
    path = Path(path)
    with atomic_path(path) as tmp:
        if not export_brep(shape, str(tmp)):
            raise RuntimeError(f"BREP export of {path.name} failed")
    return path


def ewg_drive_assembly(params, *, teeth: bool = True) -> list[Placed]:
    """The EWG flexspline ring and its external wave generator, in the ring's frame (no crack)."""
    ring = build_part(PartName.EWG_FLEXSPLINE_RING, params, teeth=teeth)
    gen = build_part(PartName.EWG, params)
    return [Placed(ring), Placed(gen)]


def export_part(name: str, params, out_path: Path, *, crack_depth_mm: float | None = None, teeth: bool = True,
                png: Path | None = None) -> list[Path]:
    """Build ``name`` (a part name or ``assembly``), write STEP with its face index ``NAME.faces.json`` (the
    face names gmsh cannot read from STEP, see ``face_names``) and a PNG preview; return the written paths.

    ``assembly`` writes the cup-type gear to ``out_path`` and the EWG drive to ``<stem>-ewg-drive.step``;
    its preview draws both, every part in its colour."""
    out_path = Path(out_path)
    written: list[Path] = []
    if name == ASSEMBLY:
        drives = {CUP_GEAR: cup_gear_assembly(params, crack_depth_mm=crack_depth_mm, teeth=teeth),
                  EWG_DRIVE: ewg_drive_assembly(params, teeth=teeth)}
        for drive, path in ((CUP_GEAR, out_path), (EWG_DRIVE, out_path.with_name(out_path.stem + "-ewg-drive.step"))):
            step = write_assembly_step(drive, drives[drive], path)
            # gmsh reads no STEP face names: the sidecar gives them, from the names just written
            written += [step, write_face_index(step, named_refs(drives[drive]), [p.shape for p in drives[drive]])]
        if png is not None:
            from strainwave.geometry.preview import render_assembly_preview
            written.append(render_assembly_preview(drives, Path(png)))
        return written
    part = build_part(part_name(name), params, crack_depth_mm=crack_depth_mm, teeth=teeth)
    step = write_step(part, out_path)
    written += [step, write_face_index(step, named_refs([Placed(part)]), [part.solid])]
    if png is not None:
        from strainwave.geometry.preview import render_preview
        written.append(render_preview(part, Path(png)))
    return written
