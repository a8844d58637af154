"""Every design factor of the drive in closed form, by the one method of ``analytic.design_method``, and the
wave generator bearing's ratings (Hertz p0, ISO 76 static, ISO 281 L10).

The factors (component key: the point and its cycle):
- ``ring``: the EWG flexspline ring's tooth root (inner fibre). The ring passes the generator's major and
  minor axes: seed 003's eqs 10-11 corrected, sigma_a = K_delta 6.7214 X, sigma_m = +K_delta 1.8366 X
  (tensile at the inner fibre), X = W0 E delta / d_m^2; notch K_sigma; K_delta, K_sigma from the project's
  tooth-factor fit at this rim (analytic/tooth_factors.py). Z_R,min by the same line: ``minimal_teeth``.
- ``cup_tooth_root``: the cup's tooth root on the wave generator: the wave's bending, fully reversed
  (E' t/2 (n^2-1) w0 / r_m^2, analytic/ring_prescribed.py), times K_delta; the mesh load, pulsating 0 ->
  sigma_F twice per revolution, sigma_F = 6 F0 (1.35 m) / (b s^2) with s = pi m/2 (a cantilever tooth loaded at
  the pitch circle) and F0 = pi T/(R z), the peak of the CLOSED-FORM load distribution F0 cos 2 phi over
  +-45 deg at both mesh zones (the tooth-mesh FE's peak flank load, 10-13x larger on the shipped gears, is
  shown beside it with the factor it implies, not used: ``fe_mesh_load_beside``); the torque's shear
  tau = T/(2 pi r_m^2 t), a steady mean, as sqrt(sigma_m^2 + 3 tau^2); notch K_sigma on the amplitude.
- ``wg_inner_ring``: the bearing's inner ring at the race, major axis: the ring turns with the cam, so the
  cam's bending (curved beam, analytic/wg_bearing.py) is a steady mean; the balls press the ring onto the cam
  through its thickness: the structural amplitude they add is the FEA's (validate), zero in closed form. The
  contact itself is rolling-contact fatigue: ISO 281's L10 and ISO 76's static p0, not Goodman on p0.
- ``wg_outer_ring``: the flexible outer ring, bent into the wave and turning with the flexspline: the wave
  passes it twice per input revolution, fully reversed, 3 E t_o w0 / (2 r_o^2).
"""
from __future__ import annotations

import math
from dataclasses import replace

from strainwave.analytic import fatigue, ring, ring_prescribed, tooth_factors, tooth_number, torsion, wg_bearing
from strainwave.analytic import wg_contact
from strainwave.analytic.design_method import (Advice, FatigueFactor, bearing_steel, flexspline_steel, goodman,
                                               solve_for)

__all__ = ["ring_factor", "cup_tooth_root_factor", "wg_inner_ring_factor", "wg_outer_ring_factor", "diaphragm_factor",
           "closed_form_factors", "bearing_ratings", "minimal_teeth", "materials_table", "TITLES"]

TITLES = {"ring": "EWG flexspline ring, tooth root", "cup_tooth_root": "Flexspline cup, tooth root on the wave generator",
          "wg_inner_ring": "Wave generator bearing inner ring (race, major axis)",
          "wg_outer_ring": "Wave generator bearing outer ring (bent by the wave)",
          "cup_band_edge": "Flexspline cup, band edge", "cup_diaphragm": "Flexspline cup, diaphragm"}
RATED = "rated output torque T (gear.rated_output_torque_Nmm)"


def materials_table(params) -> dict[str, dict]:
    """One material per part, with its source."""
    f, b = flexspline_steel(params).to_dict(), bearing_steel(params).to_dict()
    return {"flexspline cup": f, "EWG flexspline ring": f, "output shaft": f,
            "wave generator bearing: inner ring, outer ring, balls": b}


