"""Tooth profiles by name: ``ToothProfile`` (params) -> the function that draws a toothed outline.

A profile is one member of ``strainwave.params.ToothProfile`` plus one drawing function here, registered in
``DRAWERS``. A drawing function takes a ``ToothSpec`` and returns the outline tooth by tooth, as
``involute.gear_edges`` does: a list of (the tooth's edges from root circle to root circle, the root arc to the
next tooth), tooth 0 centred on +x, in the xy plane. Every toothed part of the drive draws through ``edges``.
"""
from __future__ import annotations

from typing import Callable

from strainwave.params import ToothProfile

from strainwave.geometry.involute import ToothSpec, gear_edges

__all__ = ["DRAWERS", "edges", "outline_wire"]

DRAWERS: dict[ToothProfile, Callable[[ToothSpec], list]] = {
    ToothProfile.INVOLUTE: gear_edges,
}


def edges(profile: ToothProfile, spec: ToothSpec) -> list:
    """The toothed outline of ``spec`` in ``profile``'s form, tooth by tooth (see the module docstring)."""
    try:
        draw = DRAWERS[ToothProfile(profile)]
    except KeyError:   # a member added to the vocabulary without its drawing: a programming error
        raise NotImplementedError(f"tooth profile {profile!r} has no drawing function in DRAWERS") from None
    return draw(spec)


def outline_wire(profile: ToothProfile, spec: ToothSpec):
    """The closed toothed outline as one build123d Wire."""
    from build123d import Wire

    return Wire([e for tooth, root in edges(profile, spec) for e in (*tooth, root)])
