"""The answer of `strainwave diagnose`: the verdict, the ranked models and the quantities, as text and JSON."""
from __future__ import annotations

import enum
from dataclasses import dataclass, field

from strainwave.compare.diagnose.baseline import Baseline
from strainwave.compare.diagnose.catalogue_values import CatalogueValues
from strainwave.compare.diagnose.locate import Located
from strainwave.compare.diagnose.structure import StructureTest
from strainwave.compare.diagnose.units import Display


class Verdict(str, enum.Enum):
    """The three answers, decided in this order."""
    AGREES = "agrees"              # residual after the nuisance fit is consistent with the noise
    EXPLAINED = "explained"        # a mismatch, and catalogue effect(s) bring the residual to the noise
    UNEXPLAINED = "unexplained"    # a mismatch no catalogue model brings to the noise


@dataclass(frozen=True)
class RankedEffect:
    id: str
    components: tuple[str, ...]
    parameters: dict            # name -> (value, unit)
    delta_bic: float
    rms: float                  # physical units
    model: str = ""             # id with the model variant, e.g. nonlinear_stiffness[two-slope]
    errors: dict = field(default_factory=dict)      # name -> standard error (same unit)
    weight: float = 0.0         # BIC weight among the ranked models
    warnings: tuple[str, ...] = ()

    def to_dict(self, display: Display = Display()) -> dict:
        return {"id": self.id, "model": self.model or self.id, "components": list(self.components),
                "parameters": {k: _with_error(display, v, u, self.errors.get(k))
                               for k, (v, u) in self.parameters.items()},
                "delta_bic": self.delta_bic, "bic_weight": self.weight, "rms": self.rms,
                "warnings": list(self.warnings)}


