"""Three refinements of one quantity -> a Quantity carrying its grid convergence index.

Sizes are h, h r, h r^2 (fine first); r = 1.4 keeps every ratio above the 1.3 that Roache/ASME V&V 20
ask for while the coarse mesh stays cheap.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Sequence, TypeVar

from strainwave.fea.convergence import Convergence, GciUndefined, formal_order, grid_convergence
from strainwave.fea.meshing import Refine
from strainwave.fea.result import Quantity

DEFAULT_RATIO = 1.4
T = TypeVar("T")


def refinement_sizes(h_fine_mm: float, ratio: float = DEFAULT_RATIO) -> tuple[float, float, float]:
    """(h, h r, h r^2), finest first."""
    return (h_fine_mm, h_fine_mm * ratio, h_fine_mm * ratio ** 2)


def crack_front_size_mm(h_mm: float, h_fine_mm: float, depth_mm: float, *, tip_over_a: float,
                        floor_over_h: float) -> float:
    """Element size at a seam crack's front on the mesh of global size h: ``tip_over_a`` a on the finest
    mesh (never above h_fine, never below ``floor_over_h`` h_fine), times h / h_fine on the coarser ones,
    so that the front refines with the mesh and the GCI sees the crack-tip error converge (P2 without
    quarter-point elements: delta compliance error O(tip size), observed order ~1)."""
    return (h_mm / h_fine_mm) * max(min(h_fine_mm, tip_over_a * depth_mm), floor_over_h * h_fine_mm)


@dataclass(frozen=True)
class CrackFrontGrading:
    """How a seam crack's front is meshed, in units of the crack depth a and the global size h: size
    ``crack_front_size_mm`` (``tip_over_a``, ``floor_over_h``) within ``near_over_a`` a of the front,
    growing linearly to h at ``zone_over_a`` a + ``grow_over_h`` h. Each study measures its own values
    (their comments hold the numbers)."""

    tip_over_a: float
    floor_over_h: float
    near_over_a: float
    zone_over_a: float
    grow_over_h: float

    def refine(self, front_mm, h_mm: float, h_fine_mm: float, depth_mm: float) -> Refine:
        tip = crack_front_size_mm(h_mm, h_fine_mm, depth_mm, tip_over_a=self.tip_over_a,
                                  floor_over_h=self.floor_over_h)
        return Refine(size_mm=tip, dist_min_mm=max(self.near_over_a * depth_mm, tip),
                      dist_max_mm=self.zone_over_a * depth_mm + self.grow_over_h * h_mm, points_mm=front_mm)


# Formal order 1 for crack compliances, used with Fs = 3 unless the observed order (always shown) confirms it
# (docs/decisions/010-shaft-axisymmetric-crack.md, docs/verification.md).
CRACK_FORMAL_ORDER = 1.0


def converged_quantity(name: str, unit: str, h_mm: Sequence[float], values: Sequence[float], *,
                       order: float | None = None, element_order: int = 2) -> Quantity:
    """Quantity with the finest value and the GCI of the three (h, value) pairs; ``order``: its formal
    order (default: ``convergence.formal_order`` of its name and unit on elements of ``element_order``)."""
    formal = formal_order(name, unit, element_order)[0] if order is None else order
    try:
        conv = grid_convergence(tuple(h_mm), tuple(values), formal_order=formal)
    except GciUndefined as exc:
        # e.g. a field the element space holds exactly: the record says so instead of a 0 % band
        conv = Convergence.refusal(h_mm, values, str(exc), formal)
    return Quantity(name, float(conv.values[0]), unit, conv)


def on_three_meshes(solve: Callable[[float, int], T], refinements: Sequence[float], *,
                    progress: Callable[[str], None] = lambda m: None, label: str = "") -> tuple[T, T, T]:
    """Run ``solve(refinement, k)`` coarse to fine over three refinements given finest first (k = 0 is the
    finest); returns the three results finest first. The one three-mesh loop of every study."""
    if len(refinements) != 3:
        raise ValueError(f"three refinements are needed, got {len(refinements)}")
    out: dict[int, T] = {}
    for step, k in enumerate((2, 1, 0)):
        progress(f"{label}refinement {step + 1}/3: {refinements[k]:.3g}")
        out[k] = solve(refinements[k], k)
    return out[0], out[1], out[2]


def crack_flexibility_quantities(sizes, uncracked: list[float], cracked: list[float] | None,
                                 unit: str, *, delta: list[float] | None = None) -> dict[str, Quantity]:
    """Flexibility, and with a crack the cracked flexibility and the difference, each on the same three
    meshes (finest first): the difference carries its own GCI, as the crack checks need. ``delta``: the
    difference as solved (a global-local crack), instead of cracked - uncracked."""
    out = {"flexibility_rad_per_Nmm": converged_quantity("flexibility_rad_per_Nmm", unit, sizes, uncracked)}
    if cracked:
        out["cracked_flexibility_rad_per_Nmm"] = converged_quantity(
            "cracked_flexibility_rad_per_Nmm", unit, sizes, cracked)
        out["delta_flexibility_rad_per_Nmm"] = converged_quantity(
            "delta_flexibility_rad_per_Nmm", unit, sizes,
            [c - u for c, u in zip(cracked, uncracked)] if delta is None else list(delta),
            order=CRACK_FORMAL_ORDER)
    return out
