"""Mesh build123d parts (3D) and plane sections (2D) with gmsh inside a session.

The solid is handed over as BREP (unitless, so millimetres stay millimetres) and imported with OCC;
named faces from ``geometry/`` are matched to gmsh surfaces by centre of mass and area and become
physical groups. Quadratic meshes keep gmsh's geometry-following mid nodes (``Mesh.SecondOrderLinear``
= 0): on the hollow shaft, curved P2 reaches -0.0014 % twist error where straight P2 needs far more dofs.
"""
from __future__ import annotations

import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np

from strainwave.fea.mesh_data import MeshData
from strainwave.fea.result import MeshQuality

# gmsh element type ids
_CELL_TYPES = {(3, 1): 4, (3, 2): 11, (2, 1): 2, (2, 2): 9}


class MeshingFailed(RuntimeError):
    """gmsh could not import, match or mesh the geometry; studies turn it into a StageError."""


class MeshLimitExceeded(MeshingFailed):
    """The meshing child (fea/session.py) passed its wall time or memory limit, or died: a retry will not help."""


@dataclass(frozen=True)
class Refine:
    """Local size: ``size_mm`` within ``dist_min_mm`` of the targets, growing to the global size at
    ``dist_max_mm`` (gmsh Distance + Threshold fields). Targets: points and/or named groups."""

    size_mm: float
    dist_min_mm: float
    dist_max_mm: float
    points_mm: tuple[tuple[float, float, float], ...] = ()
    groups: tuple[str, ...] = ()
    along_curves: bool = True     # False: a corner point refines around itself, not along its edges


def _export_brep(shape, path: Path) -> None:
    if hasattr(shape, "wrapped"):
        import build123d as bd
        if not bd.export_brep(shape, str(path)):
            raise MeshingFailed("BREP export of the build123d shape failed")
    else:  # a bare OCP TopoDS_Shape
        from OCP.BRepTools import BRepTools
        BRepTools.Write_s(shape, str(path))


def import_shape(model, shape) -> None:
    """An OCC shape into the gmsh ``model`` (through a BREP file: gmsh's own OCC, not build123d's)."""
    with tempfile.TemporaryDirectory(prefix="strainwave-brep-") as tmp:
        path = Path(tmp) / "shape.brep"
        _export_brep(shape, path)
        model.occ.importShapes(str(path), highestDimOnly=False)
    model.occ.synchronize()


def _match(model, dim: int, refs, tol_mm: float, rel_tol: float = 1e-3) -> list[int]:
    """Entity tags of dimension ``dim`` whose centre of mass and measure match ``refs``.

    ``refs`` is a tuple of FaceRef (centre, area or length) or ONE callable: for curves it gets (21, 3)
    points sampled along the curve, for surfaces the centre of mass (3,); it returns True to select."""
    tags = []
    if callable(refs):
        if dim == 1:  # curves: the predicate sees 21 points sampled along the curve (arcs have off-curve centres)
            def samples(t):
                lo, hi = model.getParametrizationBounds(1, t)
                return np.asarray(model.getValue(1, t, np.linspace(lo[0], hi[0], 21))).reshape(-1, 3)
            return [t for _, t in model.getEntities(1) if refs(samples(t))]
        return [t for _, t in model.getEntities(dim) if refs(np.array(model.occ.getCenterOfMass(dim, t)))]
    entities = [(t, np.array(model.occ.getCenterOfMass(dim, t)), model.occ.getMass(dim, t))
                for _, t in model.getEntities(dim)]
    for ref in refs:
        c_ref = np.asarray(ref.center_mm, float)
        hits = [t for t, c, m in entities
                if np.linalg.norm(c - c_ref) <= tol_mm and abs(m - ref.area_mm2) <= rel_tol * max(ref.area_mm2, 1e-12)]
        if not hits:
            best = min(entities, key=lambda e: np.linalg.norm(e[1] - c_ref))
            raise MeshingFailed(f"no gmsh entity (dim {dim}) matches centre {tuple(c_ref)} measure {ref.area_mm2:g}; "
                                f"nearest: centre {tuple(np.round(best[1], 4))} measure {best[2]:g}")
        tags.extend(hits)
    return sorted(set(tags))


