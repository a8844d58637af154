"""``build_part``: one entry point that dispatches to one module per part."""
from __future__ import annotations

import dataclasses

from strainwave.errors import InputError

from strainwave.geometry import (bearing_ring, circular_spline, drive_assembly, ewg, ewg_ring, flexspline_cup,
                                 output_shaft, wg_cam)
from strainwave.geometry.part import CrackModel, Part, PartName

_BUILDERS = {
    PartName.FLEXSPLINE_CUP: flexspline_cup.build,
    PartName.EWG_FLEXSPLINE_RING: ewg_ring.build,
    PartName.EWG: ewg.build,
    PartName.OUTPUT_SHAFT: output_shaft.build,
    PartName.WG_BEARING_RING: bearing_ring.build,
    PartName.WG_CAM: wg_cam.build,
    PartName.CIRCULAR_SPLINE: circular_spline.build,
    PartName.WG_BEARING_BALLS: drive_assembly.build_balls,
    PartName.WG_BEARING_OUTER_RING: drive_assembly.build_outer_ring,
}
CRACKABLE = (PartName.FLEXSPLINE_CUP, PartName.OUTPUT_SHAFT, PartName.WG_BEARING_RING)


def part_name(name: PartName | str) -> PartName:
    if isinstance(name, PartName):
        return name
    try:
        return PartName(name)
    except ValueError:
        raise InputError("part", name, f"must be one of {', '.join(p.value for p in PartName)}") from None


def build_part(name: PartName | str, params, *, crack_depth_mm: float | None = None, teeth: bool = True,
               crack_model: CrackModel = CrackModel.SLOT) -> Part:
    """Build one part in mm, axis z, with named faces (see the package docstring for conventions).

    ``crack_depth_mm=None`` gives the uncracked part; a value seeds the part's crack slot with that
    depth (other crack data from ``params.cracks`` and ``params.crack_geometry``). Parts without a
    seeded crack (the EWG ring and the EWG) refuse a crack depth. ``crack_model`` SLOT cuts the CAD slot
    (STEP export, previews); SEAM returns the uncracked solid with ``Part.crack_surface``/``crack_plane``
    (a zero-width crack surface the mesher embeds, for FEA on one mesh cracked and uncracked).
    """
    pn = part_name(name)
    if crack_depth_mm is not None and pn not in CRACKABLE:
        raise InputError("crack_depth_mm", crack_depth_mm,
                         f"part {pn.value} has no seeded crack; cracks exist on "
                         f"{', '.join(p.value for p in CRACKABLE)}")
    kw = {"crack_model": CrackModel(crack_model)} if pn in CRACKABLE else {}
    part = _BUILDERS[pn](params, crack_depth_mm=crack_depth_mm, teeth=teeth, **kw)
    # an empty set (e.g. the bore of a solid shaft) would become an empty gmsh physical group: drop it
    return dataclasses.replace(part, named_faces={k: v for k, v in part.named_faces.items() if v})
