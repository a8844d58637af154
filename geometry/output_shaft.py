"""Hollow output shaft (seed 000): d_s / d_s2, length L_s, optional circumferential crack.

z runs from 0 (end face ``fixed``) to L_s (end face ``loaded``); ``outer`` and ``bore`` are the
cylinders. The crack is a slot of depth a from the outer surface at z = ratio * L_s, centred on +x,
over ``crack_geometry.shaft_arc_deg`` (360 = full circumferential crack). ``CrackModel.SEAM`` keeps the
solid whole and returns the annulus (sector) z = z_c, r_o - a .. r_o as ``Part.crack_surface``.
"""
from __future__ import annotations

import math

from strainwave.errors import InputError

from strainwave.geometry import faces as F
from strainwave.geometry.crack_seams import circumferential_seam
from strainwave.geometry.cracks import check_crack, circumferential_slot
from strainwave.geometry.occ import cut, cut_bare
from strainwave.geometry.part import CrackModel, FaceRef, Part, PartName


def build(params, *, crack_depth_mm: float | None = None, teeth: bool = True,
          crack_model: CrackModel = CrackModel.SLOT) -> Part:
    sh, cg = params.output_shaft, params.crack_geometry
    r_o, r_i, length = sh.outer_diameter_mm / 2, sh.inner_diameter_mm / 2, sh.length_mm
    seam = crack_model == CrackModel.SEAM
    w = 0.0 if seam else cg.slot_width_mm        # a seam has no width to check
    if crack_depth_mm is not None:  # refuse bad cracks before any CAD work
        check_crack(crack_depth_mm, sh.wall_mm, "output_shaft wall (outer - inner)/2", w)
        if not w < cg.shaft_axial_position_ratio * length < length - w:
            raise InputError("crack_geometry.shaft_axial_position_ratio", cg.shaft_axial_position_ratio,
                             "the slot must lie inside the shaft length")
    from build123d import Solid

    solid = Solid(_hollow_bare(r_o, r_i, length))
    meta = _meta(r_o, r_i, length)
    if crack_depth_mm is not None and seam:
        z_c = cg.shaft_axial_position_ratio * length
        cs = circumferential_seam(r_o, crack_depth_mm, z_c, cg.shaft_arc_deg)
        meta.update(cs.meta, crack_depth_mm=crack_depth_mm, crack_model=CrackModel.SEAM.value)
        return Part(PartName.OUTPUT_SHAFT, solid, _plain_faces(solid, length, r_o, r_i), cs.front_mm, None, meta,
                    cs.face, (cs.point_mm, cs.normal))
    slot = None
    if crack_depth_mm is not None:
        z_c = cg.shaft_axial_position_ratio * length
        slot = circumferential_slot(r_o, crack_depth_mm, z_c, cg.slot_width_mm, cg.shaft_arc_deg)
        solid = cut(solid, slot.tool)
        meta.update(slot.meta, crack_depth_mm=crack_depth_mm, slot_width_mm=cg.slot_width_mm,
                    slot_volume_mm3=slot.volume_mm3)
        meta["volume_closed_form_mm3"] -= slot.volume_mm3

    named = _plain_faces(solid, length, r_o, r_i)
    infos = F.face_infos(solid)
    front: tuple = ()
    if slot is not None:
        zc, w = meta["crack_z_mm"], cg.slot_width_mm
        walls = F.select(infos, lambda fi: (F.is_zplane(zc - w / 2)(fi) or F.is_zplane(zc + w / 2)(fi)))
        bottom = F.select(infos, F.is_cylinder(r_o - crack_depth_mm))
        # a part-through arc also has two radial end faces: they belong to the front
        ends = F.select(infos, lambda fi: fi.kind == "plane" and abs(fi.normal[2]) < 1e-9)
        named["crack_face"] = F.refs(walls)
        named["crack_front"] = F.refs(bottom + ends)
        front = slot.front_mm
    return Part(PartName.OUTPUT_SHAFT, solid, named, front, None, meta)