@dataclass(frozen=True)
class Diagnosis:
    recording: str
    kind: str
    specimen: str
    baseline: Baseline
    mismatch: bool
    noise_std: float
    located: Located
    effects: tuple[RankedEffect, ...]
    rms_before: float
    rms_after: float
    bic_before: float
    bic_after: float
    explanation: str
    n_samples: int
    verdict: Verdict = Verdict.AGREES
    named: tuple[str, ...] = ()                # catalogue ids of the named set (empty unless explained)
    ambiguous: bool = False                    # runner-up within AMBIGUOUS_BIC of the best
    runner_up: str | None = None
    margin_bic: float | None = None            # BIC(runner-up) - BIC(best)
    suggestion: RankedEffect | None = None     # best partial model when unexplained
    structure: str = ""                        # the residual's structure in physical terms
    gof_baseline: StructureTest | None = None
    gof_model: StructureTest | None = None
    quantities: dict = field(default_factory=dict)   # name -> (value, unit) of the best model
    fitted_rows: int = 0
    noise_model: str = ""                      # the recording's noise model the structures were judged against
    catalogue: CatalogueValues | None = None   # K1..T2 on the loop's mean curve, loss, lost motion (torsion)
    events: tuple[str, ...] = ()               # events taken out of the fit (tooth ratcheting), in words
    display: Display = Display()               # the recording's own units for text and JSON (values stay canonical)

    def __post_init__(self):
        if not isinstance(self.verdict, Verdict):
            raise ValueError(f"verdict must be a Verdict, got {self.verdict!r}")
        if self.named and self.verdict is not Verdict.EXPLAINED:
            raise ValueError("only an explained diagnosis names effects")

    @property
    def response_unit(self) -> str:
        return "rad" if self.kind == "torsion" else "mm"

    def in_units(self, value: float) -> float:
        """A response-unit value (noise, RMS) in the recording's own unit."""
        return self.display.convert(value, self.response_unit)[0]

    @property
    def primary(self) -> str | None:
        """The named effect: the first component of the best model (components ordered by own delta BIC)."""
        return self.named[0] if self.named else None

    def quantity(self, name: str) -> float | None:
        """A quantity of the named model (None unless explained or when absent): shape-free loop quantities
        ``hysteresis_loss_arcmin`` (loop width at zero torque), ``hysteresis_energy_per_cycle_Nmm_rad``
        (closed integral of T dphi), or any reported parameter (``K1``, ``T1``, ...)."""
        if self.verdict is not Verdict.EXPLAINED:
            return None
        if name in self.quantities:
            return float(self.quantities[name][0])
        params = self.effects[0].parameters
        for key in (name, *(f"{c}.{name}" for c in self.named)):
            if key in params:
                return float(params[key][0])
        return None

    def to_dict(self) -> dict:
        return {"recording": self.recording, "kind": self.kind, "specimen": self.specimen,
                "baseline": {"source": self.baseline.source, "compliance": self.baseline.compliance,
                             "unit": self.baseline.unit, "uncertainty": self.baseline.uncertainty},
                "verdict": self.verdict.value, "named": list(self.named), "primary": self.primary,
                "ambiguous": self.ambiguous, "mismatch": self.mismatch,
                "confidence": {"runner_up": self.runner_up, "margin_bic": self.margin_bic,
                               "bic_weight": self.effects[0].weight if self.effects else None},
                "quantities": {k: _shown(self.display, v, u) for k, (v, u) in self.quantities.items()},
                "catalogue": self._catalogue_dict(), "events": list(self.events),
                "units": self.display.to_dict(),
                "suggestion": self.suggestion.to_dict(self.display) if self.suggestion else None,
                "structure": self.structure,
                "goodness_of_fit": {"baseline": self.gof_baseline.to_dict() if self.gof_baseline else None,
                                    "model": self.gof_model.to_dict() if self.gof_model else None,
                                    "noise_model": self.noise_model},
                "noise_std": self.in_units(self.noise_std), "located": self.located.to_dict(),
                "effects": [e.to_dict(self.display) for e in self.effects] if self.mismatch else [],
                "fit": {"rms_before": self.in_units(self.rms_before), "rms_after": self.in_units(self.rms_after),
                        "bic_before": self.bic_before, "bic_after": self.bic_after,
                        "fitted_rows": self.fitted_rows},
                "explanation": self.explanation}

    def summary(self) -> str:
        lines = [f"{self.recording}: {self.kind} / {self.specimen}, {self.n_samples} samples; "
                 f"baseline {self.baseline.source}",
                 f"  noise std {self.response_text(self.noise_std)} ({self.noise_model or 'white'}); "
                 f"rms {self.response_text(self.rms_before)} -> {self.response_text(self.rms_after)}; "
                 f"BIC {self.bic_before:.1f} -> {self.bic_after:.1f}",
                 f"  verdict: {self.verdict.value}" + (f" ({' + '.join(self.named)})" if self.named else "")
                 + (" - AMBIGUOUS with " + str(self.runner_up) if self.ambiguous else "")]
        lines.extend(f"  event (kept out of the fit): {e}" for e in self.events)
        if self.mismatch:
            lines.append(f"  located: {self.located.description}")
            if self.structure and self.verdict is Verdict.UNEXPLAINED:
                lines.append(f"  residual structure: {self.structure}")
            for e in self.effects[:5]:
                lines.append(f"  {e.model or e.id:<52s} delta BIC {e.delta_bic:9.1f}  weight {e.weight:.2f}")
            top = self.effects[0] if self.effects else None
            for name, (v, u) in (top.parameters.items() if top else ()):
                lines.append(f"    {name:<38s} " + _text(self.display, v, u, top.errors.get(name)))
            for w in (top.warnings if top else ()):
                lines.append(f"    warning: {w}")
        if self.catalogue is not None:
            lines.append("  catalogue values (loop's mean curve; Harmonic Drive's definitions):")
            for name, (v, se, u) in self.catalogue.values.items():
                lines.append(f"    {name:<38s} " + _text(self.display, v, u, se))
            lines.extend(f"    warning: {w}" for w in self.catalogue.warnings)
        lines.append(f"  {self.explanation}")
        return "\n".join(lines)

    def response_text(self, value: float) -> str:
        return self.display.text(value, self.response_unit)

    def _catalogue_dict(self) -> dict | None:
        if self.catalogue is None:
            return None
        return {"source": self.catalogue.source, "warnings": list(self.catalogue.warnings),
                "values": {k: _with_error(self.display, v, u, se)
                           for k, (v, se, u) in self.catalogue.values.items()}}


def _shown(display: Display, value, unit: str) -> dict:
    """A value in the recording's units."""
    v, u = display.convert(value, unit)
    return {"value": v, "unit": u}


def _with_error(display: Display, value, unit: str, std_error) -> dict:
    """A value and its standard error (None when unknown) in the recording's units."""
    return {**_shown(display, value, unit),
            "std_error": None if std_error is None else display.convert(std_error, unit)[0]}


def _text(display: Display, value, unit: str, std_error=None) -> str:
    v, u = display.convert(value, unit)
    se = None if std_error is None else display.convert(std_error, unit)[0]
    return f"{v:.6g}" + (f" +/- {se:.2g}" if se is not None else "") + f" {u}"


__all__ = ["Diagnosis", "RankedEffect", "Verdict"]