def _size_fields(model, size_mm: float, refine: Sequence[Refine], group_tags: Mapping[str, list[int]],
                 dim: int) -> None:
    thresholds = []
    for r in refine:
        fd = model.mesh.field.add("Distance")
        if r.points_mm:
            pts = [model.occ.addPoint(*p) for p in r.points_mm]
            model.occ.synchronize()
            model.mesh.field.setNumbers(fd, "PointsList", pts)
            # the curves through the points (crack-front edges) refine along their whole length
            near = []
            for _, c in (model.getEntities(1) if r.along_curves else ()):
                d = min(np.linalg.norm(np.array(model.getClosestPoint(1, c, p)[0]) - p) for p in r.points_mm)
                if d <= 0.5 * r.size_mm:
                    near.append(c)
            if near:
                model.mesh.field.setNumbers(fd, "CurvesList", near)
                # samples at most half the size apart: a fixed count left gaps (docs/decisions/005-meshing-algorithm.md)
                longest = max(model.occ.getMass(1, c) for c in near)
                model.mesh.field.setNumber(fd, "Sampling", int(np.clip(np.ceil(2 * longest / r.size_mm), 100, 20000)))
        tags = [t for g in r.groups for t in group_tags[g]]
        if tags:
            model.mesh.field.setNumbers(fd, "SurfacesList" if dim == 3 else "CurvesList", tags)
        ft = model.mesh.field.add("Threshold")
        model.mesh.field.setNumber(ft, "InField", fd)
        model.mesh.field.setNumber(ft, "SizeMin", r.size_mm)
        model.mesh.field.setNumber(ft, "SizeMax", size_mm)
        model.mesh.field.setNumber(ft, "DistMin", r.dist_min_mm)
        model.mesh.field.setNumber(ft, "DistMax", r.dist_max_mm)
        thresholds.append(ft)
    if thresholds:
        fm = model.mesh.field.add("Min")
        model.mesh.field.setNumbers(fm, "FieldsList", thresholds)
        model.mesh.field.setAsBackgroundMesh(fm)
        import gmsh
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)


# gmsh's default: tetrahedra below this quality are optimised
OPTIMIZE_THRESHOLD = 0.3


def _options(size_mm: float, optimize_threshold: float = OPTIMIZE_THRESHOLD) -> None:
    import gmsh
    gmsh.option.setNumber("Mesh.MeshSizeMax", size_mm)
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0.0)
    gmsh.option.setNumber("Mesh.SecondOrderLinear", 0)     # mid nodes on the true geometry
    gmsh.option.setNumber("Mesh.Algorithm", 6)             # Frontal-Delaunay 2D
    # HXT in one thread: faster than Delaunay, a better worst element, and deterministic (docs/decisions/005-meshing-algorithm.md)
    gmsh.option.setNumber("Mesh.Algorithm3D", 10)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.Optimize", 1)
    gmsh.option.setNumber("Mesh.OptimizeThreshold", optimize_threshold)
    # setOrder's closing check only logs; _straighten_inverted checks itself (docs/decisions/005-meshing-algorithm.md)
    gmsh.option.setNumber("Mesh.HighOrderSkipQualityCheck", 1)


def generate(model, dim: int, order: int, *, size_mm: float, refine: Sequence[Refine] | None = None,
             group_tags: Mapping[str, list[int]] | None = None,
             optimize_threshold: float = OPTIMIZE_THRESHOLD, preload_kernels: bool = True) -> None:
    """Options, size fields and meshing of the synchronised ``model``; gmsh errors -> MeshingFailed.

    The one meshing tail of every builder here and of other fea modules that draw their own geometry
    (e.g. the axisymmetric shaft section). ``optimize_threshold``: tetrahedra below this quality are
    optimised (gmsh's Mesh.OptimizeThreshold). ``preload_kernels``: a P2 tetrahedral mesh that will reach
    ``fused_sweeps.MIN_DOFS`` loads the assembly's numba kernels beside setOrder (False where another
    process assembles it: mesh_isolated's child)."""
    _options(size_mm, optimize_threshold)
    _size_fields(model, size_mm, refine or (), group_tags or {}, dim)
    try:
        _generate(model, dim, order, preload_kernels)
    except Exception as exc:  # gmsh raises plain Exception with its log message
        reason = str(exc).strip() or f"{type(exc).__name__} without a message (gmsh gives none when out of memory)"
        raise MeshingFailed(f"gmsh meshing failed: {reason}") from exc


# P2 nodes per vertex, the lowest seen: errs towards not loading the kernels (docs/decisions/005-meshing-algorithm.md).
P2_NODES_PER_VERTEX = 6.0


