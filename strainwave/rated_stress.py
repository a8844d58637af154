"""A study's stress field at its rated load: peak von Mises and where, peak displacement, fatigue safety factor.

Read from the study's own VTU field (the finest mesh) and scaled by rated / solved load (linear elasticity).
Both ``strainwave solve`` and the validation report state these numbers; the pictures draw the same scaled
field (``compare/validate/images.py``).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from strainwave.analytic.rated_load import RatedLoad, fatigue_safety_factor
from strainwave.registry import study as registered

__all__ = ["read_vtu", "FieldNames", "field_names", "displacement3", "applied_scale", "scaled_to_rated",
           "write_at_rated", "FieldPeaks", "field_peaks", "StressAtRated", "stress_field_of", "rated_load", "rated_load_of", "stress_at_rated", "groups_at_node"]


def read_vtu(vtu: Path):
    """The mesh of ``vtu`` (one place that reads a field file, so pyvista is imported only when one is read)."""
    import pyvista as pv

    return pv.read(str(vtu))


@dataclass(frozen=True)
class FieldNames:
    displacement: str | None
    von_mises: str | None


def field_names(mesh) -> FieldNames:
    """The displacement and von Mises arrays of a VTU the studies wrote (names carry units: *_mm, *_MPa)."""
    keys = list(mesh.point_data.keys()) + list(mesh.cell_data.keys())
    disp = next((k for k in keys if k.lower().startswith("disp")), None)
    mises = next((k for k in keys if "mises" in k.lower()), None)
    return FieldNames(disp, mises)


def displacement3(mesh, name: str) -> np.ndarray:
    """(N, 3) displacement (2D fields padded with z = 0)."""
    u = np.asarray(mesh.point_data[name], dtype=float)
    if u.ndim == 1 or u.shape[1] < 3:
        u = np.column_stack([u.reshape(len(u), -1), np.zeros((len(u), 3 - u.reshape(len(u), -1).shape[1]))])
    return u


def applied_scale(mesh) -> float:
    """The factor a field file's load-linear arrays already carry over the solved load (1: as solved)."""
    if "load_scale_applied" in mesh.field_data.keys():
        return float(np.asarray(mesh.field_data["load_scale_applied"]).ravel()[0])
    return 1.0


def scaled_to_rated(mesh, scale: float):
    """A copy of ``mesh`` whose every displacement and stress array is ``scale`` x the solved load's (linear
    problem), whatever scale the file was written at (``load_scale_applied``, fea/fields.py)."""
    from strainwave.fea.fields import LINEAR_WORDS

    if not (np.isfinite(scale) and scale > 0):
        raise ValueError(f"load scale must be finite and > 0, got {scale}")
    out = mesh.copy()
    factor = scale / applied_scale(mesh)
    for data in (out.point_data, out.cell_data):
        for key in list(data.keys()):
            if any(word in key.lower() for word in LINEAR_WORDS):
                data[key] = np.asarray(data[key], dtype=float) * factor
    out.field_data["load_scale_applied"] = np.array([scale])
    return out


def write_at_rated(fields, load: RatedLoad) -> None:
    """Rewrite a study's VTU files (``fields``: its written paths) at the rated ``load``, which their FieldData
    then states (``fields_at``, ``load_scale_applied``, ``rated_load``, ``solved_load``)."""
    from strainwave.fea.fields import rescale_vtu

    for path in fields:
        if str(path).endswith(".vtu") and not str(path).endswith(".boundary.vtu") and Path(path).exists():
            rescale_vtu(Path(path), load.scale, f"the rated load: {load.describe()}; fields x {load.scale:.6g} "
                        f"of the solved {load.solved:g} {load.unit}",
                        {"rated_load": load.rated, "solved_load": load.solved})


