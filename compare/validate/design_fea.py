"""The design verdict's factors on the FEA's stresses, by the one method of ``analytic.design_method`` (issue 49).

Each factor takes its cycle from the FEA where a study solved it, and from the closed form
(``analytic.design_factors``) where none did, saying which:
- ``ring``: study ring-compression at the operating W0: the smooth ring's inner-fibre hoop stress at B and D
  (the tooth root's fibre), amplitude times the FEA's own root factor K_delta K_sigma (``root_stress_factor``,
  the toothed ring's root peak over the smooth inner fibre), mean times the FEA's K_delta: the FEA's own
  notched peak, notch 1 (never the fitted factors as well).
- ``cup_tooth_root``: study wg-cup's revolution cycle of the smooth band at the root circle (contact,
  nonlinear, rated T), with the fitted tooth factors, the closed-form mesh load and the FEA's torque shear.
- ``wg_inner_ring``: study wg-bearing: the cam's hoop stress at the race (a mean: the ring turns with the cam)
  and half the change the rated ball loads add at the load line (the amplitude of the ball passes).
- ``wg_outer_ring``: closed form (no study models the outer ring).
- ``cup_diaphragm``: closed form (no study resolves the diaphragm: wg-cup holds the closed end round), the annular
  plate of analytic/diaphragm.py, stated as closed form in its sources.
- ``cup_band_edge``: study wg-cup, prescribed linear: the wall's bending at the band's edge (station 1.0 band
  widths from the rim), fully reversed as the wave passes, a smooth wall (notch 1).
- every other reported component (torsion of the cup and the shaft): its FEA peak von Mises at the rated
  torque, fully reversed (the torque reverses with the motion), notch 1 (the FEA's own peak).
Every GCI-carrying cycle carries its band (``design.factor_band``).
"""
from __future__ import annotations

from dataclasses import replace

from strainwave.analytic import design_factors as df
from strainwave.analytic.design_method import FatigueFactor, flexspline_steel, goodman
from strainwave.compare.validate.design import ComponentFactor, factor_band

__all__ = ["design_factors_from_fea", "REPLACED_COMPONENTS"]

# Reported components whose material-only peak factor the method's factor replaces (the seed-000 bearing ring's
# peak is the seed's contact patch: the bearing is judged by wg_inner_ring, wg_outer_ring and its ratings).
REPLACED_COMPONENTS = ("ring", "bearing")


def _q(book, label, name):
    return book.quantity(label, name)[0] if label else None


def ring_fea(book, label, params) -> dict | None:
    names = ("sigma_B_inner_MPa", "sigma_D_inner_MPa", "root_stress_factor", "tooth_influence")
    q = {n: _q(book, label, n) for n in names}
    if any(v is None for v in q.values()):
        return None
    b, d, kk, kd = (q[n] for n in names)

    def cycle(sb, sd, prod, infl):
        return prod * 0.5 * abs(sd - sb), infl * 0.5 * (sd + sb)
    amp, mean = cycle(b.value, d.value, kk.value, kd.value)
    steel = flexspline_steel(params)
    band = factor_band(lambda *v: goodman(*cycle(*v), 1.0, steel), *((x.value, x.uncertainty) for x in (b, d, kk, kd)))
    return {"amplitude_MPa": amp, "mean_MPa": mean, "band": band, "notch_source": "1: the FEA's own root peak",
            "amplitude_source": (f"FEA {label}: K_delta K_sigma = {kk.value:.4g} (toothed root peak / smooth inner fibre) x "
                                 f"half the smooth inner fibre's swing B {b.value:.4g} -> D {d.value:.4g} MPa"),
            "mean_source": f"FEA {label}: K_delta = {kd.value:.4g} x the smooth inner fibre's mean (tensile at the root)",
            "load": "EWG deformation W0 = 0.5 m dZ (seed 003 eq 7), FEA"}


def cup_fea(record: dict) -> dict | None:
    f = record.get("fatigue") if record else None
    if not f:
        return None
    band = None
    if f.get("amplitude_gci_MPa") is not None and f.get("mean_gci_MPa") is not None:
        band = (f["amplitude_MPa"], f["amplitude_gci_MPa"]), (f["mean_MPa"], f["mean_gci_MPa"])
    return {"amplitude_MPa": f["amplitude_MPa"], "mean_MPa": f["mean_MPa"], "_band_inputs": band,
            "source": f"FEA {record.get('case', '')}: the smooth band's root-circle cycle, contact, nonlinear, rated T"}


def inner_ring_fea(book, label, params) -> dict | None:
    cam, net = _q(book, label, "race_stress_major_MPa"), _q(book, label, "net_race_stress_major_MPa")
    if cam is None or net is None:
        return None
    amp, mean = 0.5 * abs(net.value - cam.value), 0.5 * (net.value + cam.value)
    steel = df.bearing_steel(params)
    band = factor_band(lambda c, n: goodman(0.5 * abs(n - c), 0.5 * (n + c), 1.0, steel),
                       (cam.value, cam.uncertainty), (net.value, net.uncertainty))
    return {"amplitude_MPa": amp, "mean_MPa": mean, "band": band,
            "amplitude_source": (f"FEA {label}: half the change the rated ball loads add at the race's load line, "
                                 f"cam alone {cam.value:.4g} -> cam + balls {net.value:.4g} MPa"),
            "mean_source": f"FEA {label}: the midpoint of that swing (the cam's bending is steady: the ring turns with it)"}


