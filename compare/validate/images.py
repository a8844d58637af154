"""Off-screen stress images from the studies' VTU fields (pyvista; the only place it renders in compare/).

Every plotter comes from ``strainwave.render.off_screen_plotter`` with its settings passed in: nothing here
changes pyvista or the environment. VTK errors inside a render are raised as exceptions (a silently black
image would pass for a result). Every PNG is written under a temporary name and renamed.

Stress pictures are drawn at the rated load: the fields are linear in the load, so stresses and
displacements are multiplied by ``scale`` = rated / solved load before anything is drawn or measured.
"""
from __future__ import annotations

import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from strainwave.io_atomic import atomic_write_bytes
from strainwave.analytic.rated_load import RatedLoad
from strainwave.rated_stress import StressAtRated, displacement3, field_names, read_vtu, scaled_to_rated
from strainwave.render import RenderSettings, off_screen_plotter

WINDOW = (1200, 900)
TITLE_PT = 18        # report.html shows stress pictures full width (about 1150 px): ~12 px text
SUPPORT_COLOR = "black"
LOAD_COLOR = "magenta"


@dataclass(frozen=True)
class Marks:
    """What the picture marks, from the study's named boundary facets (``NAME.boundary.vtu``)."""
    support_groups: tuple[str, ...]    # held fixed: faces ("fixed", "bore") or points (the 2D ring's A, B, D)
    load_group: str | None             # facets the load acts on, e.g. "loaded" or "contact"
    load_label: str                    # e.g. "T", "F_r"


@dataclass(frozen=True)
class Zoom:
    """A second panel around the peak von Mises point, ``radius_mm`` wide."""
    radius_mm: float
    title: str = "close-up at the peak"


@dataclass(frozen=True)
class Rendered:
    path: Path
    caption: str
    exaggeration: float | None


def read_field(vtu: Path):
    """``vtu``'s mesh."""
    return read_vtu(vtu)


def auto_exaggeration(mesh, disp: str, fraction: float = 0.06) -> float:
    """Scale that makes the largest displacement ``fraction`` of the model's size (a round number)."""
    u_max = float(np.max(np.linalg.norm(displacement3(mesh, disp), axis=1)))
    if u_max <= 0:
        return 1.0
    raw = fraction * mesh.length / u_max
    exponent = np.floor(np.log10(raw))
    mantissa = raw / 10 ** exponent
    nice = 5.0 if mantissa >= 5 else 2.0 if mantissa >= 2 else 1.0
    return float(nice * 10 ** exponent)


def _png_bytes(image: np.ndarray) -> bytes:
    from PIL import Image

    buffer = io.BytesIO()
    Image.fromarray(image).save(buffer, format="PNG")
    return buffer.getvalue()


def _bar(title: str) -> dict:
    return {"title": title, "color": "black", "vertical": True, "position_x": 0.86, "position_y": 0.12,
            "title_font_size": 20, "label_font_size": 18, "fmt": "%.3g", "width": 0.08, "height": 0.7}


def _view(plotter, plane: bool, view_from=None) -> None:
    """Plane fields from +z; 3D ones isometric, or from the direction ``view_from`` (z up)."""
    if plane:
        plotter.view_xy()
    elif view_from is not None:
        plotter.view_vector(view_from, viewup=(0.0, 0.0, 1.0))
    else:
        plotter.view_isometric()


def boundary_groups(vtu: Path, names: tuple[str, ...]):
    """{name: facets} of the named groups of ``vtu``'s boundary file (fea/fields.py), those that exist."""
    from strainwave.fea.fields import field_text

    path = Path(vtu).with_name(f"{Path(vtu).stem}.boundary.vtu")
    if not path.exists():
        return {}
    boundary = read_vtu(path)
    known = field_text(boundary, "physical_group_names") if "physical_group_names" in boundary.field_data.keys() \
        else []
    ids = np.asarray(boundary.cell_data["physical_group"])
    out = {}
    for name in names:
        if name in known:
            # id k is entry k - 1 of physical_group_names (fields.py)
            cells = np.flatnonzero(ids == known.index(name) + 1)
            if cells.size:
                out[name] = boundary.extract_cells(cells)
    return out