# ---- EWG ring -----------------------------------------------------------------------------------------------
def ring_cycle(params) -> dict:
    """X, K_delta, K_sigma of the ring (fitted tooth factors at this rim) and its smooth inner-fibre cycle."""
    e, E = params.ewg_drive, params.material.youngs_modulus_MPa
    delta = e.rim_thickness_mm
    r_m = ring.mid_layer_radius_mm(e.module_mm, e.flexspline_teeth, delta, e.dedendum_coefficient)
    w0 = ring.radial_deformation_from_teeth_mm(e.module_mm, e.tooth_difference)
    x = w0 * E * delta / (2.0 * r_m) ** 2
    h = tooth_factors.tooth_height_mm(e.module_mm, e.dedendum_coefficient)
    kd = tooth_factors.tooth_influence(h / delta, e.module_mm / delta, tooth_factors.FITTED)
    ks = tooth_factors.stress_concentration(h / delta, e.module_mm / delta, tooth_factors.FITTED)
    return {"X_MPa": x, "K_delta": kd, "K_sigma": ks, "amplitude_smooth_MPa": fatigue.amplitude_coefficient() * x,
            "mean_smooth_MPa": -fatigue.mean_stress_coefficient() * x}   # inner fibre: the mean is tensile


def fit_margin() -> float:
    """The fitted K_delta K_sigma's largest unconservative error where the toothed-ring FEA was solved at a rim
    it was not fitted on (tooth_number.FEA_AT_MINIMUM: FEA product / model product - 1, at least 0): Z_R,min is
    found at [n] (1 + this), so that the FEA's own root cycle at that Z_R still meets [n]."""
    worst = 0.0
    for (z, _), fea in tooth_number.FEA_AT_MINIMUM.items():
        hd, md = tooth_number.rim_ratios(z, fatigue.ToothDesign())
        model = tooth_factors.root_product(hd, md, tooth_factors.FITTED)
        worst = max(worst, fea["tooth_influence"] * fea["stress_concentration"] / model - 1.0)
    return worst


def minimal_teeth(params, tooth_difference: int | None = None) -> tooth_number.ToothNumberResult:
    """Z_R,min by Goodman (eq 14 with psi_sigma = sigma_-1/R_m), tooth factors at each Z_R (the ring factor's
    line), at [n] (1 + fit_margin())."""
    from strainwave.analytic.seed003 import design_from_params

    e, m = params.ewg_drive, params.material
    design = replace(design_from_params(params), mean_stress_influence=m.fatigue_limit_MPa / m.ultimate_strength_MPa)
    return tooth_number.minimal_teeth_with_model(tooth_difference or e.tooth_difference,
                                                 e.permissible_safety * (1.0 + fit_margin()),
                                                 m.fatigue_limit_MPa, m.youngs_modulus_MPa, design)


def ring_factor(params, fea: dict | None = None, advise: bool = True) -> FatigueFactor:
    """The ring's factor; ``fea`` = {amplitude_MPa, mean_MPa, band, source}: the FEA's own root cycle (notch 1)."""
    c = ring_cycle(params)
    n_req = params.ewg_drive.permissible_safety
    if fea is None:
        amp, mean, notch = c["K_delta"] * c["amplitude_smooth_MPa"], c["K_delta"] * c["mean_smooth_MPa"], c["K_sigma"]
        a_src = (f"seed 003 eq 11 corrected: K_delta 6.7214 W0 E delta/d_m^2 = {c['K_delta']:.3f} x 6.7214 x "
                 f"{c['X_MPa']:.4g} MPa (inner fibre)")
        m_src = f"seed 003 eq 10 corrected: +K_delta 1.8366 X (tensile at the inner fibre, the tooth root)"
        n_src = f"K_sigma = {c['K_sigma']:.3f}, the tooth-factor fit at this rim (K_delta = {c['K_delta']:.3f})"
        band, load = None, "EWG deformation W0 = 0.5 m dZ (seed 003 eq 7)"
    else:
        amp, mean, notch, band = fea["amplitude_MPa"], fea["mean_MPa"], 1.0, fea.get("band")
        a_src, m_src, n_src, load = fea["amplitude_source"], fea["mean_source"], fea["notch_source"], fea["load"]
    advice = None
    if advise and goodman(amp, mean, notch, flexspline_steel(params)) < n_req:
        z = minimal_teeth(params).Z_R_min
        advice = Advice("ewg_drive.flexspline_teeth", float(z), ">=", (2.0, 5000.0),
                        f"Goodman's eq 14, the fitted tooth factors at each Z_R, [n] x (1 + {fit_margin():.3f}): "
                        "the fit's error where the FEA checked it")
    return FatigueFactor("ring", TITLES["ring"], amp, mean, a_src, m_src, notch, n_src, flexspline_steel(params),
                         n_req, load, band=band, advice=advice, extra={"closed_form": c})


