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

# Elements per min(h, t) h^2 cell (plane: min(h, t) h) are each study's ``elements_per_cell``, fitted on its own
# meshes (docs/decisions/008-element-and-teeth-budget.md).


# Teeth one CAD build may cut: OCC's work grows faster than the tooth count (docs/decisions/008-element-and-teeth-budget.md).
MAX_CAD_TEETH = 400
# The toothed parts and the tooth-count key each is cut from (the cup study meshes a smooth shell).
TOOTHED_PARTS = {"flexspline-cup": "flexspline_cup.teeth", "ewg-flexspline-ring": "ewg_drive.flexspline_teeth",
                 "ewg": "ewg_drive.flexspline_teeth", "circular-spline": "flexspline_cup.teeth"}


# The keys each meshed part's size and wall come from, for a budget refusal of the parameters themselves.
PART_KEYS = {"flexspline-cup": "flexspline_cup.pitch_diameter_mm, wall_thickness_mm, length_mm",
             "output-shaft": "output_shaft.outer_diameter_mm, inner_diameter_mm, length_mm",
             "wg-bearing-ring": "wave_generator.bearing_inner_ring_thickness_mm, contact_semi_axes_mm and "
                                "flexspline_cup.pitch_diameter_mm, wall_thickness_mm",
             "ewg-flexspline-ring": "ewg_drive.flexspline_teeth, module_mm, rim_thickness_ratio"}


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


def _facts(study: str):
    from strainwave.registry import study as registered
    return registered(study).facts()


def estimate(study: str, params, mesh_size_mm: float | None, quick: bool = False) -> MeshEstimate:
    """Elements of ``study``'s finest mesh at ``mesh_size_mm`` (None: the study's default), from the facts
    its variant class states (``fea.study_facts.StudyFacts``)."""
    facts = _facts(study)
    h = float(mesh_size_mm) if mesh_size_mm else facts.default_size_mm(params, quick)
    volume, wall = facts.volume_and_wall(params)
    # a plane study is meshed as a section: triangles per min(h, t) * h of its area
    cell = min(h, wall) * h if facts.plane else min(h, wall) * h * h
    cells = volume / cell if cell > 0 else math.inf   # h = 5e-324: the cell underflows to 0
    cells += facts.feature_cells(params, h, wall)
    return MeshEstimate(study, h, wall, volume, int(min(facts.elements_per_cell * cells, 1e18)))


def check_budget(study: str, params, mesh_size_mm: float | None, quick: bool = False,
                 flag: str = "--mesh-size-mm") -> MeshEstimate:
    """Refuse (InputError naming ``flag``, the estimate and the budget) a run whose finest mesh would
    exceed ``MAX_ELEMENTS``; returns the estimate when it fits."""
    teeth = _facts(study).teeth_key
    if teeth is not None:
        check_cad_teeth(params, [p for p, k in TOOTHED_PARTS.items() if k == teeth][:1], flag)
    est = estimate(study, params, mesh_size_mm, quick)
    if est.elements > MAX_ELEMENTS and not mesh_size_mm:   # the parameters alone: name them, not a flag not given
        from strainwave.registry import study as registered
        part = registered(study).part
        raise InputError(f"the {part} ({PART_KEYS.get(part, 'its parameters')})", f"{est.elements:.3g} elements",
                         f"{study} would need that many on its finest mesh at its default size h = {est.h_mm:.3g} mm "
                         f"(part volume {est.volume_mm3:.3g} mm^3, wall {est.wall_mm:.3g} mm); the budget is "
                         f"{MAX_ELEMENTS:,}: the part is too large for its wall to mesh")
    if est.elements > MAX_ELEMENTS:
        raise InputError(flag, mesh_size_mm,
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
