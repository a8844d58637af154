"""Per row of `strainwave catalogue`: every missed goal and the physics the model leaves out that would move it.

One short phrase per (quantity, side of the miss), fixed here and held to what the decisions measured
(065-069; decision 069-cat48d section 3 and "Where this leaves item 5"; decision 070-loss48 for the loss rows).
A phrase names what is not modelled; where a decision measured its size, the phrase says so, and where
nothing measured it, the phrase says "not measured".
"""
from __future__ import annotations

from strainwave.analytic.catalogue_loss import ARCMIN

__all__ = ["BANDS", "PHRASES", "MU_SOURCE", "PINCHED_NOTE", "row_left_out", "loss_note", "loss_lines", "left_out_lines"]

# |predicted / catalogue - 1| beyond these is a miss: issue 48's goals; K2 has none there, so it takes K1's
# band (said in the output) so that a K2 miss is named too
BANDS = {"K1_Nm_per_rad": 0.35, "K2_Nm_per_rad": 0.35, "K3_Nm_per_rad": 0.25, "T1_Nm": 0.35, "T2_Nm": 0.35}
_SHORT = {"K1_Nm_per_rad": "K1", "K2_Nm_per_rad": "K2", "K3_Nm_per_rad": "K3", "T1_Nm": "T1", "T2_Nm": "T2",
          "hysteresis": "hysteresis loss", "lost_motion": "lost motion"}
PHRASES = {
    ("K1_Nm_per_rad", "high"): "compliance not modelled: the housing letting the circular spline ovalise (its body "
                               "is in series face-clamped; free, K1 came within on 19/21 rows, decision "
                               "070-cshousing48); without a stated class the teeth are ideal: pitch/profile errors "
                               "delay engagement (K1 16/21 at ISO 1328-1 class 5, decision 070-engage48; HD's class "
                               "unknown)",
    ("K1_Nm_per_rad", "low"): "support one linear foundation: no rim support that stiffens with load, no WG preload "
                              "(not measured)",
    ("K2_Nm_per_rad", "high"): "compliance not modelled: the housing letting the circular spline ovalise (with the "
                               "free body in series K2 came within +-35 % on 20/21 rows, decision 070-loss48)",
    ("K2_Nm_per_rad", "low"): "fewer teeth share the load than in a real S-tooth zone (not measured)",
    ("K3_Nm_per_rad", "high"): "compliance not modelled: the housing letting the circular spline ovalise (its body "
                               "is in series with the face clamped: 2 % of the miss; free it is the size of the miss; "
                               "bolts alone 5-18 %, decision 070-cshousing48)",
    ("K3_Nm_per_rad", "low"): "fewer teeth share the load than in a real S-tooth zone (not measured)",
    ("T1_Nm", "low"): "ideal teeth engage from 0 N m (i = 100: the knee is the balls' Hertz softening); pitch/profile "
                      "errors raise it at i >= 50, not at 30 (decision 070-engage48)",
    ("T1_Nm", "high"): "the ideal rack's contact-set growth: its first knee later than the real profile's "
                       "(not measured)",
    ("T2_Nm", "low"): "the engagement zone ends early: the real S-tooth adds teeth to higher torque",
    ("T2_Nm", "high"): "no clearance spread from manufacturing: profile and pitch errors (not measured)",
    ("hysteresis", "high"): "flank clearance: free play beyond the unit's (flank friction opens no loop at 0 N m "
                            "here, decision 070)",
    ("lost_motion", "high"): "low-torque twist too large: K1 too soft, no support stiffening or WG preload "
                             "(not measured)",
    ("lost_motion", "high, clearance"): "flank clearance: {play:.2f}' of free play at 0 N m (decision 070)",
    ("lost_motion", "high, test torque"): "test torque: 4 % of the rules' rated torque (the unit's own is not in the "
                                          "table); the catalogue's own K1 over the same +-4 % is above the bound "
                                          "too (its angle on the row)",
}
MU_SOURCE = ("the rules' flank mu (MeshRules.friction_coefficient), the shipped gear's: the 0.05-0.12 band of "
             "boundary-lubricated flanks (../shared/tooth-mesh-references.md section 4), not fitted to this table")
PINCHED_NOTE = ("hysteresis loss 0: flank friction here scales with the flank load, which is zero at 0 N m (the loop "
                "pinches there; 'max width' is its widest point): within the bound, but the bound cannot test mu; left "
                "out: friction with a load-free part (the WG's radial preload on teeth and balls)")


def _goal_misses(rp) -> list[dict]:
    out = []
    for name, band in BANDS.items():
        q = rp.ratio_of(name)
        if q is not None and abs(q - 1.0) > band:
            side = "high" if q > 1.0 else "low"
            out.append({"quantity": _SHORT[name], "side": side, "predicted_over_catalogue": q,
                        "band": band, "left_out": PHRASES[(name, side)]})
    return out


