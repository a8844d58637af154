"""Element-count estimate of a study's finest mesh, made from the parameters before any CAD or meshing.

A 1e6 mm shaft or ``--mesh-size-mm 1e-6`` asked gmsh for billions of elements and crashed it
(docs/decisions/008-element-and-teeth-budget.md). The estimate is the part's volume over the volume one
element fills, with the through-wall size capped by the wall (a thin wall is meshed with at least one layer
whatever the global size):

    N ~ C * V / (min(h, t) * h^2)

C is measured per study on its own meshes (``ELEMENTS_PER_CELL``; the estimate is within a factor of 2
of the real count there), so the budget check refuses a run by what it would cost, with the estimate
in the message, and lets every default run through.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from strainwave.errors import InputError

# Finest-mesh elements one run may ask for: what fits a shared 2-core machine (docs/decisions/008-element-and-teeth-budget.md).
MAX_ELEMENTS = 300_000

# Elements per min(h, t) h^2 cell (plane ring: min(h, t) h), fitted per study (docs/decisions/008-element-and-teeth-budget.md).
# wg-bearing (2D, graded to the race patches and the crack tip): the cracked quick mesh at a = 1 mm, h = 1.67 mm,
# ~15,700 triangles vs 1,306 cells (12).
ELEMENTS_PER_CELL = {"shaft-torsion": 4.7, "cup-torsion": 13.3, "bearing-ring": 10.2, "ring-compression": 0.54,
                     "wg-bearing": 12.0,
                     # cup-wave-generator: quarter wall of 27-node hexahedra, one through the wall, h/2 along the
                     # band: quick n = 14: 294 elements vs 239 cells (1.23)
                     "cup-wave-generator": 1.23,
                     # cup-surface-crack: quarter block graded to the front (a/12): a = 0.2 t, h = t/3:
                     # 11,805 tets vs 129 cells (92)
                     "cup-surface-crack": 100.0}
PLANE_STUDIES = ("ring-compression", "wg-bearing")     # meshed as a plane section: cells of min(h, t) * h


# Teeth one CAD build may cut: OCC's work grows faster than the tooth count (docs/decisions/008-element-and-teeth-budget.md).
MAX_CAD_TEETH = 400
# The toothed parts and the tooth-count key each is cut from (the cup study meshes a smooth shell).
TOOTHED_PARTS = {"flexspline-cup": "flexspline_cup.teeth", "ewg-flexspline-ring": "ewg_drive.flexspline_teeth",
                 "ewg": "ewg_drive.flexspline_teeth"}
_STUDY_TEETH = {"ring-compression": "ewg_drive.flexspline_teeth"}


def check_cad_teeth(params, parts, flag: str = "--params") -> None:
    """Refuse a CAD build of any of ``parts`` whose tooth count exceeds ``MAX_CAD_TEETH``."""
    data = params.to_dict()
    for part in parts:
        key = TOOTHED_PARTS.get(part)
        if key is None:
            continue
        section, _, name = key.partition(".")
        if data[section][name] > MAX_CAD_TEETH:
            raise InputError(key, data[section][name],
                             f"building {part} with more than {MAX_CAD_TEETH} teeth takes over ~1.5 min of CAD per "
                             f"part (150 teeth 18 s, 300 teeth 50 s measured); --no-teeth builds the smooth shell")


@dataclass(frozen=True)
class MeshEstimate:
    study: str
    h_mm: float              # finest global size
    wall_mm: float           # through-wall size that caps the element size across the wall
    volume_mm3: float        # the part's volume (the 2D ring: its section area x 1 mm)
    elements: int

    def __post_init__(self):
        if not (self.h_mm > 0 and self.wall_mm > 0 and self.volume_mm3 > 0 and self.elements >= 0):
            raise ValueError(f"MeshEstimate: sizes must be > 0, got {self}")


def _default_h_mm(study: str, params, quick: bool) -> float:
    """The study's own default finest size (read from the study module, not restated here)."""
    if study == "shaft-torsion":
        from strainwave.fea.shaft_torsion import default_size_mm
    elif study == "cup-torsion":
        from strainwave.fea.cup_torsion import default_size_mm
    elif study == "bearing-ring":
        from strainwave.fea.bearing_ring import default_size_mm
    elif study == "wg-bearing":
        from strainwave.fea.wg_bearing import default_size_mm
    elif study == "cup-wave-generator":
        from strainwave.fea.cup_wave_generator import default_size_mm
    elif study == "cup-surface-crack":
        from strainwave.fea.surface_crack import default_size_mm
    else:
        from strainwave.fea.ring_compression import mesh_sizes_mm, ring_geometry
        return mesh_sizes_mm(ring_geometry(params), None, quick)[0]
    return default_size_mm(params, quick)


