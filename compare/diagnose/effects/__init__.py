"""The physics catalogue: one module per effect, stable ids."""
from __future__ import annotations

from strainwave.compare.diagnose.effects import (compliance_offset, crack_closure, encoder_error, hysteresis, kinematic_error, large_deflection,
               lost_motion, nonlinear_stiffness, plasticity, stiffness_ripple, thick_ring)
from strainwave.compare.diagnose.effects.base import Context, Effect, Param

CATALOGUE = {m.EFFECT.id: m.EFFECT for m in (compliance_offset, nonlinear_stiffness, hysteresis, lost_motion,
                                             crack_closure, thick_ring, large_deflection, plasticity,
                                             kinematic_error, stiffness_ripple, encoder_error)}

# other model forms of the same physics: the named effect must not depend on one law's shape
VARIANTS = (nonlinear_stiffness.TWO_SLOPE, nonlinear_stiffness.SMOOTH_KNEE, nonlinear_stiffness.MONOTONE,
            nonlinear_stiffness.CONTACT, hysteresis.DAHL_EXPONENT, hysteresis.BOUC_WEN, hysteresis.PLAY,
            hysteresis.PLAY_FINE, hysteresis.PREISACH, hysteresis.PREISACH_ELASTIC, hysteresis.PREISACH_FINE,
            crack_closure.GRADUAL, crack_closure.PROGRESSIVE, crack_closure.OPENING,
            lost_motion.FLANK, lost_motion.SHAPE, large_deflection.SECOND_ORDER, plasticity.LIMIT_LOAD)


def effects_for(kind: str) -> tuple[Effect, ...]:
    """The catalogue entries (and their variants) that apply to a test kind, in catalogue order."""
    return tuple(e for e in (*CATALOGUE.values(), *VARIANTS) if kind in e.kinds)


__all__ = ["CATALOGUE", "Context", "Effect", "Param", "effects_for"]
