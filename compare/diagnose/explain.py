"""The paragraph a gear engineer reads: the verdict, what differs, where, which physics, how much, how sure."""
from __future__ import annotations

from strainwave.compare.diagnose.effects import CATALOGUE


def loss_sentence(quantities: dict) -> str:
    """Which hysteresis loss is reported: read from the data at zero torque, or from the fitted loop model;
    and a caveat where the recording holds a single full-scale cycle."""
    if "hysteresis_loss_arcmin" not in quantities:
        return ""
    at, unit = quantities.get("hysteresis_loss_read_at_load", (0.0, ""))
    if at != 0.0:
        # a test that never crosses zero torque (unipolar, about a preload) holds no width at zero torque
        return (f"Loop width {quantities['hysteresis_loss_arcmin'][0]:.4g}{_pm(quantities)} arcmin, read at "
                f"{at:.4g} {unit}, the middle of the recorded load range (from the fitted loop model): the test never "
                f"crosses zero torque, so the catalogue's hysteresis loss (the width at zero torque of a +/- rated "
                f"torque cycle) is not measured by it.")
    cycles = quantities.get("hysteresis_full_scale_cycles", (2, ""))[0]
    # a joint without return-point memory (Bouc-Wen-like) settles over cycles: its first full-scale cycle may
    # be wider than the steady one the catalogue quotes (up to 13 % over family 2's laws)
    caveat = "" if cycles >= 2 else (" Read on the recording's only full-scale cycle: a joint that settles over "
                                     "cycles reaches the catalogue's steady loss only after several.")
    return _loss_source(quantities) + _precision(quantities) + caveat


# a reliability engineer compares a loss with a catalogue limit or an earlier test to about 10 %: a reading
# less precise than that is said to be so, rather than left to a +/- in the text
LOSS_PRECISION = 0.10


def _precision(quantities: dict) -> str:
    se = quantities.get("hysteresis_loss_std_error_arcmin")
    value = quantities["hysteresis_loss_arcmin"][0]
    if se is None or not value > 0.0 or se[0] <= LOSS_PRECISION * value:
        return ""
    return (f" This recording fixes the loss only to +/- {100 * se[0] / value:.0f} % (one standard error): more "
            f"full-scale cycles or less noise would narrow it.")


def _loss_source(quantities: dict) -> str:
    value = quantities["hysteresis_loss_arcmin"][0]
    model = quantities["hysteresis_loss_model_arcmin"][0]
    if "hysteresis_loss_data_arcmin" in quantities:
        data = quantities["hysteresis_loss_data_arcmin"][0]
        se = quantities["hysteresis_loss_data_std_error_arcmin"][0]
        if quantities["hysteresis_loss_source"][0] == "data":
            return (f"Hysteresis loss {value:.4g} +/- {se:.2g} arcmin, read from the data at zero torque (steady "
                    f"branches, model-free): the fitted loop model's {model:.4g} arcmin is contradicted by the data "
                    f"(its loop has another shape there).")
        return (f"Hysteresis loss {value:.4g}{_pm(quantities)} arcmin from the fitted loop model; the data at zero "
                f"torque agree ({data:.4g} +/- {se:.2g} arcmin, model-free).")
    return (f"Hysteresis loss {value:.4g}{_pm(quantities)} arcmin from the fitted loop model (the data do not cover "
            f"zero torque on both steady full-scale branches, or a backlash band sits there).")


def _pm(quantities: dict) -> str:
    """The model width's standard error (fit, model-form spread and the sensor's wander between readings)."""
    se = quantities.get("hysteresis_loss_std_error_arcmin")
    return f" +/- {se[0]:.2g}" if se is not None else ""


def _parameter(display, name: str, value: float, unit: str, std_error: float | None) -> str:
    """``name = value +/- error unit`` in the recording's units."""
    v, u = display.convert(value, unit)
    se = None if std_error is None else display.convert(std_error, unit)[0]
    return f"{name} = {v:.4g}".rstrip() + (f" +/- {se:.2g}" if se is not None else "") + f" {u}"


def explain(diag) -> str:
    noise = diag.response_text(diag.noise_std)
    verdict = diag.verdict.value
    if verdict == "agrees":
        return (f"The recording agrees with the baseline ({diag.baseline.source}) within the noise "
                f"({noise}, coloured noise allowed for) and the stated {100 * diag.baseline.uncertainty:.0f} % "
                f"uncertainty of the simulated stiffness: residual RMS {diag.response_text(diag.rms_before)}; its "
                f"structure test finds nothing beyond the noise and no catalogue effect improves BIC by more than 10.")
    top = diag.effects[0] if diag.effects else None
    if verdict == "unexplained":
        sugg = ""
        # the best model may reach the noise and still not explain: its values break its own physics (a glitch
        # or a stuck channel, the other reasons, are said in the structure sentence)
        implausible = (top is not None and bool(top.warnings) and diag.gof_model is not None
                       and not diag.gof_model.structured)
        if top is not None:
            but = (f"it reaches the noise only with values its physics does not allow ({'; '.join(top.warnings)})"
                   if implausible else "it leaves a residual that is not noise")
            sugg = (f" The best partial model, offered only as a suggestion, is {top.id.replace('+', ' with ')} "
                    f"(delta BIC {top.delta_bic:.1f}, RMS {diag.response_text(diag.rms_before)} -> "
                    f"{diag.response_text(top.rms)}), but {but}.")
        none = ("no catalogue model explains it with plausible values" if implausible else
                "no catalogue model brings the residual back to the noise")
        return (f"MISMATCH NOT EXPLAINED: the recording departs from the baseline ({diag.baseline.source}) beyond "
                f"its noise ({noise}), and {none}. The residual: "
                f"{diag.structure}.{sugg} Check the rig (sensor channels, clamping, drift, sampling) before trusting "
                f"any named physics.")
    why = "; and ".join(CATALOGUE[c].explanation for c in top.components)
    params = ", ".join(_parameter(diag.display, k, v, u, top.errors.get(k))
                       for k, (v, u) in list(top.parameters.items())[:6])
    runner = ""
    if diag.runner_up is not None and diag.margin_bic is not None:
        runner = (f" The runner-up, {diag.runner_up}, scores {diag.margin_bic:.1f} BIC units worse"
                  f"{' - AMBIGUOUS: the data cannot tell the two apart' if diag.ambiguous else ''}.")
    warn = (" Warnings: " + "; ".join(top.warnings) + ".") if top.warnings else ""
    return (f"The recording departs from the baseline ({diag.baseline.source}) beyond its noise ({noise}) "
            f"and the {100 * diag.baseline.uncertainty:.0f} % stiffness uncertainty: {diag.located.description}. "
            f"The best explanation is {top.id.replace('+', ' together with ')}: {why}. Fitted: {params}. "
            f"It lowers the residual RMS from {diag.response_text(diag.rms_before)} to "
            f"{diag.response_text(diag.rms_after)} (BIC by "
            f"{top.delta_bic:.1f}, weight {top.weight:.2f}) and leaves a residual consistent with the noise."
            f"{runner}{warn}" + (" " + loss_sentence(diag.quantities) if diag.quantities else ""))