# ---- the cup's tooth root --------------------------------------------------------------------------------------
def cup_cycle(params) -> dict:
    """The cup's tooth-root stresses (module docstring): wave bending, mesh load, torque shear, tooth factors."""
    fc, mat, g = params.flexspline_cup, params.material, params.gear
    t, m = fc.wall_thickness_mm, fc.module_mm
    r_m = 0.5 * (fc.pitch_diameter_mm - t)
    bend = float(ring_prescribed.hoop_bending_stress_MPa(0.0, g.radial_deformation_mm, t, r_m, mat.youngs_modulus_MPa,
                                                         mat.poisson_ratio, wave_number=g.wave_number))
    T = g.rated_output_torque_Nmm
    f0 = math.pi * T / (0.5 * m * fc.teeth * fc.teeth)
    b, s = params.circular_spline.face_width_mm, 0.5 * math.pi * m
    sigma_f = 6.0 * f0 * 1.35 * m / (b * s * s)
    tau = T / (2.0 * math.pi * r_m ** 2 * t)
    h = tooth_factors.tooth_height_mm(m, 1.35)
    kd = tooth_factors.tooth_influence(h / t, m / t, tooth_factors.FITTED)
    ks = tooth_factors.stress_concentration(h / t, m / t, tooth_factors.FITTED)
    return {"bending_MPa": bend, "mesh_peak_force_N": f0, "mesh_root_MPa": sigma_f, "shear_MPa": tau,
            "K_delta": kd, "K_sigma": ks, "r_m_mm": r_m}


# Which of the cup's two tooth-root factors is the verdict, and why (issue 49: analytic 1.9 against validate 1.19)
CUP_GOVERNS = ("validate's FEA governs (study cup-wave-generator: the band on the rigid cam, nonlinear, rated T). The "
               "closed form is the wall's bending alone, a ring forced into w0 cos 2phi (fully reversed, no mean); the "
               "FEA's root-circle cycle adds what that ring cannot hold: the membrane hoop stress of the coned band "
               "and the cam's contact (the band leaves the cam between the axes: a larger swing and a tensile mean; "
               "docs/decisions/067-design49b-buckling-and-advice.md gives both gears' numbers). Same tooth factors, "
               "mesh load and shear in both: only the wave's cycle differs")


def cup_tooth_root_factor(params, fea: dict | None = None, advise: bool = True) -> FatigueFactor:
    """The cup's tooth-root factor; ``fea`` = {amplitude_MPa, mean_MPa, band}: the smooth band's cycle from the
    FEA of the cup on the wave generator (replacing the wave's bending and its mean), the tooth factors kept."""
    c = cup_cycle(params)
    bend_a, bend_m = (c["bending_MPa"], 0.0) if fea is None else (fea["amplitude_MPa"], fea["mean_MPa"])
    amp = c["K_delta"] * bend_a + 0.5 * c["mesh_root_MPa"]
    normal_mean = c["K_delta"] * bend_m + 0.5 * c["mesh_root_MPa"]
    mean = math.copysign(math.sqrt(normal_mean ** 2 + 3.0 * c["shear_MPa"] ** 2), normal_mean)
    bend_src = ("E' t/2 3 w0/r_m^2, the wall forced into w0 cos 2phi (analytic/ring_prescribed.py)" if fea is None
                else fea["source"])
    a_src = (f"K_delta x wave bending {bend_a:.4g} MPa ({bend_src}) + half the mesh root stress "
             f"{c['mesh_root_MPa']:.4g} MPa (6 F0 1.35 m/(b s^2), F0 = pi T/(R z) = {c['mesh_peak_force_N']:.4g} N: the "
             "closed-form cos 2phi load over +-45 deg; the tooth-mesh FE's flank load is shown beside)")
    m_src = (f"half the mesh root stress (pulsating) + K_delta x the wave's mean {bend_m:.4g} MPa, with the torque's "
             f"shear tau = T/(2 pi r_m^2 t) = {c['shear_MPa']:.4g} MPa as sqrt(sigma_m^2 + 3 tau^2)")
    n_src = f"K_sigma = {c['K_sigma']:.3f} (K_delta = {c['K_delta']:.3f}), the tooth-factor fit at the cup's h/t, m/t"
    extra = {"closed_form": c, "governs": CUP_GOVERNS}
    if fea is not None:
        extra["closed_form_n"] = cup_tooth_root_factor(params, None, False).n
    if fea is not None and fea.get("mesh_peak_force_N"):
        extra["fe_mesh_load"] = fe_mesh_load_beside(params, fea, c)
    factor = FatigueFactor("cup_tooth_root", TITLES["cup_tooth_root"], amp, mean, a_src, m_src, c["K_sigma"], n_src,
                           flexspline_steel(params), params.ewg_drive.permissible_safety,
                           f"wave generator insertion w0 + {RATED}", band=None if fea is None else fea.get("band"),
                           extra=extra)
    if not advise:
        return factor
    return _with_advice(factor, params, "flexspline_cup.wall_thickness_mm", cup_tooth_root_factor, fea,
                        (0.1, 0.5 * params.flexspline_cup.pitch_diameter_mm * 0.2))


