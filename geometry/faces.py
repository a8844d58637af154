"""Geometric face selection, done on the final solid after the last boolean.

Each face is reduced to plain data (surface kind, centre of mass, area, plane normal, cylinder radius)
and the part modules classify those records with simple predicates. Labels are never used: OCC does not
carry them reliably through booleans.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Iterable

from strainwave.geometry.part import FaceRef


@dataclass(frozen=True)
class FaceInfo:
    index: int
    kind: str                                   # "plane" | "cylinder" | "other"
    center_mm: tuple[float, float, float]
    area_mm2: float
    normal: tuple[float, float, float] | None   # planes only (outward for a solid's face)
    radius_mm: float | None                     # cylinders only
    bbox_min: tuple[float, float, float]
    bbox_max: tuple[float, float, float]

    @property
    def ref(self) -> FaceRef:
        return FaceRef(self.center_mm, self.area_mm2)

    @property
    def rho_mm(self) -> float:
        """Distance of the centre of mass from the z axis."""
        return math.hypot(self.center_mm[0], self.center_mm[1])


def face_infos(solid) -> list[FaceInfo]:
    """One FaceInfo per face of ``solid`` (a build123d shape)."""
    from build123d import GeomType, Vector
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    out = []
    for i, f in enumerate(solid.faces()):
        # one surface integration for centre and area (build123d's center() and area each run their own)
        props = GProp_GProps()
        BRepGProp.SurfaceProperties_s(f.wrapped, props)
        c = Vector(props.CentreOfMass())
        bb = f.bounding_box()
        kind, normal, radius = "other", None, None
        if f.geom_type == GeomType.PLANE:
            kind = "plane"
            n = f.normal_at(c)
            normal = (n.X, n.Y, n.Z)
        elif f.geom_type == GeomType.CYLINDER:
            kind, radius = "cylinder", float(f.radius)
        out.append(FaceInfo(i, kind, (c.X, c.Y, c.Z), float(props.Mass()), normal, radius,
                            (bb.min.X, bb.min.Y, bb.min.Z), (bb.max.X, bb.max.Y, bb.max.Z)))
    return out


def select(infos: Iterable[FaceInfo], pred: Callable[[FaceInfo], bool]) -> tuple[FaceInfo, ...]:
    return tuple(fi for fi in infos if pred(fi))


def refs(infos: Iterable[FaceInfo]) -> tuple[FaceRef, ...]:
    return tuple(fi.ref for fi in infos)


# ---- predicates -------------------------------------------------------------------------------

def is_zplane(z_mm: float, tol_mm: float = 1e-6):
    """Planar face perpendicular to z lying at height z."""
    def pred(fi: FaceInfo) -> bool:
        return (fi.kind == "plane" and abs(abs(fi.normal[2]) - 1.0) < 1e-9
                and abs(fi.center_mm[2] - z_mm) < tol_mm)
    return pred


def is_cylinder(radius_mm: float, tol_mm: float = 1e-6, z_range: tuple[float, float] | None = None):
    """Cylindrical face of the given radius (coaxial with z assumed by the part), optionally within a z band."""
    def pred(fi: FaceInfo) -> bool:
        if fi.kind != "cylinder" or abs(fi.radius_mm - radius_mm) > tol_mm:
            return False
        if z_range is not None:
            return z_range[0] - tol_mm <= fi.bbox_min[2] and fi.bbox_max[2] <= z_range[1] + tol_mm
        return True
    return pred


def in_box(lo: tuple[float, float, float], hi: tuple[float, float, float]):
    """Face whose bounding box lies inside the axis-aligned box [lo, hi]."""
    def pred(fi: FaceInfo) -> bool:
        return all(lo[k] <= fi.bbox_min[k] and fi.bbox_max[k] <= hi[k] for k in range(3))
    return pred


def both(*preds):
    return lambda fi: all(p(fi) for p in preds)


def without(pred, *excluded: Iterable[FaceInfo]):
    """``pred`` minus faces already claimed by other sets."""
    taken = {fi.index for group in excluded for fi in group}
    return lambda fi: fi.index not in taken and pred(fi)


def find_faces(solid, face_refs: Iterable[FaceRef], tol: float = 1e-6) -> list:
    """The build123d faces of ``solid`` matching FaceRefs (centre within tol * size, same area)."""
    face_refs = list(face_refs)
    if not face_refs:
        # most parts lack the faces the preview asks for; face_infos is costly (docs/decisions/015-cad-build-speed.md)
        return []
    infos = face_infos(solid)
    faces = solid.faces()
    out = []
    for ref in face_refs:
        for fi in infos:
            scale = max(1.0, math.sqrt(ref.area_mm2))
            if (abs(fi.area_mm2 - ref.area_mm2) <= tol * max(1.0, ref.area_mm2)
                    and math.dist(fi.center_mm, ref.center_mm) <= tol * scale * 100):
                out.append(faces[fi.index])
                break
    return out