@dataclass(frozen=True)
class FieldPeaks:
    peak_von_mises_MPa: float
    peak_location_mm: tuple[float, float, float]
    peak_displacement_mm: float
    peak_node: int = -1                  # the node of the peak in the field file
    peak_on: tuple[str, ...] = ()        # the named faces (or points) that node lies on, e.g. ("fixed",)
    # the crack's singular zone, left out of the peak: its radius, and the peak inside it (shown apart)
    tip_radius_mm: float | None = None
    tip_peak_von_mises_MPa: float | None = None
    tip_peak_location_mm: tuple[float, float, float] | None = None
    # the part's sharp re-entrant edges (StudyFacts.singular_edges_mm), left out alike: radius, peak, where
    corner_radius_mm: float | None = None
    corner_peak_von_mises_MPa: float | None = None
    corner_peak_location_mm: tuple[float, float, float] | None = None

    def __post_init__(self):
        if not (np.isfinite(self.peak_von_mises_MPa) and self.peak_von_mises_MPa >= 0):
            raise ValueError(f"peak von Mises must be finite and >= 0, got {self.peak_von_mises_MPa}")


# Nodes within this fraction of the crack depth of the crack front are the crack's singular field: their
# stress grows with refinement and is set by the mesh, so no safety factor or colour range is drawn from it.
TIP_RADIUS_OVER_A = 0.25


def field_peaks(mesh, tip_zone: np.ndarray | None = None, tip_radius_mm: float | None = None,
                corner_zone: np.ndarray | None = None, corner_radius_mm: float | None = None) -> FieldPeaks:
    """Peak nodal von Mises with its location, and the peak |u|, of a (scaled) field; nodes where ``tip_zone``
    or ``corner_zone`` (bool per node) is set are left out of the peak, and each zone's own maximum is recorded
    apart."""
    names = field_names(mesh)
    if names.von_mises is None or names.von_mises not in mesh.point_data:
        raise ValueError("the field has no nodal von Mises array")
    vm = np.asarray(mesh.point_data[names.von_mises], dtype=float)
    zones = {kind: (np.zeros(vm.size, bool) if zone is None else np.asarray(zone, bool), radius)
             for kind, zone, radius in (("tip", tip_zone, tip_radius_mm), ("corner", corner_zone, corner_radius_mm))}
    outside = ~(zones["tip"][0] | zones["corner"][0])
    if not outside.any():
        raise ValueError("every node of the field lies in a singular zone")
    k = int(np.argmax(np.where(outside, vm, -np.inf)))
    u = displacement3(mesh, names.displacement) if names.displacement else np.zeros((mesh.n_points, 3))
    apart = {}
    for kind, (zone, radius) in zones.items():
        if zone.any():
            t = int(np.argmax(np.where(zone, vm, -np.inf)))
            apart.update({f"{kind}_radius_mm": radius, f"{kind}_peak_von_mises_MPa": float(vm[t]),
                          f"{kind}_peak_location_mm": tuple(float(x) for x in mesh.points[t])})
    return FieldPeaks(float(vm[k]), tuple(float(x) for x in mesh.points[k]), float(np.linalg.norm(u, axis=1).max()),
                      k, **apart)


def crack_front_nodes(vtu: Path) -> np.ndarray:
    """Nodes of ``vtu`` on its crack front: those on both opened crack faces (fea/crack_seam keeps the front's
    nodes shared), or, for a crack on a symmetry plane, those its face shares with the ligament; read from the
    boundary file. Empty without a crack."""
    from strainwave.fea.fields import VOLUME_POINT_ID, field_text

    path = Path(vtu).with_name(f"{Path(vtu).stem}.boundary.vtu")
    if not path.exists():
        return np.zeros(0, int)
    boundary = read_vtu(path)
    names = field_text(boundary, "physical_group_names") if "physical_group_names" in boundary.field_data.keys() \
        else []
    pair = next((p for p in (("crack_minus", "crack_plus"), ("crack", "ligament")) if set(p) <= set(names)), None)
    if pair is None:
        return np.zeros(0, int)
    ids = np.asarray(boundary.cell_data["physical_group"])
    sides = []
    for name in pair:
        cells = boundary.extract_cells(np.flatnonzero(ids == names.index(name) + 1))
        sides.append(np.asarray(cells.point_data[VOLUME_POINT_ID]))
    return np.intersect1d(sides[0], sides[1])


