"""Thin wrappers over OCC booleans that do NOT unify same-domain faces.

build123d's operators call ``clean()`` (ShapeUpgrade_UnifySameDomain) after a boolean, which merges
coplanar or co-cylindrical faces. The parts rely on split faces (the torque band of the cup, the
contact strips and patches), so fusing and cutting go through these helpers instead.
"""
from __future__ import annotations


def _boolean(op, a, tools, glue: bool = False):
    """``op`` run on bare OCC shapes (``TopoDS_Shape``); the result is a bare shape too."""
    from OCP.collections import List_TopoDS_Shape

    args, tls = List_TopoDS_Shape(), List_TopoDS_Shape()
    args.Append(a)
    for t in tools:
        tls.Append(t)
    op.SetArguments(args)
    op.SetTools(tls)
    op.SetRunParallel(False)      # the machine's two cores are shared; OCC threads do not pay here
    op.SetUseOBB(True)            # oriented boxes prune face pairs better on the 1400-face toothed cup
    if glue:
        # touching shapes: "shift" gluing skips the face/face intersection (docs/decisions/015-cad-build-speed.md)
        from OCP.BOPAlgo import BOPAlgo_GlueEnum
        op.SetGlue(BOPAlgo_GlueEnum.BOPAlgo_GlueShift)
    op.Build()
    if not op.IsDone():
        raise RuntimeError(f"OCC boolean {type(op).__name__} failed")
    return op.Shape()


def _run(op, a, tools, glue: bool = False):
    from build123d import Shape

    return Shape.cast(_boolean(op, a.wrapped, [t.wrapped for t in tools], glue))


def single_solid(shape):
    """The one Solid inside ``shape`` (a boolean result is often a Compound of one Solid)."""
    solids = shape.solids()
    if len(solids) != 1:
        raise RuntimeError(f"expected one solid, got {len(solids)}")
    return solids[0]


def fuse(a, *tools, touching: bool = False):
    """Union; ``touching=True`` when the solids share faces but do not overlap in volume (glue mode)."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Fuse
    return single_solid(_run(BRepAlgoAPI_Fuse(), a, tools, glue=touching))


def cut(a, *tools):
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut
    return single_solid(_run(BRepAlgoAPI_Cut(), a, tools))


def cut_bare(a, *tools):
    """``cut`` of bare OCC shapes, without build123d (whose import costs far more than OCP's): the same
    boolean and the same solid, as a ``TopoDS_Solid`` (docs/decisions/013-sweep-worker-start-up.md)."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    found, explorer = {}, TopExp_Explorer(_boolean(BRepAlgoAPI_Cut(), a, tools), TopAbs_SOLID)
    while explorer.More():
        found[hash(explorer.Current())] = explorer.Current()   # what build123d's solids() keeps
        explorer.Next()
    if len(found) != 1:
        raise RuntimeError(f"expected one solid, got {len(found)}")
    return TopoDS.Solid(next(iter(found.values())))


def imprint(a, *faces):
    """Split the faces of solid ``a`` by faces lying on its surface (an imprint; the solid stays whole)."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Splitter
    result = _run(BRepAlgoAPI_Splitter(), a, faces)
    return max(result.solids(), key=lambda s: s.volume)


def sew_solid(faces, expected_faces: int, tol_mm: float = 1e-6):
    """The closed solid bounded by ``faces`` (build123d faces that meet edge to edge, an edge of one may be
    split on its neighbour), or None unless sewing gives one shell of ``expected_faces`` faces without
    free or multiply shared edges. Joins solids that touch on one face without a boolean over all faces."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeSolid, BRepBuilderAPI_Sewing
    from OCP.BRepLib import BRepLib
    from OCP.TopAbs import TopAbs_SHELL
    from OCP.TopoDS import TopoDS
    from build123d import Shape

    sewing = BRepBuilderAPI_Sewing(tol_mm)
    for face in faces:
        sewing.Add(face.wrapped)
    sewing.Perform()
    shell = sewing.SewedShape()
    if shell.ShapeType() != TopAbs_SHELL or sewing.NbFreeEdges() or sewing.NbMultipleEdges():
        return None
    solid = BRepBuilderAPI_MakeSolid(TopoDS.Shell(shell)).Solid()
    if not BRepLib.OrientClosedSolid_s(solid):    # outward normals, whichever way the shell came out
        return None
    solid = Shape.cast(solid)
    return solid if len(solid.faces()) == expected_faces else None