def _volume_and_wall(study: str, params) -> tuple[float, float]:
    if study == "shaft-torsion":
        s = params.output_shaft
        return math.pi / 4 * (s.outer_diameter_mm ** 2 - s.inner_diameter_mm ** 2) * s.length_mm, s.wall_mm
    if study == "cup-torsion":
        c = params.flexspline_cup
        tube = math.pi * c.pitch_diameter_mm * c.wall_thickness_mm * c.length_mm
        diaphragm = math.pi / 4 * c.pitch_diameter_mm ** 2 * c.wall_thickness_mm
        return tube + diaphragm, c.wall_thickness_mm
    if study == "cup-wave-generator":
        from strainwave.fea.wg_band import tube_geometry
        g = tube_geometry(params)     # the quarter wall the study meshes
        return 0.5 * math.pi * g.r_m_mm * g.wall_mm * (g.length_mm - g.z_end_mm), g.wall_mm
    if study == "cup-surface-crack":     # the deepest crack's quarter block (fea/surface_crack.py)
        from strainwave.fea.surface_crack import deepest_block_volume_mm3
        return deepest_block_volume_mm3(params), params.flexspline_cup.wall_thickness_mm
    if study in ("bearing-ring", "wg-bearing"):     # wg-bearing: the plane section, per mm of width
        wg, c = params.wave_generator, params.flexspline_cup
        t = wg.bearing_inner_ring_thickness_mm
        # geometry/bearing_ring.py: race radius d1/2 - delta - 1.5 t_i, bore 1 t_i inside, width 4 a'
        r_race = max(c.pitch_diameter_mm / 2 - c.wall_thickness_mm - 1.5 * t, t)
        volume = math.pi * (r_race ** 2 - max(r_race - t, 0.0) ** 2)
        return (volume if study == "wg-bearing" else volume * 4 * wg.contact_semi_axes_mm[0]), t
    e = params.ewg_drive   # ring-compression: the plane section (toothed rim), per mm of depth
    r_in = 0.5 * e.module_mm * e.flexspline_teeth
    r_out = r_in + e.dedendum_coefficient * e.module_mm + e.rim_thickness_mm + 2.25 * e.module_mm
    return math.pi * (r_out ** 2 - r_in ** 2), e.rim_thickness_mm


def estimate(study: str, params, mesh_size_mm: float | None, quick: bool = False) -> MeshEstimate:
    """Elements of ``study``'s finest mesh at ``mesh_size_mm`` (None: the study's default)."""
    if study not in ELEMENTS_PER_CELL:
        raise ValueError(f"no element estimate for study {study!r}")   # a registry/budget mismatch, not input
    h = float(mesh_size_mm) if mesh_size_mm else _default_h_mm(study, params, quick)
    volume, wall = _volume_and_wall(study, params)
    # the ring is meshed as a plane section: triangles per min(h, t) * h of its area
    cell = min(h, wall) * h if study in PLANE_STUDIES else min(h, wall) * h * h
    cells = volume / cell if cell > 0 else math.inf   # h = 5e-324: the cell underflows to 0
    cells += _feature_cells(study, params, h, wall)
    return MeshEstimate(study, h, wall, volume, int(min(ELEMENTS_PER_CELL[study] * cells, 1e18)))


def _feature_cells(study: str, params, h: float, wall: float) -> float:
    """Cells of the refined zones beyond the global size: the bearing's contact patch (fea/bearing_ring.py
    ring_refine: size min(h, b'/3) within max(a', b') of the patch centre), which [1e3, 3] made 5.9 GB."""
    if study != "bearing-ring":
        return 0.0
    a_ax, b_circ = params.wave_generator.contact_semi_axes_mm
    c = min(h, b_circ / 3)
    reach = max(a_ax, b_circ)
    zone_mm3 = min(_volume_and_wall(study, params)[0], (2 * reach) ** 2 * wall)
    cell = min(c, wall) * c * c
    return zone_mm3 / cell if cell > 0 else math.inf


def check_budget(study: str, params, mesh_size_mm: float | None, quick: bool = False,
                 flag: str = "--mesh-size-mm") -> MeshEstimate:
    """Refuse (InputError naming ``flag``, the estimate and the budget) a run whose finest mesh would
    exceed ``MAX_ELEMENTS``; returns the estimate when it fits."""
    if study in _STUDY_TEETH:
        check_cad_teeth(params, [p for p, k in TOOTHED_PARTS.items() if k == _STUDY_TEETH[study]][:1], flag)
    est = estimate(study, params, mesh_size_mm, quick)
    if est.elements > MAX_ELEMENTS:
        raise InputError(flag, mesh_size_mm if mesh_size_mm else f"default h = {est.h_mm:.3g} mm",
                         f"{study} would need about {est.elements:.3g} elements on its finest mesh (part volume "
                         f"{est.volume_mm3:.3g} mm^3, h = {est.h_mm:.3g} mm, wall {est.wall_mm:.3g} mm); the budget "
                         f"is {MAX_ELEMENTS:,}: " + ("choose a larger --mesh-size-mm or a smaller part" if flag == "--mesh-size-mm"
                                                      else "the part is too large for its wall to mesh"))
    global _current_elements   # the largest of the process's runs (validate checks every study first)
    _current_elements = max(est.elements, _current_elements or 1)
    return est


# The meshing guard's limits (fea/session.py, mesh_in_child), from the element budget: a gmsh child may take
# MESH_BASE_S plus MESH_S_PER_ELEMENT per element of the run's estimate (MAX_ELEMENTS where none was made),
# and MESH_BASE_BYTES plus MESH_BYTES_PER_ELEMENT per element beyond the address space it inherits. Both are
# generous (P2 tets mesh at thousands per second and take a few KB each): they stop a hang or a runaway
# size field, never a mesh the budget accepted.
MESH_BASE_S = 30.0
MESH_S_PER_ELEMENT = 2e-3
MESH_BASE_BYTES = 1 << 30
MESH_BYTES_PER_ELEMENT = 16 << 10

# The estimate of the run being meshed (check_budget sets it), so the limits follow the run, not the budget.
_current_elements: int | None = None


@dataclass(frozen=True)
class MeshLimits:
    wall_s: float
    extra_bytes: int
    elements: int


def mesh_limits() -> MeshLimits:
    """Wall time and memory one gmsh call may take: from the estimate check_budget last made in this
    process, else from MAX_ELEMENTS (a sweep's worker, a library call without a budget check)."""
    n = min(_current_elements or MAX_ELEMENTS, MAX_ELEMENTS)
    return MeshLimits(MESH_BASE_S + MESH_S_PER_ELEMENT * n, int(MESH_BASE_BYTES + MESH_BYTES_PER_ELEMENT * n), n)
