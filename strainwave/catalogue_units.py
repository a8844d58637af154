"""The catalogue's units beside the model's: drive catalogues give torque in N m, torsional stiffness in N m/rad
and twist (lost motion, hysteresis) in arcmin, where strainwave computes in N mm and rad."""
from __future__ import annotations

import math

__all__ = ["in_catalogue_units", "beside"]

# model unit -> (catalogue unit, factor from the model's unit to the catalogue's)
_CATALOGUE = {"N*mm": ("N m", 1e-3), "N mm": ("N m", 1e-3), "N*mm/rad": ("N m/rad", 1e-3),
              "N mm/rad": ("N m/rad", 1e-3), "rad/(N*mm)": ("arcmin/(N m)", 1e3 * 60 * 180 / math.pi),
              "rad": ("arcmin", 60 * 180 / math.pi)}


def in_catalogue_units(value: float, unit: str) -> tuple[float, str] | None:
    """(value, unit) in the catalogue's unit, or None where the unit has no catalogue counterpart."""
    found = _CATALOGUE.get(unit.strip())
    return None if found is None else (value * found[1], found[0])


def beside(value: float, unit: str) -> str:
    """' (1000 N m)' for (1e6, 'N*mm'); '' where the unit has no catalogue counterpart."""
    found = in_catalogue_units(value, unit)
    return "" if found is None else f" ({found[0]:.4g} {found[1]})"
