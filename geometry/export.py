"""STEP / BREP writers (atomic) and ``export_part`` behind ``strainwave export-step``.

A part is written as one STEP product named after the part (unit mm). ``assembly`` writes two STEP
assemblies: the cup-type gear (flexspline cup, bearing inner ring, output shaft) to the given path
and the EWG drive (flexspline ring and EWG) next to it as ``<stem>-ewg-drive.step``.
"""
from __future__ import annotations

from pathlib import Path

from strainwave.io_atomic import atomic_path

from .parts import build_part, part_name
from .part import Part, PartName

ASSEMBLY = "assembly"


def _labelled(shape, label: str):
    shape.label = label
    return shape


def write_step(part_or_shape, path: Path | str) -> Path:
    """Write a Part (or a build123d shape/assembly Compound) as STEP in mm, atomically."""
    from build123d import Unit, export_step

    shape = part_or_shape
    if isinstance(part_or_shape, Part):
        shape = _labelled(part_or_shape.solid, part_or_shape.name.value)
    path = Path(path)
    with atomic_path(path) as tmp:
        if not export_step(shape, str(tmp), unit=Unit.MM):
            raise RuntimeError(f"STEP export of {path.name} failed")
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


def cup_gear_assembly(params, *, crack_depth_mm: float | None = None, teeth: bool = True):
    """Compound (assembly) of cup, bearing inner ring (centred on the tooth band) and output shaft below the hub."""
    from build123d import Compound, Location

    cup = build_part(PartName.FLEXSPLINE_CUP, params, crack_depth_mm=crack_depth_mm, teeth=teeth)
    ring = build_part(PartName.WG_BEARING_RING, params, crack_depth_mm=crack_depth_mm)
    shaft = build_part(PartName.OUTPUT_SHAFT, params, crack_depth_mm=crack_depth_mm)
    z_band = 0.5 * sum(cup.meta["band_z_mm"])
    children = [
        _labelled(cup.solid, cup.name.value),
        _labelled(ring.solid.moved(Location((0, 0, z_band - 0.5 * ring.meta["width_mm"]))), ring.name.value),
        _labelled(shaft.solid.moved(Location((0, 0, -shaft.meta["length_mm"]))), shaft.name.value),
    ]
    return Compound(children=children, label="cup-type-gear"), (cup, ring, shaft)


def ewg_drive_assembly(params, *, teeth: bool = True):
    """Compound (assembly) of the EWG flexspline ring and its external wave generator, in the ring's frame."""
    from build123d import Compound

    ring = build_part(PartName.EWG_FLEXSPLINE_RING, params, teeth=teeth)
    gen = build_part(PartName.EWG, params)
    children = [_labelled(ring.solid, ring.name.value), _labelled(gen.solid, gen.name.value)]
    return Compound(children=children, label="ewg-drive"), (ring, gen)


def export_part(name: str, params, out_path: Path, *, crack_depth_mm: float | None = None, teeth: bool = True,
                png: Path | None = None) -> list[Path]:
    """Build ``name`` (a part name or ``assembly``), write STEP (and a PNG preview); return the written paths."""
    out_path = Path(out_path)
    written: list[Path] = []
    if name == ASSEMBLY:
        cup_asm, cup_parts = cup_gear_assembly(params, crack_depth_mm=crack_depth_mm, teeth=teeth)
        ewg_asm, _ = ewg_drive_assembly(params, teeth=teeth)
        written.append(write_step(cup_asm, out_path))
        written.append(write_step(ewg_asm, out_path.with_name(out_path.stem + "-ewg-drive.step")))
        preview_part = cup_parts[0]
    else:
        pn = part_name(name)
        part = build_part(pn, params, crack_depth_mm=crack_depth_mm, teeth=teeth)
        written.append(write_step(part, out_path))
        preview_part = part
    if png is not None:
        from .preview import render_preview
        written.append(render_preview(preview_part, Path(png)))
    return written