def _deformed(mesh, disp: str | None, exaggeration: float):
    if disp is None or disp not in mesh.point_data:
        return mesh
    shown = mesh.copy()
    shown.points = mesh.points + exaggeration * displacement3(mesh, disp)
    return shown


def _draw_marks(pv, plotter, shown, groups: dict, marks: Marks, disp: str | None, scale: float,
                exaggeration: float) -> list[str]:
    """Supports (black) and loaded facets (magenta, with an arrow and label); returns the legend entries."""
    legend = []
    size = 0.12 * shown.length
    held = [g for g in marks.support_groups if g in groups]
    for name in held:
        support = _deformed(scaled_to_rated(groups[name], scale), disp, exaggeration)
        if support.n_cells and support.get_cell(0).type == pv.CellType.VERTEX:   # a point support
            plotter.add_mesh(support, color=SUPPORT_COLOR, point_size=14, render_points_as_spheres=True)
            plotter.add_point_labels(support.points[:1], [name], font_size=18, text_color=SUPPORT_COLOR,
                                     shape_opacity=0.0, show_points=False, always_visible=True)
        else:
            plotter.add_mesh(support, color=SUPPORT_COLOR, style="wireframe", line_width=2)
    if held:
        legend.append("black: supports (" + ", ".join(f"'{g}'" for g in held) + ")")
    if marks.load_group in groups:
        loaded = _deformed(scaled_to_rated(groups[marks.load_group], scale), disp, exaggeration)
        planar = np.ptp(shown.points[:, 2]) == 0.0
        # a planar field's load group is its contact edges (thick lines); a 3D face is outlined by its facets
        plotter.add_mesh(loaded, color=LOAD_COLOR, style="wireframe", line_width=5 if planar else 1)
        arrows = _load_arrows(loaded, disp, np.asarray(shown.center))
        for k, (start, direction) in enumerate(arrows):
            plotter.add_mesh(pv.Arrow(start=start - size * direction, direction=direction, scale=size),
                             color=LOAD_COLOR)
            if k and len(arrows) > 2:
                continue   # a torque's four arrows carry one label
            plotter.add_point_labels([start - 1.1 * size * direction], [marks.load_label], font_size=18,
                                     text_color=LOAD_COLOR, shape_opacity=0.0, show_points=False,
                                     always_visible=True)
        legend.append(f"magenta: load {marks.load_label} on '{marks.load_group}'")
    return legend