def expected_p2_dofs(n_vertices: int) -> int:
    """Displacement dofs the linear tetrahedral mesh of ``n_vertices`` will have once curved to P2."""
    return int(3 * P2_NODES_PER_VERTEX * n_vertices)


def _generate(model, dim: int, order: int, preload_kernels: bool = True) -> None:
    model.mesh.generate(dim)
    if order == 2:
        if preload_kernels and dim == 3:
            from strainwave.fea import fused_sweeps
            # the assembly of a system this large runs numba kernels: they load beside setOrder, which runs
            # in C++ with the interpreter lock released
            if expected_p2_dofs(len(model.mesh.getNodes()[0])) >= fused_sweeps.MIN_DOFS:
                fused_sweeps.warm_up_assembly()
        model.mesh.setOrder(2)
        _straighten_inverted(model, dim)


def _straighten_inverted(model, dim: int, passes: int = 4) -> None:
    """Put the mid nodes of inverted curved elements back on their straight edges.

    Curving P2 nodes onto the geometry can invert an element whose size exceeds the local radius or wall
    (coarse meshes of the thin cup, slivers at a crack slot). gmsh's ``optimize("HighOrder")`` may abort
    the whole process in that case (an uncaught C++ exception, seen on the cup), so the fix is local:
    only those elements lose their curvature, and the edges they share with neighbours stay conforming.
    """
    import gmsh
    cell_type = _CELL_TYPES[(dim, 2)]
    pairs = {3: ((0, 1), (1, 2), (2, 0), (3, 0), (3, 2), (3, 1)), 2: ((0, 1), (1, 2), (2, 0))}[dim]
    nv = dim + 1
    for _ in range(passes):
        tags, nodes = model.mesh.getElementsByType(cell_type)
        if tags.size == 0:
            return
        q = np.asarray(gmsh.model.mesh.getElementQualities(tags, "minSJ"))
        bad = np.flatnonzero(q <= 0.0)
        if bad.size == 0:
            return
        conn = nodes.reshape(tags.size, -1)[bad]
        done = set()
        for row in conn:
            for j, (a, b) in enumerate(pairs):
                mid = int(row[nv + j])
                if mid in done:
                    continue
                done.add(mid)
                xa = np.asarray(model.mesh.getNode(int(row[a]))[0])
                xb = np.asarray(model.mesh.getNode(int(row[b]))[0])
                model.mesh.setNode(mid, list(0.5 * (xa + xb)), [])


def extract(model, dim: int, order: int, group_tags: Mapping[str, tuple[int, list[int]]], h_mm: float) -> MeshData:
    """The meshed model as MeshData with the named groups (name -> (dim, entity tags))."""
    import gmsh
    node_tags, coords, _ = model.mesh.getNodes()
    coords = coords.reshape(-1, 3)
    tag_to_row = np.full(int(node_tags.max()) + 1, -1, dtype=np.int64)
    tag_to_row[node_tags] = np.arange(node_tags.size)
    etypes, etags, enodes = model.mesh.getElements(dim)
    want = _CELL_TYPES[(dim, order)]
    if want not in list(etypes):
        raise MeshingFailed(f"gmsh produced no {dim}D elements of order {order} (types {list(etypes)})")
    k = list(etypes).index(want)
    cell_tags = etags[k]
    cells = tag_to_row[enodes[k]].reshape(cell_tags.size, -1)
    # the sorted used rows by a mask, far cheaper than np.unique's hash (docs/decisions/005-meshing-algorithm.md)
    used = np.flatnonzero(np.bincount(cells.ravel(), minlength=node_tags.size))
    compact = np.full(node_tags.size, -1, dtype=np.int64)
    compact[used] = np.arange(used.size)
    cells = compact[cells]
    groups = {}
    for name, (gdim, tags) in group_tags.items():
        blocks = []
        for t in tags:
            ft, _, fn = model.mesh.getElements(gdim, t)
            for typ, nodes in zip(ft, fn):
                n_per = gmsh.model.mesh.getElementProperties(typ)[3]
                blocks.append(compact[tag_to_row[nodes]].reshape(-1, n_per))
        if blocks:
            arr = np.vstack(blocks) if len({b.shape[1] for b in blocks}) == 1 else np.vstack([b[:, :1] for b in blocks])
            if (arr < 0).any():
                raise MeshingFailed(f"group {name!r} has nodes outside the {dim}D mesh")
            groups[name] = arr
    q = gmsh.model.mesh.getElementQualities(cell_tags, "minSICN")
    quality = MeshQuality(elements=int(cell_tags.size), nodes=int(used.size), dofs=int(used.size * dim),
                          order=order, min_quality=float(q.min()), mean_quality=float(q.mean()))
    nodes = coords[used]
    return MeshData(nodes_mm=nodes, cells=cells, dim=dim, order=order, groups=groups, quality=quality, h_mm=h_mm)