def tip_zone_of(mesh, vtu: Path, crack_depth_mm: float | None) -> tuple[np.ndarray | None, float | None]:
    """(bool per node, radius) of the crack's singular zone: within TIP_RADIUS_OVER_A x a of the front."""
    if not crack_depth_mm:
        return None, None
    front = crack_front_nodes(vtu)
    if front.size == 0:
        return None, None
    from scipy.spatial import cKDTree

    radius = TIP_RADIUS_OVER_A * crack_depth_mm
    distance, _ = cKDTree(np.asarray(mesh.points)[front]).query(np.asarray(mesh.points))
    return distance <= radius, radius


def corner_zone_of(mesh, edges_mm) -> tuple[np.ndarray | None, float | None]:
    """(bool per node, radius) of the zones around sharp re-entrant edges, circles (r, z, radius) about the z axis
    (``StudyFacts.singular_edges_mm``); (None, None) without any."""
    if not edges_mm:
        return None, None
    x = np.asarray(mesh.points, dtype=float)
    r = np.hypot(x[:, 0], x[:, 1])
    zone = np.zeros(len(x), bool)
    for r_e, z_e, radius in edges_mm:
        zone |= np.hypot(r - r_e, x[:, 2] - z_e) <= radius
    return zone, max(e[2] for e in edges_mm)


def groups_at_node(vtu: Path, node: int) -> tuple[str, ...]:
    """The named groups of ``vtu``'s boundary file (fea/fields.py: its points carry their node ids in the field's
    file) that hold the field's node ``node``."""
    from strainwave.fea.fields import VOLUME_POINT_ID, field_text

    path = Path(vtu).with_name(f"{Path(vtu).stem}.boundary.vtu")
    if not path.exists() or node < 0:
        return ()
    boundary = read_vtu(path)
    names = field_text(boundary, "physical_group_names") if "physical_group_names" in boundary.field_data.keys() \
        else []
    local = np.flatnonzero(np.asarray(boundary.point_data[VOLUME_POINT_ID]) == node)
    if local.size == 0:
        return ()
    near = boundary.extract_points(local, adjacent_cells=True, include_cells=True)
    ids = np.unique(np.asarray(near.cell_data["physical_group"])) if near.n_cells else []
    return tuple(names[i - 1] for i in ids if 0 < i <= len(names))   # id k is entry k - 1


def stress_field_of(study: str, fields, crack_depth_mm: float | None) -> tuple[Path, bool] | None:
    """(VTU, cracked) of ``fields`` (a study's written files) that its rated-load stress picture shows; cracked
    says whether that field carries the crack (a solve with a crack whose fields hold no separate
    ``_cracked``/``_uncracked`` pair wrote the cracked field)."""
    files = [Path(p) for p in fields if str(p).endswith(".vtu") and not str(p).endswith(".boundary.vtu")]
    suffix = registered(study).facts().stress_field_suffix   # the study's own choice, else the uncracked part
    chosen = [p for p in files if suffix and p.stem.endswith(suffix)] or \
             [p for p in files if not p.stem.endswith(("_cracked", "_smooth"))] or files
    if not chosen:
        return None
    path = chosen[0]
    paired = any(p.stem.endswith("_cracked") for p in files) and not path.stem.endswith("_cracked")
    # a study that sweeps its own cracks may write only its uncracked part, named so
    return path, crack_depth_mm is not None and not paired and not path.stem.endswith("_uncracked")


def rated_load(study: str, params, solved: float, quantities=None) -> RatedLoad:
    """The rated load of ``study`` against the load ``solved`` its fields were computed at, by the function its
    variant names (``StudyFacts.rated_load``); ``quantities``: {name: value} of its result, where the rated
    load follows from the FEA (the EWG ring's force for W0)."""
    import importlib

    name = registered(study).facts().rated_load
    if name is None:
        raise ValueError(f"no rated load for study {study!r}")
    module, _, function = name.partition(":")
    return getattr(importlib.import_module(module), function)(study, params, solved, quantities)


def rated_load_of(study: str, params, result) -> RatedLoad:
    """The rated load of a solved study (a ``StudyResult``) against the load it solved (its typed ``Load``)."""
    registered(study)      # an unknown study is an InputError (exit 2), before any field is read
    return rated_load(study, params, result.load.magnitude, {k: q.value for k, q in result.quantities.items()})


