"""Column rows in the engineer's units: ``Torque [Nm];Angle [arcmin]``.

A column named ``<quantity> [<unit>]`` is mapped to the recording's canonical column (``torque_Nmm``,
``twist_rad``, ...) and its values converted by pint, a maintained units library. The quantity is read from
the name's first word(s); the unit must be one of the allowed spellings of that quantity (pint alone would
read ``Nm`` as a nanometre, so the spellings are listed, and pint converts them).
"""
from __future__ import annotations

import re

from strainwave.errors import InputError

_BRACKETED = re.compile(r"^\s*(?P<name>[^\[\]]*?)\s*\[\s*(?P<unit>[^\[\]]+?)\s*\]\s*$")
# allowed spellings -> pint expression, per canonical unit
_TORQUE = {"N m": "N*m", "Nm": "N*m", "N*m": "N*m", "N.m": "N*m", "kN m": "kN*m", "kNm": "kN*m", "kN*m": "kN*m",
           "N mm": "N*mm", "Nmm": "N*mm", "N*mm": "N*mm"}
_ANGLE = {"rad": "rad", "mrad": "mrad", "urad": "urad", "deg": "deg", "°": "deg", "arcmin": "arcmin",
          "arcsec": "arcsec"}
_FORCE = {"N": "N", "kN": "kN"}
_LENGTH = {"mm": "mm", "um": "um", "µm": "um", "m": "m"}
_TIME = {"s": "s", "ms": "ms", "min": "min"}
# (name prefixes, canonical column, canonical pint unit, allowed spellings) per kind
QUANTITIES = {
    "torsion": ((("torque", "moment"), "torque_Nmm", "N*mm", _TORQUE),
                (("input angle", "input_angle", "wave generator", "input"), "input_angle_rad", "rad", _ANGLE),
                (("angle", "twist", "output angle"), "twist_rad", "rad", _ANGLE),
                (("time",), "time_s", "s", _TIME)),
    "ring_compression": ((("force", "load"), "force_N", "N", _FORCE),
                         (("delta_ab", "delta ab"), "delta_ab_mm", "mm", _LENGTH),
                         (("delta_cd", "delta cd", "deflection", "displacement", "delta"), "delta_cd_mm", "mm",
                          _LENGTH),
                         (("time",), "time_s", "s", _TIME)),
}


def canonical_column(column: str, kind: str, where: str) -> tuple[str, float, str]:
    """(canonical column, factor to its unit, the recording's own unit) of a column; a column without a
    bracketed unit is returned as it is (factor 1). An unknown quantity or unit: InputError at ``where``."""
    m = _BRACKETED.match(column)
    if m is None:
        return column, 1.0, ""
    name, unit = m.group("name").strip().lower(), m.group("unit").strip()
    for prefixes, canonical, target, spellings in QUANTITIES[kind]:
        if any(name.startswith(p) for p in prefixes):
            if unit not in spellings:
                raise InputError(where, unit, f"unknown unit for {m.group('name').strip()!r}; allowed: "
                                              f"{', '.join(spellings)}")
            return canonical, _factor(spellings[unit], target), unit
    names = sorted({p for q in QUANTITIES[kind] for p in q[0]})
    raise InputError(where, column, f"unknown quantity for kind {kind!r}; a column '<quantity> [<unit>]' starts "
                                    f"with one of: {', '.join(names)}")


def _factor(unit: str, target: str) -> float:
    import pint
    registry = _registry(pint)
    return float(registry.Quantity(1.0, unit).to(target).magnitude)


_REGISTRY = []


def _registry(pint):
    if not _REGISTRY:
        _REGISTRY.append(pint.UnitRegistry())
    return _REGISTRY[0]


__all__ = ["QUANTITIES", "canonical_column"]