def _plain_faces(solid, length: float, r_o: float, r_i: float) -> dict:
    infos = F.face_infos(solid)
    return {
        "fixed": F.refs(F.select(infos, F.is_zplane(0.0))),
        "loaded": F.refs(F.select(infos, F.is_zplane(length))),
        "outer": F.refs(F.select(infos, F.is_cylinder(r_o))),
        "bore": F.refs(F.select(infos, F.is_cylinder(r_i))) if r_i > 0 else (),
    }


def _meta(r_o: float, r_i: float, length: float) -> dict:
    return {"outer_radius_mm": r_o, "inner_radius_mm": r_i, "length_mm": length,
            "volume_closed_form_mm3": math.pi * (r_o ** 2 - r_i ** 2) * length}


def _hollow_bare(r_o: float, r_i: float, length: float):
    """The uncracked shaft as a bare ``TopoDS_Solid``: the one recipe of ``build`` and ``build_bare``."""
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeCylinder
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt
    from OCP.TopoDS import TopoDS

    def cylinder(radius_mm: float):
        # build123d's Solid.make_cylinder(radius, length) on Plane.XY, argument for argument
        axes = gp_Ax2(gp_Pnt(0.0, 0.0, 0.0), gp_Dir(0.0, 0.0, 1.0), gp_Dir(1.0, 0.0, 0.0))
        return TopoDS.Solid(BRepPrimAPI_MakeCylinder(axes, radius_mm, length, 360 * (math.pi / 180.0)).Shape())

    solid = cylinder(r_o)
    return cut_bare(solid, cylinder(r_i)) if r_i > 0 else solid


def build_bare(params) -> Part:
    """The uncracked shaft as ``build`` makes it, its solid a bare ``TopoDS_Solid``, without build123d.

    What the FEA meshes (``fea.meshing`` writes either kind to BREP; the same file): a worker solving
    uncracked shaft points then never imports build123d, the costliest import of its start
    (docs/decisions/013-sweep-worker-start-up.md). CAD
    uses (STEP, previews, volumes) keep ``build``. An empty face set (the bore of a solid shaft) is left
    out, as ``build_part`` does.
    """
    sh = params.output_shaft
    r_o, r_i, length = sh.outer_diameter_mm / 2, sh.inner_diameter_mm / 2, sh.length_mm
    solid = _hollow_bare(r_o, r_i, length)
    named = {k: v for k, v in _plain_faces_bare(solid, length, r_o, r_i).items() if v}
    return Part(PartName.OUTPUT_SHAFT, solid, named, (), None, _meta(r_o, r_i, length))


def _plain_faces_bare(solid, length: float, r_o: float, r_i: float) -> dict:
    """``_plain_faces`` of a bare solid: the same faces (``faces.is_zplane``, ``faces.is_cylinder`` at their
    default tolerances) and the same FaceRefs, from the same OCC mass properties as build123d's."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.BRepGProp import BRepGProp
    from OCP.GeomAbs import GeomAbs_Cylinder, GeomAbs_Plane
    from OCP.GProp import GProp_GProps
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    faces, explorer = {}, TopExp_Explorer(solid, TopAbs_FACE)
    while explorer.More():
        faces[hash(explorer.Current())] = TopoDS.Face(explorer.Current())   # build123d's faces(), in its order
        explorer.Next()
    named = {"fixed": [], "loaded": [], "outer": [], "bore": []}
    for face in faces.values():
        props = GProp_GProps()
        BRepGProp.SurfaceProperties_s(face, props)
        c = props.CentreOfMass()
        ref = FaceRef((c.X(), c.Y(), c.Z()), props.Mass())
        surface = BRepAdaptor_Surface(face)
        if surface.GetType() == GeomAbs_Plane and abs(abs(surface.Plane().Axis().Direction().Z()) - 1.0) < 1e-9:
            for name, z_mm in (("fixed", 0.0), ("loaded", length)):
                if abs(c.Z() - z_mm) < 1e-6:
                    named[name].append(ref)
        elif surface.GetType() == GeomAbs_Cylinder:
            radius = surface.Cylinder().Radius()
            for name, r_mm in (("outer", r_o), ("bore", r_i)):
                if abs(radius - r_mm) <= 1e-6 and (name == "outer" or r_i > 0):
                    named[name].append(ref)
    return {name: tuple(refs) for name, refs in named.items()}
