"""Off-screen stress images from the studies' VTU fields (pyvista; the only place it is used in compare/).

Rendering is off-screen (``pv.OFF_SCREEN``); nothing here sets DISPLAY or asks for an X server: VTK
picks EGL when there is none. VTK errors inside a render are raised as exceptions (a silently
black image would pass for a result). Every PNG is written under a temporary name and renamed.
"""
from __future__ import annotations

import io
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...io_atomic import atomic_write_bytes

WINDOW = (1000, 750)


@dataclass(frozen=True)
class FieldNames:
    displacement: str | None
    von_mises: str | None


@dataclass(frozen=True)
class Rendered:
    path: Path
    caption: str
    exaggeration: float | None


def field_names(mesh) -> FieldNames:
    """Pick the displacement vector and the von Mises scalar among the point (or cell) arrays."""
    arrays = {**{k: mesh.point_data[k] for k in mesh.point_data.keys()},
              **{k: mesh.cell_data[k] for k in mesh.cell_data.keys()}}
    vectors = [k for k, v in arrays.items() if v.ndim == 2 and v.shape[1] in (2, 3) and k in mesh.point_data]
    disp = next((k for k in vectors if "disp" in k.lower()), None) or next(
        (k for k in vectors if k.lower() in ("u", "displacement_mm")), None) or (vectors[0] if vectors else None)
    mises = next((k for k, v in arrays.items() if "mises" in k.lower() and v.ndim == 1), None)
    return FieldNames(disp, mises)


def _pv():
    if not os.environ.get("DISPLAY"):
        # No X server: ask VTK for its EGL window directly instead of letting it try X first and log
        # "bad X server connection" on every render. With a display, VTK's own choice stands.
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    import pyvista as pv

    pv.OFF_SCREEN = True
    return pv


def _displacement3(mesh, name: str) -> np.ndarray:
    u = np.asarray(mesh.point_data[name], dtype=float)
    if u.shape[1] == 2:  # plane meshes carry (ux, uy)
        u = np.column_stack([u, np.zeros(len(u))])
    return u


def auto_exaggeration(mesh, disp: str, fraction: float = 0.06) -> float:
    """Scale that makes the largest displacement ``fraction`` of the model's size (a round number)."""
    u_max = float(np.max(np.linalg.norm(_displacement3(mesh, disp), axis=1)))
    if u_max <= 0.0:
        return 1.0
    raw = fraction * mesh.length / u_max
    exponent = np.floor(np.log10(raw))
    mantissa = raw / 10 ** exponent
    step = 1.0 if mantissa < 2 else (2.0 if mantissa < 5 else 5.0)
    return float(step * 10 ** exponent)


def _png_bytes(image: np.ndarray) -> bytes:
    from PIL import Image

    buffer = io.BytesIO()
    Image.fromarray(image).save(buffer, format="PNG")
    return buffer.getvalue()


def _plot(pv, mesh, scalars: str | None, title: str, *, plane: bool, focus=None):
    plotter = pv.Plotter(off_screen=True, window_size=WINDOW)
    plotter.set_background("white")
    bar = {"title": title, "color": "black", "vertical": True, "position_x": 0.85, "position_y": 0.1}
    plotter.add_mesh(mesh, scalars=scalars, cmap="turbo", show_edges=False, scalar_bar_args=bar,
                     color=None if scalars else "lightsteelblue")
    if plane:
        plotter.view_xy()
    else:
        plotter.view_isometric()
    if focus is not None:
        plotter.set_focus(focus)
    plotter.reset_camera()
    return plotter