def fe_mesh_load_beside(params, fea: dict, c: dict) -> dict:
    """The same factor with the tooth-mesh study's peak flank load in place of the closed form's F0: shown beside
    the verdict, not the verdict (the FE mesh is 1.2-2x stiffer than the catalogue's drives, decision 067-cat48b,
    so how many teeth share the load is not settled)."""
    F = float(fea["mesh_peak_force_N"])
    m, b = params.flexspline_cup.module_mm, params.circular_spline.face_width_mm
    s = 0.5 * math.pi * m
    root = 6.0 * F * 1.35 * m / (b * s * s)
    amp = c["K_delta"] * fea["amplitude_MPa"] + 0.5 * root
    normal_mean = c["K_delta"] * fea["mean_MPa"] + 0.5 * root
    mean = math.copysign(math.sqrt(normal_mean ** 2 + 3.0 * c["shear_MPa"] ** 2), normal_mean)
    n = goodman(amp, mean, c["K_sigma"], flexspline_steel(params))
    out = {"peak_force_N": F, "closed_form_peak_force_N": c["mesh_peak_force_N"], "mesh_root_MPa": root,
           "amplitude_MPa": amp, "mean_MPa": mean, "n": n, "source": fea.get("mesh_source", "FEA tooth-mesh")}
    if fea.get("mesh_root_fe_MPa") is not None:
        # the FE's fillet peak is notched already; Goodman multiplies the amplitude by K_sigma (a fit for the wave's
        # bending, not the tooth's), so it enters divided by K_sigma: the notch counted once, shown beside only
        fe_root = float(fea["mesh_root_fe_MPa"]) / c["K_sigma"]
        amp_fe = c["K_delta"] * fea["amplitude_MPa"] + 0.5 * fe_root
        nm_fe = c["K_delta"] * fea["mean_MPa"] + 0.5 * fe_root
        mean_fe = math.copysign(math.sqrt(nm_fe ** 2 + 3.0 * c["shear_MPa"] ** 2), nm_fe)
        out |= {"fe_root_MPa": float(fea["mesh_root_fe_MPa"]),
                "n_fe_root": goodman(amp_fe, mean_fe, c["K_sigma"], flexspline_steel(params))}
    return out


def band_edge_closed(params, fea: dict | None = None, advise: bool = False) -> FatigueFactor:
    """The band edge's dependence on the parameters for the advice only: the wall's bending of a ring forced into
    w0 cos 2phi (its FEA factor is the verdict, compare/validate/design_fea.band_edge_factor)."""
    c = cup_cycle(params)
    return FatigueFactor("cup_band_edge", TITLES["cup_band_edge"], c["bending_MPa"], 0.0,
                         "E' t/2 3 w0/r_m^2 (analytic/ring_prescribed.py)", "0: fully reversed", 1.0, "1: smooth wall",
                         flexspline_steel(params), params.ewg_drive.permissible_safety, "wave generator insertion w0")


def with_advice(factor: FatigueFactor, params, key: str, build, span: tuple[float, float]) -> FatigueFactor:
    """``_with_advice`` for a factor computed on the FEA (``build``: its closed-form dependence on ``key``)."""
    return _with_advice(factor, params, key, build, {}, span)


# ---- the wave generator bearing -------------------------------------------------------------------------------
def inner_ring_radii(params) -> tuple[float, float]:
    from strainwave.geometry.bearing_ring import check_ring_fits
    return check_ring_fits(params)