def mesh_part(model, part, *, size_mm: float, order: int = 2, refine: Sequence[Refine] | None = None,
              match_tol_mm: float | None = None, optimize_threshold: float = OPTIMIZE_THRESHOLD,
              preload_kernels: bool = True) -> MeshData:
    """Tetrahedral mesh of ``part.solid`` with one physical group per entry of ``part.named_faces``.

    Parameters
    ----------
    model : the ``gmsh.model`` yielded by ``gmsh_session``.
    part : ``geometry.part.Part`` (solid in mm, named faces as FaceRef tuples). A part with a
        ``crack_surface`` (CrackModel.SEAM) gets it embedded as the conforming internal group "crack".
    size_mm : global element size; ``refine`` adds local sizes (crack front points, named faces).
    order : 1 (straight P1) or 2 (curved P2).
    optimize_threshold : tetrahedra below this quality are optimised (see ``generate``).
    preload_kernels : see ``generate``.
    """
    import_shape(model, part.solid)
    if not model.getEntities(3):
        raise MeshingFailed(f"{part.name}: the BREP holds no volume")
    bbox = np.array(model.getBoundingBox(-1, -1))
    tol = match_tol_mm if match_tol_mm is not None else 1e-4 * np.linalg.norm(bbox[3:] - bbox[:3]) + 1e-6
    if getattr(part, "crack_surface", None) is not None:
        group_tags = _embed_crack(model, part.crack_surface, part.named_faces, tol)
    else:
        group_tags = {name: _match(model, 2, refs, tol) for name, refs in part.named_faces.items()}
    for name, tags in group_tags.items():
        model.addPhysicalGroup(2, tags, name=name)
    model.addPhysicalGroup(3, [t for _, t in model.getEntities(3)], name="solid")
    generate(model, 3, order, size_mm=size_mm, refine=refine, group_tags=group_tags,
             optimize_threshold=optimize_threshold, preload_kernels=preload_kernels)
    return extract(model, 3, order, {n: (2, t) for n, t in group_tags.items()}, size_mm)


def _embed_crack(model, face, named_faces, tol_mm: float) -> dict[str, list[int]]:
    """Fragment the volume with the crack face so that the face becomes a conforming internal surface,
    and match the named faces again on the fragmented model.

    Faces the crack mouth does not split keep their centre and area (an internal edge does not change
    them; the bearing's contact patch) and match as before. A split face (the shaft's outer cylinder,
    cut in two by a full circumferential mouth) is matched piece by piece: same surface type, inside the
    original's bounding box. (gmsh's ``out_map`` is not used: with the volume's faces passed as objects
    it returned tags that no longer held those faces.) Crack pieces outside the solid (the face reaches
    beyond the free surface) are not embedded by the fragment and are removed. Returns the named groups
    plus "crack" (the embedded pieces)."""
    before = {}
    for name, refs in named_faces.items():
        tags = _match(model, 2, refs, tol_mm)
        before[name] = [(model.getType(2, t), np.array(model.getBoundingBox(2, t)), model.occ.getMass(2, t))
                        for t in tags]
    with tempfile.TemporaryDirectory(prefix="strainwave-brep-") as tmp:
        path = Path(tmp) / "crack.brep"
        _export_brep(face, path)
        tool = model.occ.importShapes(str(path), highestDimOnly=True)
    model.occ.synchronize()
    vols = model.getEntities(3)
    _, out_map = model.occ.fragment(vols, tool)
    model.occ.synchronize()
    pieces = sorted({t for k in range(len(vols), len(out_map)) for d, t in out_map[k] if d == 2})
    embedded = {t for _, v in model.getEntities(3) for d, t in model.mesh.getEmbedded(3, v) if d == 2}
    inside = [t for t in pieces if t in embedded]
    outside = [(2, t) for t in pieces if t not in embedded]
    if not inside:
        raise MeshingFailed("the crack surface does not lie inside the solid (nothing to embed)")
    if outside:
        model.occ.remove(outside, recursive=True)
        model.occ.synchronize()
    free = {t for _, t in model.getEntities(2)} - set(inside)
    group_tags: dict[str, list[int]] = {}
    split = {}
    for name, refs in named_faces.items():
        try:
            group_tags[name] = _match(model, 2, refs, tol_mm)
        except MeshingFailed:
            split[name] = before[name]
    free -= {t for tags in group_tags.values() for t in tags}
    # smallest original first: a piece inside two candidates' boxes belongs to the tighter one
    for name, olds in sorted(split.items(), key=lambda kv: min(np.prod(o[1][3:] - o[1][:3] + tol_mm) for o in kv[1])):
        got = []
        for kind, box, _ in olds:
            for t in sorted(free):
                b = np.array(model.getBoundingBox(2, t))
                if model.getType(2, t) == kind and (b[:3] >= box[:3] - tol_mm).all() and (b[3:] <= box[3:] + tol_mm).all():
                    got.append(t)
                    free.discard(t)
        area = sum(model.occ.getMass(2, t) for t in got)
        want = sum(o[2] for o in olds)
        if abs(area - want) > 1e-3 * want:
            raise MeshingFailed(f"named face set {name!r}: pieces after embedding the crack cover {area:g} "
                                f"of {want:g} mm^2")
        group_tags[name] = sorted(got)
    group_tags["crack"] = inside
    return group_tags


