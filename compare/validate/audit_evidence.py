"""The seed audit with the FEA evidence that settles each item where the FEA can.

Every inconsistency from ``analytic.audit`` is listed. Where the item names a check (``fea_check``), the
check's verdict is attached: ``corrected`` or ``published`` settles it, ``both`` means the FEA cannot
tell the variants apart at its tolerance, ``neither`` means both disagree with the FEA. Two items get
evidence of their own: the crack-compliance exponent (a^2 or a^3, fitted from the shaft's sweep) and the
shape of the deformed ring (delta_AB/delta_CD: 0.918 for the thin ring, 1 for an ellipse).
"""
from __future__ import annotations

from .checks import Check
from .crack_scaling import PowerFit, closer_exponent

SETTLES = {"corrected": "FEA supports the corrected form", "published": "FEA supports the published form",
           "both": "FEA cannot tell the variants apart at its tolerance",
           "neither": "FEA contradicts both variants", "not evaluated": "no FEA evidence (check not evaluated)"}


def exponent_evidence(fit: PowerFit | None, analytic_exponents: dict[str, float]) -> dict:
    """FEA exponent of delta_lambda(a) against the exponents of the closed forms over the same depths."""
    if fit is None:
        return {"kind": "crack exponent", "settles": "not evaluated",
                "finding": "fewer than two resolved sweep depths: no exponent fitted"}
    band = 2.0 * (fit.stderr or 0.0)
    closer = closer_exponent(fit.exponent, analytic_exponents)
    other = next((k for k in analytic_exponents if k != closer), closer)
    # Decisive only if the fitted exponent is nearer one variant by more than its own 2-sigma band.
    decisive = abs(fit.exponent - analytic_exponents[other]) - abs(fit.exponent - analytic_exponents[closer]) > band
    return {"kind": "crack exponent", "fit": fit.to_dict(), "analytic_exponents": analytic_exponents,
            "settles": closer if decisive else "both",
            "finding": (f"FEA delta_lambda ~ a^{fit.exponent:.2f}" + (f" +/- {band:.2f} (2 sigma)" if band else "")
                        + f" over {fit.points} depths; closed forms over the same depths: "
                        + ", ".join(f"{k} a^{v:.2f}" for k, v in analytic_exponents.items())
                        + f" -> {closer}" + ("" if decisive else " (not decisive)"))}


def ellipse_evidence(checks: dict[str, Check]) -> dict | None:
    cd, ab = checks.get("ring.delta_cd"), checks.get("ring.delta_ab")
    if cd is None or ab is None or cd.fea in (None, 0.0) or ab.fea is None:
        return None
    ratio = abs(ab.fea / cd.fea)
    thin = abs(ab.analytic.get("published", 0.0) / cd.analytic["published"]) if cd.analytic.get("published") else None
    return {"kind": "ring shape", "fea_ratio_delta_ab_over_delta_cd": ratio, "thin_ring_ratio": thin,
            "ellipse_ratio": 1.0, "settles": "corrected" if abs(ratio - 1.0) > 0.02 else "published",
            "finding": f"FEA delta_AB/delta_CD = {ratio:.4f}; thin ring {thin:.4f}; an ellipse would give 1"
            if thin else f"FEA delta_AB/delta_CD = {ratio:.4f}; an ellipse would give 1"}


def audit_with_evidence(records: list[dict], checks: dict[str, Check], *, shaft_exponent: dict | None) -> list[dict]:
    """Each audit record plus ``fea_evidence`` (a list) and ``settled`` (a one-line finding)."""
    out = []
    for rec in records:
        evidence = []
        check = checks.get(rec.get("fea_check") or "")
        if check is not None:
            evidence.append({"kind": "check", "check": check.id, "verdict": check.verdict, "passed": check.passed,
                             "fea": check.fea, "rel_error": dict(check.rel_error),
                             "tolerance": check.tolerance.relative, "settles": check.verdict,
                             "finding": SETTLES.get(check.verdict, check.verdict)})
        if rec.get("id") == 10 and shaft_exponent is not None:
            evidence.append(shaft_exponent)
        if rec.get("id") == 5:
            shape = ellipse_evidence(checks)
            if shape is not None:
                evidence.append(shape)
        decisive = [e for e in evidence if e.get("settles") in ("corrected", "published", "neither")]
        settled = (decisive[-1]["finding"] if decisive else
                   (evidence[-1]["finding"] if evidence else "not an FEA question (arithmetic or wording)"))
        out.append({**rec, "fea_evidence": evidence, "settled": settled,
                    "settled_by_fea": bool(decisive) and decisive[-1]["settles"] in ("corrected", "published")})
    return out
