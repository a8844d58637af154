"""Interactive 3D views of the stress fields for report.html: self-contained, offline, no library.

The field's outer surface (linear triangles through the corner nodes, deformed as on the PNG) with its von
Mises stress at the rated load goes into the page as base64 float32/uint32 arrays inside a JSON script
element; ``view3d.js`` (about 150 lines of WebGL 1, shipped here) draws every such canvas. No network, no
trame, no vtk.js bundle: the page opens from a zipped folder in any browser with WebGL, and headless Chromium
renders it with its software rasterizer (tests/test_compare_validate.py checks it).
"""
from __future__ import annotations

import base64
import json
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

from strainwave.rated_stress import StressAtRated, displacement3, field_names, read_vtu, scaled_to_rated

__all__ = ["View", "make_view", "viewer_script", "colorbar_css", "MAX_TRIANGLES"]

# Above this the surface is decimated (quadric, scalars carried along): 120k triangles are ~4 MB of page
MAX_TRIANGLES = 120_000


@dataclass(frozen=True)
class View:
    component: str
    caption: str
    triangles: int
    range_MPa: tuple[float, float]
    payload: str          # the JSON the page embeds

    def to_dict(self) -> dict:      # what results.json records (the arrays stay in the page)
        return {"component": self.component, "caption": self.caption, "triangles": self.triangles,
                "range_MPa": list(self.range_MPa)}


def _b64(a: np.ndarray) -> str:
    return base64.b64encode(np.ascontiguousarray(a).tobytes()).decode("ascii")


def make_view(component: str, vtu: Path, at: StressAtRated, *, exaggeration: float, label: str) -> View:
    """The surface of ``vtu`` at the rated load of ``at``, displacements x ``exaggeration``, as a page payload."""
    mesh = scaled_to_rated(read_vtu(vtu), at.load.scale)
    names = field_names(mesh)
    if names.von_mises is None or names.von_mises not in mesh.point_data:
        raise ValueError(f"{vtu}: no nodal von Mises field")
    if names.displacement is not None:
        mesh.points = mesh.points + exaggeration * displacement3(mesh, names.displacement)
    planar = bool(np.ptp(mesh.points[:, 2]) == 0.0)
    surface = mesh.extract_surface(nonlinear_subdivision=0, algorithm="dataset_surface").triangulate().clean()
    if surface.n_cells > MAX_TRIANGLES:
        surface = surface.decimate(1.0 - MAX_TRIANGLES / surface.n_cells, attribute_error=True).triangulate()
    faces = np.asarray(surface.faces).reshape(-1, 4)[:, 1:].astype(np.uint32)
    points = np.asarray(surface.points, dtype=float)
    points = points - 0.5 * (points.min(axis=0) + points.max(axis=0))
    points /= max(float(np.linalg.norm(points, axis=1).max()), 1e-30)
    if not planar:
        points = np.column_stack([points[:, 0], points[:, 2], -points[:, 1]])   # model z up on the screen
    scalars = np.asarray(surface.point_data[names.von_mises], dtype=np.float32)
    from strainwave.compare.validate.images import colour_top

    peak = colour_top(np.asarray(mesh.point_data[names.von_mises], float), at.peaks.peak_von_mises_MPa)
    payload = json.dumps({"positions": _b64(points.astype(np.float32)), "scalars": _b64(scalars),
                          "indices": _b64(faces.ravel()), "range": [0.0, peak],
                          "home": [0.0, 0.0] if planar else [0.5, -0.7]})
    caption = (f"{label}: von Mises (MPa) at {at.load.name} = {at.load.rated:.4g} {at.load.unit}, displacements x "
               f"{exaggeration:g}, {faces.shape[0]} surface triangles (corner nodes). Drag to rotate, wheel to "
               "zoom, double click to reset.")
    return View(component, caption, int(faces.shape[0]), (0.0, float(peak)), payload)


def viewer_script() -> str:
    return resources.files(__package__).joinpath("view3d.js").read_text(encoding="utf-8")


def colorbar_css() -> str:
    """The viewer's colour map (turbo) as a CSS gradient, from matplotlib's own table."""
    from matplotlib import colormaps

    cmap = colormaps["turbo"]
    stops = ", ".join(f"rgb({int(255 * r)},{int(255 * g)},{int(255 * b)}) {100 * t:.0f}%"
                      for t in np.linspace(0, 1, 9) for r, g, b, _ in [cmap(t)])
    return f"linear-gradient(to right, {stops})"