def _loss_misses(rp) -> list[dict]:
    loss = rp.loss
    if loss is None:
        return []
    out = []
    if loss.within("hysteresis") is False:
        out.append({"quantity": _SHORT["hysteresis"], "side": "high", "predicted_arcmin": loss.hysteresis_loss_arcmin,
                    "bound_arcmin": loss.hysteresis_bound_arcmin, "left_out": PHRASES[("hysteresis", "high")]})
    if loss.within("lost_motion") is False:
        k1 = rp.row.values.get("K1_Nm_per_rad")
        # the catalogue's own low-torque line over the same +/-4 % span: over the bound too -> the torque, not K1
        k1_lm = None if k1 is None else 2.0 * loss.lost_motion_torque_Nm / k1 / ARCMIN
        if k1_lm is not None and k1_lm >= loss.lost_motion_bound_arcmin:
            key = ("lost_motion", "high, test torque")
        elif loss.hysteresis_loss_arcmin > 1e-6:          # a loop open at 0 N m is free play in this model
            key = ("lost_motion", "high, clearance")
        else:
            key = ("lost_motion", "high")
        out.append({"quantity": _SHORT["lost_motion"], "side": "high", "predicted_arcmin": loss.lost_motion_arcmin,
                    "bound_arcmin": loss.lost_motion_bound_arcmin, "catalogue_K1_arcmin": k1_lm,
                    "left_out": PHRASES[key].format(k1=k1_lm or 0.0, play=loss.hysteresis_loss_arcmin)})
    return out


def row_left_out(rp) -> list[dict]:
    """Every miss of this row (goals and catalogue bounds), each with the one phrase for its side."""
    return _goal_misses(rp) + _loss_misses(rp)


def _flag(ok) -> str:
    return "-" if ok is None else ("within" if ok else "ABOVE")


def _bound(b) -> str:
    return "-" if b is None else f"<{b:g}"


def loss_lines(rows, mu: float | None = None) -> list[str]:
    """The loss table: predicted hysteresis loss and lost motion against the bounds, per row (``mu`` said above)."""
    lines = ["hysteresis loss (width at 0 N m of the +/-rated loop) and lost motion (end to end of a +/-4 % rated "
             "loop), arcmin; T_N the rules' (* the table's); bounds: the table's columns, else the CHA's "
             "(decision 070-loss48)" + ("" if mu is None else f"; flank mu = {mu:g}: {MU_SOURCE}"),
             f"{'size':>5} {'ratio':>5} {'hyst':>7} {'bound':>5} {'':>6} {'lost m':>7} {'bound':>5} {'':>6} "
             f"{'max width':>9} {'+-4 % T_N':>10} {'bounds':>9}"]
    for rp in rows:
        L = rp.loss
        if L is None:
            continue
        hyst = 0.0 if abs(L.hysteresis_loss_arcmin) < 5e-4 else L.hysteresis_loss_arcmin   # no "-0.000"
        lines.append(f"{rp.row.size:5g} {rp.row.ratio_label:>5} {hyst:7.3f} "
                     f"{_bound(L.hysteresis_bound_arcmin):>5} {_flag(L.within('hysteresis')):>6} "
                     f"{L.lost_motion_arcmin:7.3f} {_bound(L.lost_motion_bound_arcmin):>5} "
                     f"{_flag(L.within('lost_motion')):>6} {L.loop_width_max_arcmin:9.3f} "
                     f"{L.lost_motion_torque_Nm:8.3g}{'*' if L.test_torque_from == 'table' else ' ':1} "
                     f"{L.bounds_from:>10}")
    note = loss_note(rows)
    return lines + ([f"  {note}"] if note else [])


def loss_note(rows) -> str | None:
    """The note a zero hysteresis loss needs (a pinched loop meets any bound), or None."""
    pinched = [rp for rp in rows if rp.loss is not None and abs(rp.loss.hysteresis_loss_arcmin) < 1e-6]
    return PINCHED_NOTE if pinched else None


def left_out_lines(rows) -> list[str]:
    """One line per row with a miss (each missed quantity, its side, a note number) and, once, the notes: the same
    phrase recurs on most rows, so it is printed once."""
    notes: dict[str, int] = {}
    lines = [f"left out, per row (K2 takes K1's +/-{BANDS['K2_Nm_per_rad']:.0%}: issue 48 sets no K2 goal; "
             f"[n]: the note below):"]
    for rp in rows:
        parts = []
        for m in row_left_out(rp):
            how = (f"{m['predicted_over_catalogue']:.2f}x" if "predicted_over_catalogue" in m
                   else f"{m['predicted_arcmin']:.2f}' > {m['bound_arcmin']:g}'")
            if m.get("catalogue_K1_arcmin") is not None and "test torque" in m["left_out"]:
                how += f" (catalogue K1: {m['catalogue_K1_arcmin']:.2f}')"
            parts.append(f"{m['quantity']} {how} [{notes.setdefault(m['left_out'], len(notes) + 1)}]")
        if parts:
            lines.append(f"  {rp.row.size:g}/{rp.row.ratio_label}: " + ", ".join(parts))
    return lines + [f"  [{k}] {text}" for text, k in notes.items()]