def band_edge_factor(book, label, params) -> FatigueFactor | None:
    from strainwave.fea.cup_wave_generator import STATIONS

    q = _q(book, label, f"end_bending_major_s{STATIONS.index(1.0)}_MPa")
    if q is None:
        return None
    steel = flexspline_steel(params)
    band = factor_band(lambda a: goodman(abs(a), 0.0, 1.0, steel), (q.value, q.uncertainty))
    factor = FatigueFactor("cup_band_edge", df.TITLES["cup_band_edge"], abs(q.value), 0.0,
                           f"FEA {label}: the wall's bending (outer - inner)/2 at the band's edge, major axis, prescribed w0",
                           "0: fully reversed, the wave passes twice per input revolution", 1.0,
                           "1: the smooth wall beyond the teeth", steel, params.ewg_drive.permissible_safety,
                           "wave generator insertion w0", band=band)
    # the wall's thickness scales its bending: the advice follows the ring's closed form, scaled to the FEA
    return df.with_advice(factor, params, "flexspline_cup.wall_thickness_mm", df.band_edge_closed,
                          (0.1, 0.1 * params.flexspline_cup.pitch_diameter_mm))


def peak_factor(component: str, title: str, at, params) -> FatigueFactor:
    """A reported component's FEA peak von Mises at its rated load, fully reversed."""
    return FatigueFactor(component, title, at.peaks.peak_von_mises_MPa, 0.0,
                         f"FEA peak von Mises at the rated load ({at.load.describe()})",
                         "0: fully reversed (the rated torque reverses with the motion)", 1.0,
                         "1: the FEA's own peak", flexspline_steel(params), params.ewg_drive.permissible_safety,
                         at.load.describe())


def _fe_mesh_load(book, label) -> dict:
    """The tooth-mesh study's largest flank load at rated (for the cup's factor beside its closed-form mesh load)."""
    q = _q(book, label, "peak_tooth_load_N")
    if q is None:
        return {}
    root = _q(book, label, "root_stress_peak_tooth_MPa")
    return {"mesh_peak_force_N": q.value, "mesh_source": f"FEA {label}: the largest flank load at rated, "
            f"{q.value:.4g} +- {q.uncertainty or 0.0:.2g} N (GCI)",
            "mesh_root_fe_MPa": None if root is None else root.value}


def design_factors_from_fea(params, book, labels: dict, stresses: dict, titles: dict, components,
                            wg_cup_record: dict) -> list[ComponentFactor]:
    """Every factor of the verdict (module docstring); ``labels``: study -> case label (or None)."""
    out = []
    for component in components:
        if component in REPLACED_COMPONENTS:
            continue
        at = stresses.get(component)
        if at is None:
            out.append(ComponentFactor(component, titles[component], None, "Goodman on the FEA peak", None, None, "",
                                       "its FEA case or stress field failed (see the cases table)"))
        else:
            out.append(ComponentFactor.of(peak_factor(component, titles[component], at, params)))
    ring = ring_fea(book, labels.get("ring-compression"), params)
    out.append(ComponentFactor.of(df.ring_factor(params, ring)) if ring else _not_run("ring"))
    cup = cup_fea(wg_cup_record)
    if cup is not None:
        cup |= _fe_mesh_load(book, labels.get("tooth-mesh"))
        closed = df.cup_tooth_root_factor(params, {**cup, "band": None})
        inputs = cup.pop("_band_inputs")
        band = None if inputs is None else factor_band(
            lambda a, m: df.cup_tooth_root_factor(params, {**cup, "amplitude_MPa": abs(a), "mean_MPa": m}).n, *inputs)
        out.append(ComponentFactor.of(replace(closed, band=band)))
    else:
        out.append(_not_run("cup_tooth_root"))
    edge = band_edge_factor(book, labels.get("cup-wave-generator"), params)
    out.append(ComponentFactor.of(edge) if edge else _not_run("cup_band_edge"))
    inner = inner_ring_fea(book, labels.get("wg-bearing"), params)
    out.append(ComponentFactor.of(df.wg_inner_ring_factor(params, inner)) if inner else _not_run("wg_inner_ring"))
    out.append(ComponentFactor.of(df.wg_outer_ring_factor(params)))
    out.append(ComponentFactor.of(df.diaphragm_factor(params)))
    return out


def _not_run(component: str) -> ComponentFactor:
    return ComponentFactor(component, df.TITLES[component], None, "Goodman (analytic/design_method.py)", None, None, "",
                           "its FEA case did not run or failed (see the cases table); the closed form is in "
                           "`strainwave analytic`")