def _surface_from_loops(model, loops: Sequence[np.ndarray]) -> int:
    curve_loops = []
    for loop in loops:
        loop = np.asarray(loop, float)
        pts = [model.occ.addPoint(x, y, 0.0) for x, y in loop[:, :2]]
        lines = [model.occ.addLine(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))]
        curve_loops.append(model.occ.addCurveLoop(lines))
    return model.occ.addPlaneSurface(curve_loops)


def mesh_section(model, face=None, *, loops: Sequence[np.ndarray] | None = None, size_mm: float, order: int = 2,
                 named_edges: Mapping[str, object] | None = None,
                 named_points: Mapping[str, Sequence[tuple[float, float]]] | None = None,
                 refine: Sequence[Refine] | None = None, match_tol_mm: float | None = None) -> MeshData:
    """Triangle mesh of a plane section in the xy plane (plane stress / strain problems).

    Parameters
    ----------
    face : a build123d Face (exact curves, so P2 nodes follow circles), or None to use ``loops``.
    loops : polylines (n, 2); the first is the outer boundary, the others holes.
    named_edges : name -> tuple of FaceRef (centre, LENGTH in ``area_mm2``) or a predicate on (21, 3) points
        sampled along a curve -> bool (robust when ``named_points`` split curves). Each becomes a group of
        boundary edges (line2/line3 node rows).
    named_points : name -> points; each point is fragmented into the geometry (split boundary curves or
        embedded inside), so a node sits exactly there; the group holds those nodes as (k, 1) rows.
    """
    if face is not None:
        import_shape(model, face)
    elif loops:
        _surface_from_loops(model, loops)
        model.occ.synchronize()
    else:
        raise ValueError("mesh_section needs a face or loops")
    point_tags = {}
    if named_points:
        surfaces = model.getEntities(2)
        new = {name: [model.occ.addPoint(x, y, 0.0) for x, y in pts] for name, pts in named_points.items()}
        out, out_map = model.occ.fragment(surfaces, [(0, t) for ts in new.values() for t in ts])
        model.occ.synchronize()
        flat = [t for ts in new.values() for t in ts]
        for name, ts in new.items():
            point_tags[name] = sorted({dt[1] for t in ts for dt in out_map[len(surfaces) + flat.index(t)]})
    if not model.getEntities(2):
        raise MeshingFailed("the section holds no surface")
    bbox = np.array(model.getBoundingBox(-1, -1))
    tol = match_tol_mm if match_tol_mm is not None else 1e-4 * np.linalg.norm(bbox[3:] - bbox[:3]) + 1e-6
    group_tags = {}
    for name, refs in (named_edges or {}).items():
        tags = _match(model, 1, refs, tol)
        if not tags:
            raise MeshingFailed(f"named edge set {name!r} matches no curve")
        model.addPhysicalGroup(1, tags, name=name)
        group_tags[name] = tags
    for name, tags in point_tags.items():
        model.addPhysicalGroup(0, tags, name=name)
    model.addPhysicalGroup(2, [t for _, t in model.getEntities(2)], name="section")
    generate(model, 2, order, size_mm=size_mm, refine=refine, group_tags=group_tags)
    groups = {n: (1, t) for n, t in group_tags.items()}
    groups.update({n: (0, t) for n, t in point_tags.items()})
    return extract(model, 2, order, groups, size_mm)
