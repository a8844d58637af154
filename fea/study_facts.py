"""What the stages around a solve need to know of a study, declared once on its variant class.

The registry entry names the variant (``Study.variant``, "module:Class"); the budget, the sweep's worker
start-up, the rated load, the report's inputs section and its pictures read these class-level facts, so
no stage outside the study's own module names a study. Facts are class attributes and classmethods: they
are read without building the variant (no CAD, no mesh).
"""
from __future__ import annotations

from typing import ClassVar

__all__ = ["StudyFacts", "TORQUE_RATED", "DEFAULT_CAD_MODULES"]

# The rated load of a torque-loaded study: gear.rated_output_torque_Nmm (analytic/rated_load.py).
TORQUE_RATED = "strainwave.analytic.rated_load:rated_torque"
# What a sweep worker imports to build any part (docs/decisions/013-sweep-worker-start-up.md).
DEFAULT_CAD_MODULES = ("build123d", "strainwave.geometry.parts")


class StudyFacts:
    """Class-level facts of one study. Each variant sets ``study`` and the facts its stages read."""

    study: ClassVar[str]                                   # registry name
    # fea/budget.py: finest-mesh elements per min(h, t) h^2 cell (plane: per min(h, t) h), measured on its meshes
    elements_per_cell: ClassVar[float]
    # CPU s of one validate case per finest-mesh element of that estimate (full run, --quick): orders the cases and
    # estimates the time left (docs/decisions/049-validate-case-cost-model.md); studies differ 100-fold per element
    cpu_s_per_element: ClassVar[tuple[float, float]] = (2e-4, 2e-4)
    plane: ClassVar[bool] = False                          # meshed as a plane section
    teeth_key: ClassVar[str | None] = None                 # dotted tooth count its CAD cuts (budgeted), if any
    # "module:function" in analytic/: (study, params, solved, quantities {name: value}) -> RatedLoad; None: the
    # study has none (its fields are kept as solved)
    rated_load: ClassVar[str | None] = None
    stress_field_suffix: ClassVar[str | None] = None       # which of its VTU files the stress picture shows
    # report: the component it is shown under (None: not in the inputs/stress sections), its title, element words
    report_component: ClassVar[str | None] = None
    title: ClassVar[str] = ""
    element_text: ClassVar[str] = ""                       # "{order}" is filled with the finest mesh's degree
    image_marks: ClassVar[tuple[tuple[str, ...], str | None, str] | None] = None   # (held faces, loaded faces, load symbol)
    # why its stress field is drawn in its component's section but is no design factor (None: its peak von Mises
    # is the component's factor in the design verdict, compare/validate/design.py)
    outside_design: ClassVar[str | None] = None
    signed_stress: ClassVar[tuple[str, str] | None] = None   # (VTU array, its words) of a signed stress also drawn
    image_view_from: ClassVar[tuple[float, float, float] | None] = None   # camera direction of its 3D picture (None: isometric)
    crack_opening_states: ClassVar[tuple[str, ...]] = ()   # its VTU suffixes ("_<state>") the crack-opening picture shows
    validate_label: ClassVar[str | None] = None            # label of its one uncracked validate case (None: name)
    sweep_at_quick_size: ClassVar[bool] = False            # validate's deeper crack cases mesh at the --quick size
    # its run takes crack_field_only: the crack's own field written without the whole part's (the close-up's case)
    crack_field_alone: ClassVar[bool] = False
    shares_cache: ClassVar[bool] = False        # its run takes cache_dir: results its cases share are kept there

    @classmethod
    def default_size_mm(cls, params, quick: bool) -> float:
        """The finest global size the study meshes at when none is given."""
        raise NotImplementedError(f"{cls.study}: no default size")

    @classmethod
    def volume_and_wall(cls, params) -> tuple[float, float]:
        """The meshed volume (a plane study: its section area x 1 mm) and the wall that caps the element size."""
        raise NotImplementedError(f"{cls.study}: no volume for the element estimate")

    @classmethod
    def feature_cells(cls, params, h_mm: float, wall_mm: float) -> float:
        """Cells of refined zones beyond the global size (none by default)."""
        return 0.0

    @classmethod
    def deepest_crack_mm(cls, params) -> float:
        """Deepest crack of validate's sweep: half the wall its crack cuts (the wall params.py bounds it by)."""
        raise NotImplementedError(f"{cls.study}: carries no crack")

    @classmethod
    def cad_modules(cls, params, cracked: bool) -> tuple[str, ...]:
        """What a sweep worker imports to build this point's part."""
        return DEFAULT_CAD_MODULES

    @classmethod
    def dimensions(cls, params) -> tuple[tuple[str, str], ...]:
        """The report's dimension rows (name, value with unit) of the part it meshes."""
        return ()

    @classmethod
    def singular_edges_mm(cls, params) -> tuple[tuple[float, float, float], ...]:
        """(r, z, zone radius) of each sharp re-entrant edge of its part, a circle about the z axis, where the
        model's stress is singular: nodes within the radius are left out of the design peak (rated_stress)."""
        return ()

    @classmethod
    def image_zoom_mm(cls, params) -> float | None:
        """Radius of the stress picture's zoom panel on the peak, if the picture has one."""
        return None