def wg_inner_ring_factor(params, fea: dict | None = None, advise: bool = True) -> FatigueFactor:
    """The inner ring at the race (module docstring); ``fea`` = {mean_MPa, amplitude_MPa, band, source}."""
    r_race, r_bore = inner_ring_radii(params)
    E = params.material.youngs_modulus_MPa
    cam = wg_bearing.curved_beam_race_stress_MPa(E, r_bore, r_race, params.gear.radial_deformation_mm)
    if fea is None:
        amp, mean, band = 0.0, cam, None
        a_src = ("none in closed form: the balls press the ring onto the cam through its thickness (the FEA's "
                 "wg-bearing study gives the bending they add)")
        m_src = f"the cam's bending at the race, curved beam (analytic/wg_bearing.py), r = {r_bore:.4g}..{r_race:.4g} mm"
    else:
        amp, mean, band, a_src, m_src = (fea["amplitude_MPa"], fea["mean_MPa"], fea.get("band"),
                                         fea["amplitude_source"], fea["mean_source"])
    factor = FatigueFactor("wg_inner_ring", TITLES["wg_inner_ring"], amp, mean, a_src, m_src, 1.0,
                           "1: a smooth ground race (the contact's own stress is judged by ISO 281/76, ratings)",
                           bearing_steel(params), params.ewg_drive.permissible_safety,
                           "wave generator insertion w0 + rated radial force F_r", band=band,
                           extra={"closed_form_cam_MPa": cam})
    if not advise:
        return factor
    return _with_advice(factor, params, "wave_generator.bearing_inner_ring_thickness_mm", wg_inner_ring_factor, fea,
                        (0.1, 0.95 * r_race), admissible=True)


def wg_outer_ring_factor(params, fea: dict | None = None, advise: bool = True) -> FatigueFactor:
    wg, fc = params.wave_generator, params.flexspline_cup
    r_o = 0.5 * fc.pitch_diameter_mm - fc.wall_thickness_mm - 0.5 * wg.outer_ring_thickness_mm
    amp = wg_contact.outer_ring_bending_MPa(params.material.youngs_modulus_MPa, wg.outer_ring_thickness_mm, r_o,
                                            params.gear.radial_deformation_mm, params.gear.wave_number)
    factor = FatigueFactor("wg_outer_ring", TITLES["wg_outer_ring"], amp, 0.0,
                           f"(n^2-1) E t_o w0/(2 r_o^2), r_o = {r_o:.4g} mm: the ring follows the flexspline's bore",
                           "0: fully reversed, the wave passes the ring twice per input revolution", 1.0,
                           "1: a smooth ground ring", bearing_steel(params), params.ewg_drive.permissible_safety,
                           "wave generator insertion w0")
    if not advise:
        return factor
    return _with_advice(factor, params, "wave_generator.outer_ring_thickness_mm", wg_outer_ring_factor, None,
                        (0.1, 0.5 * r_o), admissible=True)


def diaphragm_factor(params, fea: dict | None = None, advise: bool = True) -> FatigueFactor:
    """The diaphragm in closed form (no study resolves it): analytic/diaphragm.py's annular plate under the wave
    generator's coning (fully reversed) with the torque's shear at the hub as the steady mean."""
    from strainwave.analytic.diaphragm import diaphragm_geometry, diaphragm_stresses
    a, b, t, lever = diaphragm_geometry(params)
    m = params.material
    s = diaphragm_stresses(a, b, t, lever, params.gear.radial_deformation_mm, params.gear.rated_output_torque_Nmm,
                           m.youngs_modulus_MPa, m.poisson_ratio)
    where = "hub" if abs(s.hub_bending_MPa) >= abs(s.wall_bending_MPa) else "wall"
    factor = FatigueFactor(
        "cup_diaphragm", TITLES["cup_diaphragm"], s.bending_MPa, math.sqrt(3.0) * s.hub_shear_MPa,
        (f"CLOSED FORM (no study resolves the diaphragm): radial bending 6 M_r/t^2 at the {where} edge of an annular "
         f"plate a = {a:.4g}, b = {b:.4g}, t = {t:.4g} mm under the wall's cos 2phi coning (edge rotation w0/L = "
         f"{s.edge_rotation_rad:.4g} rad, L = {lever:.4g} mm; Clebsch's n = 2 solution, Timoshenko & Woinowsky-Krieger "
         f"sec. 34; analytic/diaphragm.py): hub {s.hub_bending_MPa:.4g}, wall {s.wall_bending_MPa:.4g} MPa, fully reversed"),
        f"the torque's shear at the hub tau = T/(2 pi a^2 t) = {s.hub_shear_MPa:.4g} MPa, steady, as sqrt(3) tau",
        1.0, "1: a plate without the hub's and the wall's corner fillets (their concentration is not modelled)",
        flexspline_steel(params), params.ewg_drive.permissible_safety, f"wave generator insertion w0 + {RATED}",
        extra={"closed_form": s.to_dict()})
    if not advise:
        return factor
    length = params.flexspline_cup.length_mm
    return _with_advice(factor, params, "flexspline_cup.length_mm", diaphragm_factor, None, (0.5 * length, 4.0 * length))