def _load_arrows(loaded, disp: str | None, model_center: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """(point, unit direction) of the arrows that show a load: one per connected strip along its mean motion
    (a force); where the strip turns rather than moves (mean motion below a fifth of its mean |u|: a torque),
    four arrows along the motion at its outer rim, 90 degrees apart."""
    arrows = []
    for body in loaded.connectivity().split_bodies() if loaded.n_points else []:
        center = np.asarray(body.center)
        u = displacement3(body, disp) if disp and disp in body.point_data else np.zeros((body.n_points, 3))
        mean, size = u.mean(axis=0), np.linalg.norm(u, axis=1).mean()
        if size > 0 and np.linalg.norm(mean) < 0.2 * size:
            pts = np.asarray(body.points)
            r = np.hypot(pts[:, 0], pts[:, 1])
            rim = np.flatnonzero(r >= 0.98 * r.max())
            angle = np.arctan2(pts[rim, 1], pts[rim, 0])
            for target in (0.0, 0.5 * np.pi, np.pi, -0.5 * np.pi):
                k = rim[np.argmin(np.abs(np.angle(np.exp(1j * (angle - target)))))]
                arrows.append((pts[k], u[k] / max(np.linalg.norm(u[k]), 1e-30)))
            continue
        direction = mean if np.linalg.norm(mean) > 0 else center - model_center
        arrows.append((center, direction / max(np.linalg.norm(direction), 1e-30)))
    return arrows


# characters a title line of TITLE_PT keeps inside one WINDOW-wide panel (a longer one was cut at the edge:
# "leave the body c"); tests/test_outputs_small.py renders the longest title and finds it inside the picture
TITLE_CHARS = 80


def title_text(lines: list[str], width: int = TITLE_CHARS) -> str:
    """The title lines, each wrapped at ``width`` characters (continuations indented), one text block."""
    import textwrap
    return "\n".join(w for line in lines for w in textwrap.wrap(line, width, subsequent_indent="  ") or [""])


SPIKE_PERCENTILE = 99.5    # a peak above SPIKE_RATIO x this percentile of the nodes is a local spike
SPIKE_RATIO = 1.5


def colour_top(von_mises: np.ndarray, peak: float) -> float:
    """Top of a stress picture's colour range: the peak, unless the peak is a local spike (a support corner, a
    crack's tip) far above the rest, then the SPIKE_PERCENTILE-th percentile of the nodes."""
    top = float(np.percentile(von_mises, SPIKE_PERCENTILE))
    return top if 0.0 < top and peak > SPIKE_RATIO * top else float(peak)


def render_stress(vtu: Path, png: Path, *, label: str, at: StressAtRated, marks: Marks, section: str = "",
                  zoom: Zoom | None = None, exaggeration: float | None = None,
                  factor_line: str | None = None, view_from=None) -> Rendered:
    """von Mises at the rated load (fields x the load's scale) on the deformed shape: supports and loads
    marked, axis triad, peak marked and printed; ``zoom`` adds a close-up panel around the peak;
    ``factor_line`` replaces the safety-factor line (a field that is no design stress); ``view_from``: the
    camera's direction on a 3D field (None: isometric)."""
    import pyvista as pv

    shape = (1, 2) if zoom is not None else (1, 1)
    window = (2 * WINDOW[0], WINDOW[1]) if zoom is not None else WINDOW
    with pv.VtkErrorCatcher(raise_errors=True):
        mesh = scaled_to_rated(read_field(vtu), at.load.scale)
        names = field_names(mesh)
        plane = bool(np.ptp(mesh.points[:, 2]) == 0.0)
        exaggeration = exaggeration or (auto_exaggeration(mesh, names.displacement) if names.displacement else 1.0)
        shown = _deformed(mesh, names.displacement, exaggeration)
        groups = boundary_groups(vtu, marks.support_groups + ((marks.load_group,) if marks.load_group else ()))
        scale_text = ("undeformed (no displacement field)" if names.displacement is None else
                      f"displacements x {exaggeration:g}")
        p = at.peaks
        where = ", ".join(f"{x:.4g}" for x in p.peak_location_mm) + ")" + (
            f" on {', '.join(repr(g) for g in p.peak_on)}" if p.peak_on else "")
        lines = [f"{label}: von Mises at {at.load.name} = {at.load.rated:.4g} {at.load.unit}",
                 scale_text + (f"; {section}" if section else ""),
                 f"peak {p.peak_von_mises_MPa:.4g} MPa at ({where} mm, peak displacement {p.peak_displacement_mm:.3g} mm,",
                 factor_line or f"safety factor {at.safety_factor:.3g} vs fatigue limit {at.fatigue_limit_MPa:g} MPa"]
        if p.tip_peak_von_mises_MPa is not None:   # the singular crack tip: left out of the range, said apart
            lines.append(f"crack tip {p.tip_peak_von_mises_MPa:.4g} MPa: singular, within {p.tip_radius_mm:.3g} mm "
                         "of the front, left out of the factor")
        if p.corner_peak_von_mises_MPa is not None:
            lines.append(f"sharp corner {p.corner_peak_von_mises_MPa:.4g} MPa: singular, within "
                         f"{p.corner_radius_mm:.3g} mm of it, left out of the factor")
        top = colour_top(np.asarray(mesh.point_data[names.von_mises], float), p.peak_von_mises_MPa)
        if top < p.peak_von_mises_MPa:
            lines.append(f"colours to {top:.4g} MPa, the {SPIKE_PERCENTILE:g}th percentile (white above): a local "
                         "peak would leave the body one colour")
        plotter = off_screen_plotter(RenderSettings(window, shape=shape))
        peak_index = p.peak_node if p.peak_node >= 0 else int(np.argmax(np.asarray(mesh.point_data[names.von_mises])))
        legend: list[str] = []
        for col, z in [(0, None)] + ([(1, zoom)] if zoom is not None else []):
            plotter.subplot(0, col)
            region = shown
            if z is not None:
                c, r = shown.points[peak_index], z.radius_mm
                region = shown.clip_box([c[0] - r, c[0] + r, c[1] - r, c[1] + r, c[2] - r, c[2] + r], invert=False)
                if region.n_points == 0:
                    raise ValueError(f"{vtu}: nothing within {r:g} mm of the peak")
            plotter.add_mesh(region, scalars=names.von_mises, cmap="turbo", show_edges=False,
                             scalar_bar_args=_bar("von Mises (MPa)"), show_scalar_bar=col == 0,
                             clim=(0.0, top), above_color="white")
            if z is None:
                legend = _draw_marks(pv, plotter, shown, groups, marks, names.displacement, at.load.scale,
                                     exaggeration)
            plotter.add_point_labels([shown.points[peak_index]], ["peak"], font_size=16, point_color="white",
                                     point_size=12, render_points_as_spheres=True, always_visible=True)
            plotter.add_axes(color="black", line_width=3, labels_off=False)
            _view(plotter, plane, view_from)
            plotter.reset_camera()
            if z is None:
                plotter.camera.zoom(0.85 if len(lines) <= 4 else 0.72)   # room for the title lines above the model
            if z is not None:
                plotter.add_text(f"{z.title} ({2 * z.radius_mm:.3g} mm box)" + (f"\n{section}" if section else ""),
                                 font_size=TITLE_PT, color="black")
            else:
                plotter.add_text(title_text(lines), font_size=TITLE_PT, color="black")
        image = plotter.screenshot(None, return_img=True)
        plotter.close()
    atomic_write_bytes(png, _png_bytes(image))
    caption = " ".join(lines) + (f" ({'; '.join(legend)})" if legend else "")
    return Rendered(Path(png), caption, exaggeration)


def render_closeup(vtu: Path, png: Path, *, label: str, center_mm=None, radius_mm: float | None = None,
                   near_z_mm: float | None = None, section: str = "", load: RatedLoad | None = None) -> Rendered:
    """Close-up of the crack tip: the region around the stress peak (or ``center_mm``), undeformed, at the
    rated ``load`` (the field x its scale; None: as solved).

    ``near_z_mm`` restricts the peak search to a slab around the crack plane z (loads and supports
    elsewhere have their own stress peaks). ``section`` is said on a planar field (e.g. the axisymmetric
    (r, z) section of the shaft). The tip's peak is singular (it grows with refinement): no safety factor here.
    """
    import pyvista as pv

    with pv.VtkErrorCatcher(raise_errors=True):
        mesh = scaled_to_rated(read_field(vtu), load.scale if load is not None else 1.0)
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
        # the tip's singular peak would leave the rest of the map one colour: the range stops at the 99th
        # percentile of the nodes shown, and the caption gives the tip value
        shown_vm = np.asarray(region.point_data[names.von_mises], dtype=float)
        top, tip = float(np.percentile(shown_vm, 99.0)), float(shown_vm.max())
        plotter = off_screen_plotter(RenderSettings(WINDOW))
        plotter.add_mesh(region, scalars=names.von_mises, cmap="turbo", show_edges=False,
                         scalar_bar_args=_bar("von Mises (MPa)"), clim=(0.0, top), above_color="white")
        plotter.add_mesh(region.extract_feature_edges(), color="black", line_width=1)
        plotter.add_axes(color="black", line_width=3)
        _view(plotter, plane)
        plotter.reset_camera()
        plotter.camera.zoom(0.8)   # room for the title lines above the region
        at = f" at {load.name} = {load.rated:.4g} {load.unit}" if load is not None else " as solved"
        text = (f"{label}: crack-tip close-up{at},\n{2 * radius:.3g} mm box at "
                f"({center[0]:.3g}, {center[1]:.3g}, {center[2]:.3g}) mm, undeformed;\ncolours to the 99th "
                f"percentile {top:.3g} MPa (white above; tip {tip:.3g} MPa, singular)"
                + (f";\n{section}" if section and plane else ""))
        plotter.add_text(text, font_size=TITLE_PT, color="black")
        image = plotter.screenshot(None, return_img=True)
        plotter.close()
    atomic_write_bytes(png, _png_bytes(image))
    return Rendered(Path(png), text.replace("\n", " "), None)


def render_signed(vtu: Path, png: Path, *, label: str, array: str, words: str, load: RatedLoad,
                  view_from=None) -> Rendered:
    """A signed stress ``array`` of ``vtu`` at the rated load on the deformed shape: tension red, compression
    blue, one range symmetric about zero; the largest tension and compression marked and printed."""
    import pyvista as pv

    with pv.VtkErrorCatcher(raise_errors=True):
        mesh = scaled_to_rated(read_field(vtu), load.scale)
        if array not in mesh.point_data:
            raise ValueError(f"{vtu}: no point array {array!r}")
        names = field_names(mesh)
        values = np.asarray(mesh.point_data[array], dtype=float)
        plane = bool(np.ptp(mesh.points[:, 2]) == 0.0)
        exaggeration = auto_exaggeration(mesh, names.displacement) if names.displacement else 1.0
        shown = _deformed(mesh, names.displacement, exaggeration)
        hi, lo = int(np.argmax(values)), int(np.argmin(values))
        where = {k: "(" + ", ".join(f"{x:.4g}" for x in mesh.points[k]) + ") mm" for k in (hi, lo)}
        lines = [f"{label}: {words}", f"at {load.name} = {load.rated:.4g} {load.unit}",
                 f"displacements x {exaggeration:g}; red tension, blue compression",
                 f"tension up to {values[hi]:.4g} MPa at {where[hi]},",
                 f"compression down to {values[lo]:.4g} MPa at {where[lo]}"]
        top = max(abs(values[hi]), abs(values[lo])) or 1.0
        plotter = off_screen_plotter(RenderSettings(WINDOW))
        plotter.add_mesh(shown, scalars=array, cmap="coolwarm", clim=(-top, top), scalar_bar_args=_bar(f"{words} (MPa)"))
        plotter.add_point_labels(shown.points[[hi, lo]], ["max tension", "max compression"], font_size=16,
                                 point_color="black", point_size=12, render_points_as_spheres=True,
                                 always_visible=True)
        plotter.add_axes(color="black", line_width=3, labels_off=False)
        _view(plotter, plane, view_from)
        plotter.reset_camera()
        plotter.camera.zoom(0.72)   # room for the title lines above the model
        plotter.add_text("\n".join(lines), font_size=TITLE_PT, color="black")
        image = plotter.screenshot(None, return_img=True)
        plotter.close()
    atomic_write_bytes(png, _png_bytes(image))
    return Rendered(Path(png), " ".join(lines), exaggeration)


def crack_face_opening(vtu: Path):
    """(crack face with ``opening_um`` = 2 u_z in um and ``on_front`` (1 on the nodes it shares with the ligament),
    ligament or None) of a crack on the symmetry plane z = 0 (its boundary groups ``crack`` and ``ligament``):
    the mirror face moves by -u_z, so the faces part by 2 u_z."""
    from strainwave.fea.fields import VOLUME_POINT_ID

    groups = boundary_groups(vtu, ("crack", "ligament"))
    if "crack" not in groups:
        raise ValueError(f"{vtu}: no 'crack' boundary group")
    face, ligament = groups["crack"], groups.get("ligament")
    names = field_names(face)
    if names.displacement is None:
        raise ValueError(f"{vtu}: the crack face carries no displacement")
    face.point_data["opening_um"] = 2e3 * displacement3(face, names.displacement)[:, 2]
    shared = np.asarray(ligament.point_data[VOLUME_POINT_ID]) if ligament is not None else np.zeros(0, int)
    face.point_data["on_front"] = np.isin(np.asarray(face.point_data[VOLUME_POINT_ID]), shared).astype(np.int8)
    return face, ligament


OPEN_OVER_MAX = 1e-3    # a crack-face node counts as open where it parts by more than this x the largest opening


def render_crack_opening(vtus: dict[str, Path], png: Path, *, label: str) -> Rendered:
    """The crack plane seen along its normal, one panel per state ({state: VTU}): the crack face coloured by
    its opening 2 u_z (one colour range for all states), the ligament grey, the face's outline black."""
    import pyvista as pv

    with pv.VtkErrorCatcher(raise_errors=True):
        faces = {state: crack_face_opening(vtu) for state, vtu in vtus.items()}
        top = max(float(np.max(f.point_data["opening_um"])) for f, _ in faces.values())
        if not top > 0:
            raise ValueError(f"{label}: the crack is shut in every state drawn")
        plotter = off_screen_plotter(RenderSettings((WINDOW[0] * len(faces), WINDOW[1]), shape=(1, len(faces))))
        texts = []
        for col, (state, (face, ligament)) in enumerate(faces.items()):
            plotter.subplot(0, col)
            opening = np.asarray(face.point_data["opening_um"])
            inside = opening[np.asarray(face.point_data["on_front"]) == 0]   # the front never opens
            share = float(np.mean(inside > OPEN_OVER_MAX * top))
            text = (f"{state}: opening up to {opening.max():.3g} um, {100 * share:.0f} % of the crack face open "
                    "(nodes off the front)")
            texts.append(text)
            if ligament is not None:
                plotter.add_mesh(ligament, color="lightgrey")
            plotter.add_mesh(face, scalars="opening_um", cmap="turbo", clim=(0.0, top), show_scalar_bar=col == 0,
                             scalar_bar_args=_bar("opening 2 u_z (um)"))
            plotter.add_mesh(face.extract_feature_edges(boundary_edges=True, feature_edges=False,
                                                        manifold_edges=False), color="black", line_width=3)
            plotter.add_axes(color="black", line_width=3)
            plotter.view_xy()
            plotter.reset_camera()
            plotter.camera.zoom(0.8)   # room for the title lines above the plane
            plotter.add_text(f"{label}\n{text}", font_size=TITLE_PT, color="black")
        image = plotter.screenshot(None, return_img=True)
        plotter.close()
    atomic_write_bytes(png, _png_bytes(image))
    caption = (f"{label}: the crack plane z = 0 seen along its normal (x along the surface, y into the wall from the "
               "surface at y = 0), crack face coloured by its opening 2 u_z, ligament grey; " + "; ".join(texts))
    return Rendered(Path(png), caption, None)


def sample_circle(vtu: Path, radius_mm: float, n: int = 360) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """Radial and tangential displacement along a circle of the (plane or mid-plane) ring mesh.

    Returns (theta, u_r, u_t) at the SOLVED load (the checks' load) for the points that lie inside the mesh, or
    None without a displacement field.
    """
    import pyvista as pv

    with pv.VtkErrorCatcher(raise_errors=True):
        mesh = scaled_to_rated(read_field(vtu), 1.0)   # at the solved load, as the checks' delta_CD, delta_AB
        names = field_names(mesh)
        if names.displacement is None:
            return None
        z_mid = 0.5 * (mesh.bounds[4] + mesh.bounds[5])
        theta = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
        pts = np.column_stack([radius_mm * np.cos(theta), radius_mm * np.sin(theta), np.full(n, z_mid)])
        probe = pv.PolyData(pts).sample(mesh)
        valid = np.asarray(probe.point_data["vtkValidPointMask"], dtype=bool)
        u = displacement3(probe, names.displacement)
    radial = u[:, 0] * np.cos(theta) + u[:, 1] * np.sin(theta)
    tangential = -u[:, 0] * np.sin(theta) + u[:, 1] * np.cos(theta)
    return theta[valid], radial[valid], tangential[valid]
