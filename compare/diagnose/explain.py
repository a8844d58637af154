"""The paragraph a gear engineer reads: what differs, where, which physics, how much, how sure."""
from __future__ import annotations

from .effects import CATALOGUE


def explain(diag) -> str:
    noise = diag.noise_std
    if not diag.mismatch:
        return (f"The recording agrees with the baseline ({diag.baseline.source}) within the noise "
                f"({noise:.3g}) and the stated {100 * diag.baseline.uncertainty:.0f} % uncertainty of the simulated "
                f"stiffness: residual RMS {diag.rms_before:.3g}. No physics is missing at this resolution; the "
                f"best catalogue candidate did not improve BIC by more than 10.")
    top = diag.effects[0]
    why = "; and ".join(CATALOGUE[c].explanation for c in top.components)
    params = ", ".join(f"{k} = {v:.4g} {u}".rstrip() for k, (v, u) in list(top.parameters.items())[:6])
    runner = ""
    if len(diag.effects) > 1:
        r = diag.effects[1]
        runner = (f" The runner-up, {r.id}, scores {top.delta_bic - r.delta_bic:.1f} BIC units worse"
                  f"{' (a close call)' if top.delta_bic - r.delta_bic < 6 else ''}.")
    return (f"The recording departs from the baseline ({diag.baseline.source}) beyond its noise ({noise:.3g}) "
            f"and the {100 * diag.baseline.uncertainty:.0f} % stiffness uncertainty: {diag.located.description}. "
            f"The best explanation is {top.id.replace('+', ' together with ')}: {why}. Fitted: {params}. "
            f"Adding it lowers the residual RMS from {diag.rms_before:.3g} to {diag.rms_after:.3g} and BIC by "
            f"{top.delta_bic:.1f}.{runner}")
