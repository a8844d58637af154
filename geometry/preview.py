"""Off-screen PNG preview of a part (pyvista/VTK through ``strainwave.render``: no display, no global state).

Left: the whole part (grey), with the crack faces in red, contact/load faces in blue and fixed faces in green.
Right: a close-up on the crack front (or, for an uncracked part, on the contact or loaded faces).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from strainwave.io_atomic import atomic_path
from strainwave.render import RenderSettings, off_screen_plotter

from strainwave.geometry.faces import find_faces
from strainwave.geometry.part import Part


def _polydata(shapes, tol_mm: float):
    """The shapes' triangulation as one PolyData: OCC's mesher (as build123d's ``tessellate``, without its
    threads), handed to VTK as binary STL, not as one Python object per vertex (the slow part on the
    toothed parts' many faces)."""
    import tempfile

    import pyvista as pv
    from OCP.BRep import BRep_Builder
    from OCP.BRepMesh import BRepMesh_IncrementalMesh
    from OCP.BRepTools import BRepTools
    from OCP.StlAPI import StlAPI_Writer
    from OCP.TopoDS import TopoDS_Compound

    if not shapes:
        return None
    compound, builder = TopoDS_Compound(), BRep_Builder()
    builder.MakeCompound(compound)
    for shape in shapes:
        if not BRepTools.Triangulation_s(shape.wrapped, tol_mm):   # meshed finer already: kept, as build123d does
            BRepMesh_IncrementalMesh(shape.wrapped, tol_mm, True, 0.3, False)
        builder.Add(compound, shape.wrapped)
    with tempfile.TemporaryDirectory() as tmp:
        stl = Path(tmp) / "shapes.stl"
        writer = StlAPI_Writer()
        writer.ASCIIMode = False
        if not writer.Write(compound, str(stl)):
            raise RuntimeError("STL of the preview's shapes failed")
        mesh = pv.read(stl)
    return mesh if mesh.n_cells else None


LOAD_FACES = ("contact", "loaded")    # where a load or a contact acts: blue
SUPPORT_FACES = ("fixed",)            # where the part is held: green
LOAD_COLOUR, SUPPORT_COLOUR = "royalblue", "forestgreen"


def _refs(part: Part, names: tuple[str, ...]) -> list:
    return [ref for name in names for ref in part.named_faces.get(name, ())]


def _lifted(mesh, middle: np.ndarray, span: float):
    """``mesh`` moved 0.2 % of the part's size away from its middle, off the body's surface (no z-fighting),
    on a cylinder and on an end face alike."""
    if mesh is None:
        return None
    away = mesh.points - middle
    mesh.points = mesh.points + 2e-3 * span * away / np.maximum(np.linalg.norm(away, axis=1, keepdims=True), 1e-12)
    return mesh


def _focus(part: Part):
    """Centre and size of the region the close-up shows."""
    if part.crack_front_mm:
        pts = np.asarray(part.crack_front_mm)
        depth = float(part.meta.get("crack_depth_mm", 1.0))
        # the front's middle sample (a full circle's mean would be the axis, far from the crack)
        return pts[len(pts) // 2], 10 * depth
    for key in ("contact", "loaded", "outer"):
        refs = part.named_faces.get(key)
        if refs:
            c = np.asarray(refs[0].center_mm)
            return c, 3.0 * float(np.sqrt(refs[0].area_mm2))
    return np.zeros(3), 10.0


def render_preview(part: Part, png_path: Path | str, size: tuple[int, int] = (1400, 700)) -> Path:
    """Render ``part`` off-screen to ``png_path`` (written atomically) and return the path."""
    bb = part.solid.bounding_box()
    span = max(bb.size.X, bb.size.Y, bb.size.Z)
    body = _polydata([part.solid], 2e-3 * span)
    crack = _polydata(find_faces(part.solid, part.named_faces.get("crack_face", ())
                                 + part.named_faces.get("crack_front", ())), 1e-3)
    middle = np.array([bb.center().X, bb.center().Y, bb.center().Z])
    loads = _lifted(_polydata(find_faces(part.solid, _refs(part, LOAD_FACES)), 1e-3 * span), middle, span)
    supports = _lifted(_polydata(find_faces(part.solid, _refs(part, SUPPORT_FACES)), 1e-3 * span), middle, span)
    centre, extent = _focus(part)

    plotter = off_screen_plotter(RenderSettings(size, shape=(1, 2)))
    for col in (0, 1):
        plotter.subplot(0, col)
        plotter.add_mesh(body, color="lightsteelblue", smooth_shading=False, show_edges=False)
        if crack is not None:  # a 0.02 mm slot is seen edge-on: draw its edges too, unlit pure red
            plotter.add_mesh(crack, color="red", lighting=False)
            plotter.add_mesh(crack.extract_feature_edges(), color="red", line_width=4, lighting=False)
        if loads is not None:
            plotter.add_mesh(loads, color=LOAD_COLOUR)
        if supports is not None:
            plotter.add_mesh(supports, color=SUPPORT_COLOUR)
    plotter.subplot(0, 0)
    plotter.add_text(f"{part.name.value}", font_size=14, color="black")
    plotter.add_axes(color="black", line_width=3)
    plotter.view_isometric()
    plotter.reset_camera()
    plotter.subplot(0, 1)
    radial = np.array([centre[0], centre[1], 0.0])
    direction = radial / np.linalg.norm(radial) if np.linalg.norm(radial) > 1e-9 else np.array([1.0, 0, 0])
    direction = direction + np.array([0.0, 0.0, 0.35])
    plotter.camera.focal_point = tuple(centre)
    plotter.camera.position = tuple(centre + 4.0 * extent * direction)
    plotter.camera.up = (0.0, 0.0, 1.0)
    plotter.camera.view_angle = 30.0
    plotter.camera.clipping_range = (1e-3 * extent, 100.0 * extent + span)
    plotter.add_text("close-up: crack" if part.crack_front_mm else "close-up", font_size=14, color="black")
    png_path = Path(png_path)
    with atomic_path(png_path) as tmp:
        plotter.screenshot(str(tmp.with_suffix(".png")))
        tmp.with_suffix(".png").replace(tmp)
    plotter.close()
    return png_path


def render_assembly_preview(drives: dict, png_path: Path | str, size: tuple[int, int] = (1400, 700)) -> Path:
    """Render every part of every drive (name -> list of ``step_xcaf.Placed``), one panel per drive,
    each part in its STEP colour and placed where the STEP file has it; crack faces in red."""
    from strainwave.geometry.step_xcaf import PART_COLOURS_RGB

    plotter = off_screen_plotter(RenderSettings(size, shape=(1, len(drives))))
    for col, (drive, placed) in enumerate(drives.items()):
        plotter.subplot(0, col)
        names = []
        for item in placed:
            shape = item.shape
            bb = shape.bounding_box()
            span = max(bb.size.X, bb.size.Y, bb.size.Z)
            body = _polydata([shape], 2e-3 * span)
            plotter.add_mesh(body, color=PART_COLOURS_RGB.get(item.part.name.value, (0.7, 0.7, 0.7)))
            refs = item.part.named_faces.get("crack_face", ()) + item.part.named_faces.get("crack_front", ())
            if refs:   # the crack faces of the part as built, moved to where the assembly has it
                faces = find_faces(item.part.solid, refs)
                crack = _polydata([f if item.at is None else f.moved(item.at) for f in faces], 1e-3)
                if crack is not None:
                    plotter.add_mesh(crack, color="red", lighting=False)
            names.append(item.part.name.value)
        plotter.add_text(f"{drive}: " + ", ".join(names), font_size=9, color="black")
        plotter.view_isometric()
        plotter.reset_camera()
    png_path = Path(png_path)
    with atomic_path(png_path) as tmp:
        plotter.screenshot(str(tmp.with_suffix(".png")))
        tmp.with_suffix(".png").replace(tmp)
    plotter.close()
    return png_path