@dataclass(frozen=True)
class StressAtRated:
    """A study's stress field at its rated load, as ``solve`` prints it and the report states it."""
    study: str
    field_file: str
    load: RatedLoad
    peaks: FieldPeaks
    fatigue_limit_MPa: float
    cracked: bool

    @property
    def safety_factor(self) -> float:
        return fatigue_safety_factor(self.fatigue_limit_MPa, self.peaks.peak_von_mises_MPa)

    @property
    def note(self) -> str:
        text = ("material-only factor sigma_-1 / sigma_vM,peak (peak taken as a fully reversed amplitude, "
                "no notch, size or mean-stress factor)")
        p = self.peaks
        if p.tip_peak_von_mises_MPa is not None:
            text += (f"; the field carries the crack: nodes within {p.tip_radius_mm:.3g} mm ({TIP_RADIUS_OVER_A:g} a) "
                     f"of its front are left out (singular: the tip stress grows with refinement), their peak "
                     f"{p.tip_peak_von_mises_MPa:.4g} MPa is shown apart")
        elif self.cracked:
            text += ("; the field carries the crack, whose tip stress is singular (it grows with refinement): a peak "
                     "at the tip is not a design stress")
        if p.corner_peak_von_mises_MPa is not None:
            text += (f"; nodes within {p.corner_radius_mm:.3g} mm of a sharp re-entrant edge are left out (singular in "
                     f"the model, which has no fillet there: their stress grows with refinement and a real fillet's "
                     f"radius sets it), their peak {p.corner_peak_von_mises_MPa:.4g} MPa is shown apart")
        return text

    def lines(self) -> list[str]:
        p = self.peaks
        where = ", ".join(f"{x:.4g}" for x in p.peak_location_mm)
        on = f" on {', '.join(repr(g) for g in p.peak_on)}" if p.peak_on else ""
        return [f"at the rated load: {self.load.describe()}, fields x {self.load.scale:.4g}",
                f"  peak von Mises {p.peak_von_mises_MPa:.4g} MPa at ({where}) mm{on}; peak displacement "
                f"{p.peak_displacement_mm:.4g} mm",
                f"  safety factor vs fatigue limit {self.fatigue_limit_MPa:g} MPa: {self.safety_factor:.3g} "
                f"({self.note})"]

    def to_dict(self) -> dict:
        return {"study": self.study, "field_file": self.field_file, "load": self.load.to_dict(),
                "load_text": self.load.describe(), "peak_von_mises_MPa": self.peaks.peak_von_mises_MPa,
                "peak_location_mm": list(self.peaks.peak_location_mm), "peak_on": list(self.peaks.peak_on),
                "peak_displacement_mm": self.peaks.peak_displacement_mm, "fatigue_limit_MPa": self.fatigue_limit_MPa,
                "safety_factor": self.safety_factor, "cracked": self.cracked, "note": self.note,
                "tip_radius_mm": self.peaks.tip_radius_mm,
                "tip_peak_von_mises_MPa": self.peaks.tip_peak_von_mises_MPa,
                "tip_peak_location_mm": None if self.peaks.tip_peak_location_mm is None
                else list(self.peaks.tip_peak_location_mm),
                "corner_radius_mm": self.peaks.corner_radius_mm,
                "corner_peak_von_mises_MPa": self.peaks.corner_peak_von_mises_MPa,
                "corner_peak_location_mm": None if self.peaks.corner_peak_location_mm is None
                else list(self.peaks.corner_peak_location_mm)}


def stress_at_rated(study: str, params, result, vtu: Path, *, cracked: bool) -> StressAtRated:
    """Peaks of ``vtu`` (one of ``result``'s fields) at the study's rated load."""
    load = rated_load_of(study, params, result)
    mesh = scaled_to_rated(read_vtu(vtu), load.scale)
    zone, radius = tip_zone_of(mesh, vtu, result.crack_depth_mm if cracked else None)
    corner, corner_radius = corner_zone_of(mesh, registered(study).facts().singular_edges_mm(params))
    peaks = field_peaks(mesh, zone, radius, corner, corner_radius)
    peaks = dataclasses.replace(peaks, peak_on=groups_at_node(vtu, peaks.peak_node))
    return StressAtRated(study, Path(vtu).name, load, peaks, params.material.fatigue_limit_MPa, cracked)