def render_stress(vtu: Path, png: Path, *, label: str, exaggeration: float | None = None) -> Rendered:
    """von Mises stress on the deformed shape, displacements scaled by ``exaggeration`` (auto if None)."""
    pv = _pv()
    with pv.VtkErrorCatcher(raise_errors=True):
        mesh = pv.read(str(vtu))
        names = field_names(mesh)
        plane = bool(np.ptp(mesh.points[:, 2]) == 0.0)
        shown = mesh
        if names.displacement is not None:
            exaggeration = exaggeration or auto_exaggeration(mesh, names.displacement)
            shown = mesh.copy()
            shown.points = mesh.points + exaggeration * _displacement3(mesh, names.displacement)
        scalar_title = "von Mises (MPa)" if names.von_mises else "no stress field in VTU"
        plotter = _plot(pv, shown, names.von_mises, scalar_title, plane=plane)
        scale = "undeformed (no displacement field)" if names.displacement is None else \
            f"displacements x {exaggeration:g}"
        plotter.add_text(f"{label}: von Mises on deformed shape, {scale}", font_size=10, color="black")
        image = plotter.screenshot(None, return_img=True)
        plotter.close()
    atomic_write_bytes(png, _png_bytes(image))
    return Rendered(Path(png), f"{label}: von Mises stress on the deformed shape ({scale})", exaggeration)


def render_closeup(vtu: Path, png: Path, *, label: str, center_mm=None, radius_mm: float | None = None,
                   near_z_mm: float | None = None) -> Rendered:
    """Close-up of the crack tip: the region around the stress peak (or ``center_mm``), undeformed.

    ``near_z_mm`` restricts the peak search to a slab around the crack plane z (loads and supports
    elsewhere have their own stress peaks).
    """
    pv = _pv()
    with pv.VtkErrorCatcher(raise_errors=True):
        mesh = pv.read(str(vtu))
        names = field_names(mesh)
        if center_mm is None:
            if names.von_mises is None or names.von_mises not in mesh.point_data:
                raise ValueError(f"{vtu}: no point von Mises field to locate the crack tip")
            stress = np.asarray(mesh.point_data[names.von_mises], dtype=float).copy()
            if near_z_mm is not None:
                slab = radius_mm or 0.05 * mesh.length
                stress[np.abs(mesh.points[:, 2] - near_z_mm) > slab] = -np.inf
            center_mm = mesh.points[int(np.argmax(stress))]
        center = np.asarray(center_mm, dtype=float)
        radius = radius_mm or 0.08 * mesh.length
        region = mesh.clip_box([center[0] - radius, center[0] + radius, center[1] - radius, center[1] + radius,
                                center[2] - radius, center[2] + radius], invert=False)
        if region.n_points == 0:
            raise ValueError(f"{vtu}: nothing within {radius:g} mm of the crack tip")
        plane = bool(np.ptp(mesh.points[:, 2]) == 0.0)
        plotter = _plot(pv, region, names.von_mises, "von Mises (MPa)", plane=plane)
        plotter.add_mesh(region.extract_feature_edges(), color="black", line_width=1)
        text = (f"{label}: crack-tip close-up, {2 * radius:.3g} mm box at "
                f"({center[0]:.3g}, {center[1]:.3g}, {center[2]:.3g}) mm, undeformed")
        plotter.add_text(text, font_size=10, color="black")
        image = plotter.screenshot(None, return_img=True)
        plotter.close()
    atomic_write_bytes(png, _png_bytes(image))
    return Rendered(Path(png), text, None)


def sample_circle(vtu: Path, radius_mm: float, n: int = 360) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """Radial and tangential displacement along a circle of the (plane or mid-plane) ring mesh.

    Returns (theta, u_r, u_t) for the points that lie inside the mesh, or None without a displacement field.
    """
    pv = _pv()
    with pv.VtkErrorCatcher(raise_errors=True):
        mesh = pv.read(str(vtu))
        names = field_names(mesh)
        if names.displacement is None:
            return None
        z_mid = 0.5 * (mesh.bounds[4] + mesh.bounds[5])
        theta = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
        pts = np.column_stack([radius_mm * np.cos(theta), radius_mm * np.sin(theta), np.full(n, z_mid)])
        probe = pv.PolyData(pts).sample(mesh)
        valid = np.asarray(probe.point_data["vtkValidPointMask"], dtype=bool)
        u = _displacement3(probe, names.displacement)
    radial = u[:, 0] * np.cos(theta) + u[:, 1] * np.sin(theta)
    tangential = -u[:, 0] * np.sin(theta) + u[:, 1] * np.cos(theta)
    return theta[valid], radial[valid], tangential[valid]