def bearing_ratings(params) -> dict:
    """Hertz p0 of the most loaded ball on each race, ISO 76's static check and ISO 281's L10 in hours."""
    from strainwave.analytic.study_loads import wg_bearing_load

    wg, mat, g = params.wave_generator, params.material, params.gear
    loads = wg_bearing_load(params)
    q = max(loads["ball_loads_N"])
    r_race, _ = inner_ring_radii(params)
    r_outer_race = r_race + wg.ball_diameter_mm
    inner = wg_contact.hertz_point_contact(q, wg.ball_diameter_mm, wg.groove_radius_ratio, r_race,
                                           mat.youngs_modulus_MPa, mat.poisson_ratio, inner=True)
    outer = wg_contact.hertz_point_contact(q, wg.ball_diameter_mm, wg.groove_radius_ratio, r_outer_race,
                                           mat.youngs_modulus_MPa, mat.poisson_ratio, inner=False)
    d_pw = 2.0 * r_race + wg.ball_diameter_mm
    c_r = wg_contact.dynamic_load_rating_N(wg.ball_count, wg.ball_diameter_mm, d_pw)
    rel_speed = wg.input_speed_rpm * (1.0 + 1.0 / g.gear_ratio)   # outer ring turns with the flexspline, backwards
    p0 = max(inner.p0_MPa, outer.p0_MPa)
    return {"radial_force_N": loads["force_N"], "max_ball_load_N": q, "hertz_inner": inner.to_dict(),
            "hertz_outer": outer.to_dict(), "p0_max_MPa": p0,
            "static_contact_n": params.bearing_material.static_contact_limit_MPa / p0,
            "static_contact_source": "ISO 76:2006: C0 at p0 = 4200 MPa (radial ball bearings)",
            "C_r_N": c_r, "pitch_diameter_mm": d_pw, "relative_speed_rpm": rel_speed,
            "L10_h": wg_contact.l10_hours(c_r, loads["force_N"], rel_speed),
            "L10_note": ("ISO 281:2007 basic rating life, P = F_r at the rated torque, input speed "
                         f"{wg.input_speed_rpm:g} rpm; leaves out the flexible rings' elliptical load sharing and a_ISO")}


def closed_form_factors(params) -> list[FatigueFactor]:
    return [ring_factor(params), cup_tooth_root_factor(params), wg_inner_ring_factor(params),
            wg_outer_ring_factor(params), diaphragm_factor(params)]


def _with_advice(factor: FatigueFactor, params, key: str, build, fea, span: tuple[float, float],
                 admissible: bool = False) -> FatigueFactor:
    """``factor`` with the value of ``key`` that brings it to [n] when it falls short, and with ``admissible``
    the same value as the end of the range that keeps it at [n] whether it passes or not (a sizing parameter
    the user may have changed: the range is named either way). With FEA inputs the closed form's dependence
    on the key is used, scaled by the FEA's ratio to it at the current value."""
    fails = factor.n < factor.required or factor.static_n < 1.0
    if not (fails or admissible):
        return factor
    current = _get(params, key)
    closed = build(params, None, False) if fea is not None else factor
    ratio = factor.n / closed.n if math.isfinite(closed.n) and closed.n > 0 else 1.0

    def n_at(x: float) -> float:
        f = build(params.with_value(key, x), None, False)
        return min(f.n * ratio, f.static_n * f.required)   # the static check must hold too
    advice = solve_for(key, n_at, factor.required, current, *span,
                       note="closed-form dependence" + ("" if fea is None else ", scaled to the FEA's factor"))
    kept = None if not admissible else replace(
        advice, note=f"keeps it at [n] = {factor.required:g} and static n >= 1; now {current:g}; {advice.note}")
    return replace(factor, advice=advice if fails else None, admissible=kept)


def _get(params, key: str) -> float:
    section, _, name = key.partition(".")
    return float(getattr(getattr(params, section), name))
