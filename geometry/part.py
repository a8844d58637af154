"""What leaves geometry/: a solid plus named face sets as plain data that survives BREP/STEP export.

build123d labels do not survive boolean operations, so faces are selected geometrically after the
last operation and recorded by centre of mass and area; the mesher matches gmsh surfaces to them.
"""
from __future__ import annotations

import enum
from dataclasses import dataclass, field


class PartName(enum.Enum):
    FLEXSPLINE_CUP = "flexspline-cup"
    EWG_FLEXSPLINE_RING = "ewg-flexspline-ring"
    EWG = "ewg"
    OUTPUT_SHAFT = "output-shaft"
    WG_BEARING_RING = "wg-bearing-ring"
    WG_CAM = "wg-cam"
    CIRCULAR_SPLINE = "circular-spline"
    WG_BEARING_BALLS = "wg-bearing-balls"
    WG_BEARING_OUTER_RING = "wg-bearing-outer-ring"


class CrackModel(enum.Enum):
    """How a crack enters the geometry."""
    SLOT = "slot"    # a CAD slot of width crack_geometry.slot_width_mm cut from the solid (STEP, previews)
    SEAM = "seam"    # the uncracked solid plus a zero-width crack surface (FEA: same mesh cracked/uncracked)


@dataclass(frozen=True)
class FaceRef:
    center_mm: tuple[float, float, float]
    area_mm2: float


@dataclass(frozen=True)
class Part:
    name: PartName
    solid: object                                   # build123d Solid/Part, or a bare TopoDS_Solid (FEA only), mm
    named_faces: dict[str, tuple[FaceRef, ...]]     # e.g. fixed, loaded, bore, race, crack_face, crack_front
    crack_front_mm: tuple[tuple[float, float, float], ...] = ()   # points along the crack front, for size fields
    section: object | None = None                   # 2D build123d Face (xy plane) for prismatic parts, else None
    meta: dict = field(default_factory=dict)        # key dimensions the tests and FEA read (radii, W0, ...)
    # SEAM cracks: the planar crack Face (reaching beyond the free surface) and its plane (point, unit normal)
    crack_surface: object | None = None
    crack_plane: tuple[tuple[float, float, float], tuple[float, float, float]] | None = None

    @property
    def volume_mm3(self) -> float:
        return float(self.solid.volume)
