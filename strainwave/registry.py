"""The one registry of FEA studies: each study is declared here once, and every stage reads it.

A ``Study`` names its CLI name, its variant ("module:Class": the module's ``run`` solves it, the class holds
its facts, ``fea/study_facts.StudyFacts``: element estimate, default size, CAD, rated load, report words), the
part it meshes, the component whose crack it can seed (the dotted parameter key of that crack, or none), its
quantities (name, unit, meaning, the role diagnose reads it in), the ``analytic`` function that gives it its
load when the load follows from a seed formula (``load_inputs``: fea/ receives numbers, never a closed form),
the parameter overrides under which its closed forms are evaluated (the FEA's load conditions) and the VTU
fields it writes. The closed form beside each quantity is a validate check's (``check_list.CHECKS``).
Readers: the CLI (``STUDY_NAMES``), ``fea/studies.run_study``, validate's plan and checks, diagnose's FEA
baseline and the sweep. Adding a study is its module plus one entry here.

Pure declarations: importing this module does no work and imports nothing heavy (``load_for``, ``facts``
and ``checked`` import what they name when called).
"""
from __future__ import annotations

import importlib
from dataclasses import dataclass

from strainwave.errors import InputError

__all__ = ["QuantitySpec", "Study", "STUDIES", "STUDY_NAMES", "CRACK_KEYS", "FLEX_UNIT", "study",
           "study_of_component", "crack_key_of"]

FLEX_UNIT = "rad/(N*mm)"
# Every 3D study writes the same nodal fields (fea/fields.py).
SOLID_FIELDS = ("displacement_mm", "von_mises_MPa", "stress_MPa")


@dataclass(frozen=True)
class QuantitySpec:
    """One number a study reports. The closed form it stands beside is a validate check's
    (``compare/validate/check_list.py``: ``Study.checked``); ``role`` says what diagnose reads it as."""

    name: str                      # units in the name
    unit: str
    meaning: str
    role: str | None = None        # "flexibility" (uncracked linear compliance), "crack_delta", or None

    def __post_init__(self):
        if not self.name or not self.unit:
            raise ValueError(f"quantity {self.name!r}: name and unit are required")


@dataclass(frozen=True)
class Study:
    name: str                                  # kebab-case CLI name
    variant: str                               # "module:Class": the module's run(params, ...) solves it, the
                                               # class (fea.study_facts.StudyFacts) holds its facts
    part: str                                  # geometry PartName value it meshes
    component: str | None                      # validate's component name ("shaft", ...); None: no crack
    crack_key: str | None                      # dotted params key of the crack it seeds; None: refuses a crack
    quantities: tuple[QuantitySpec, ...]
    load_inputs: str | None = None             # "module:function" of analytic/: params -> run's load keywords
    analytic_overrides: tuple[tuple[str, float], ...] = ()   # params under which its closed forms are evaluated
    vtu_fields: tuple[str, ...] = SOLID_FIELDS
    specimen: str | None = None                # diagnose recording specimen this study models

    def __post_init__(self):
        if (self.component is None) != (self.crack_key is None):
            raise ValueError(f"study {self.name}: component and crack_key go together")
        names = [q.name for q in self.quantities]
        if len(set(names)) != len(names):
            raise ValueError(f"study {self.name}: duplicate quantity names")

    @property
    def module(self) -> str:
        return self.variant.partition(":")[0]

    def facts(self):
        """The study's variant class (``fea.study_facts.StudyFacts``): imported here, when first asked."""
        module, _, name = self.variant.partition(":")
        return getattr(importlib.import_module(module), name)

    def quantity(self, name: str) -> QuantitySpec:
        for q in self.quantities:
            if q.name == name:
                return q
        raise KeyError(f"study {self.name} has no quantity {name!r}")

    def load_for(self, params) -> dict[str, float]:
        """The keyword arguments of the study's ``run`` that set its load ({} when the load is a parameter):
        computed by the ``analytic`` function the entry names, so fea/ receives numbers, not closed forms."""
        if self.load_inputs is None:
            return {}
        module, _, name = self.load_inputs.partition(":")
        return dict(getattr(importlib.import_module(module), name)(params))

    @property
    def checked(self) -> dict[str, str]:
        """{FEA quantity name: validate check id} for the quantities a check's closed form stands beside."""
        from strainwave.compare.validate.check_list import beside
        return {name: spec.id for name, spec in beside(self.name).items()}

    @property
    def flexibility(self) -> QuantitySpec | None:
        """The study's uncracked linear compliance (what diagnose's FEA baseline reads), if it has one."""
        return next((q for q in self.quantities if q.role == "flexibility"), None)

    @property
    def crack_delta(self) -> QuantitySpec | None:
        """The quantity that is the crack's added compliance (cracked - uncracked), if the study has a crack."""
        return next((q for q in self.quantities if q.role == "crack_delta"), None)


def _flex(what: str) -> tuple[QuantitySpec, ...]:
    return (
        QuantitySpec("flexibility_rad_per_Nmm", FLEX_UNIT, f"torsional flexibility of the uncracked {what}",
                     "flexibility"),
        QuantitySpec("cracked_flexibility_rad_per_Nmm", FLEX_UNIT, f"torsional flexibility of the cracked {what}"),
        QuantitySpec("delta_flexibility_rad_per_Nmm", FLEX_UNIT, f"added flexibility of the {what}'s crack",
                     "crack_delta"),
    )


STUDIES: dict[str, Study] = {s.name: s for s in (
    Study("shaft-torsion", "strainwave.fea.shaft_torsion:ShaftTorsion", "output-shaft", "shaft", "output_shaft.crack_depth_mm",
          _flex("output shaft"), specimen="output_shaft"),
    # The cup FEA load is static and uniform, so seed 000's load factors K_u, K_d (audit 17) are 1 for it.
    Study("cup-torsion", "strainwave.fea.cup_torsion:CupTorsion", "flexspline-cup", "cup", "flexspline_cup.root_crack_depth_mm",
          _flex("flexspline cup"), specimen="flexspline_cup",
          analytic_overrides=(("cracks.stress_nonuniformity", 1.0), ("cracks.dynamic_load_factor", 1.0))),
    Study("bearing-ring", "strainwave.fea.bearing_ring:BearingRing", "wg-bearing-ring", "bearing",
          "wave_generator.bearing_crack_depth_mm", (
              QuantitySpec("radial_compliance_mm_per_N", "mm/N", "radial compliance of the uncracked inner ring",
                           "flexibility"),
              QuantitySpec("cracked_radial_compliance_mm_per_N", "mm/N", "radial compliance of the cracked ring"),
              QuantitySpec("delta_radial_compliance_mm_per_N", "mm/N", "added radial compliance of the race crack",
                           "crack_delta"),
          ), load_inputs="strainwave.analytic.study_loads:bearing_ring_load"),
    # The ring closed forms are given at the thin-ring force for W0; they scale linearly to the FEA's force.
    Study("ring-compression", "strainwave.fea.ring_compression:RingCompression", "ewg-flexspline-ring", None, None, (
        QuantitySpec("delta_cd_mm", "mm", "diameter shortening along the load line CD", "flexibility"),
        QuantitySpec("delta_ab_mm", "mm", "diameter growth across the load line AB"),
        QuantitySpec("sigma_D_outer_MPa", "MPa", "hoop stress at the outer fibre under the load (D)"),
        QuantitySpec("sigma_B_outer_MPa", "MPa", "hoop stress at the outer fibre at the free point (B)"),
        QuantitySpec("tooth_influence", "1", "K_delta: toothed over smooth rim outer-fibre stress range"),
        QuantitySpec("stress_concentration", "1", "K_sigma: toothed root over smooth rim stress range"),
    ), load_inputs="strainwave.analytic.study_loads:ring_compression_load", specimen="ewg_ring"),
    # The inner ring on the elliptical cam: 2D, its own sweep of race-crack depths in one case.
    Study("wg-bearing", "strainwave.fea.wg_bearing:WgBearing", "wg-bearing-ring", None, None, (
        QuantitySpec("race_stress_major_MPa", "MPa", "race hoop stress at the major axis, cam alone"),
        QuantitySpec("race_stress_minor_MPa", "MPa", "race hoop stress at the minor axis, cam alone"),
        QuantitySpec("bore_stress_major_MPa", "MPa", "bore hoop stress at the major axis, cam alone"),
        QuantitySpec("net_race_stress_major_MPa", "MPa", "race hoop stress at the major axis, cam + ball loads"),
        QuantitySpec("ball_load_ratio", "1", "Z Q_max / F_r with Hertz balls on the FEA ring"),
        QuantitySpec("radial_stiffness_N_per_mm", "N/mm", "K_G: F_r over the outer race's approach (balls + ring)"),
        QuantitySpec("radial_compliance_mm_per_N", "mm/N", "ring compliance under the ball loads, uncracked"),
    ), load_inputs="strainwave.analytic.study_loads:wg_bearing_load", vtu_fields=SOLID_FIELDS + ("hoop_stress_MPa",)),
    # The cup on its wave generator: prescribed shape and rigid cam, linear and nonlinear; the
    # hoop bending at the axes is checked against the ring forced into w0 cos 2 phi (analytic/ring_prescribed.py).
    Study("cup-wave-generator", "strainwave.fea.cup_wave_generator:CupWaveGenerator", "flexspline-cup", None, None, (
        QuantitySpec("prescribed_linear_bending_major_MPa", "MPa",
                     "hoop bending stress (outer - inner)/2 at the major axis, band mid-width, prescribed shape"),
        QuantitySpec("prescribed_linear_bending_minor_MPa", "MPa",
                     "hoop bending stress (outer - inner)/2 at the minor axis, band mid-width, prescribed shape"),
        QuantitySpec("contact_nonlinear_peak_von_mises_MPa", "MPa", "peak von Mises of the wall on the rigid cam"),
        QuantitySpec("contact_nonlinear_torsional_stiffness_Nmm_per_rad", "N*mm/rad",
                     "tangent torsional stiffness of the cup on the cam"),
        QuantitySpec("cycle_amplitude_MPa", "MPa", "outer-fibre hoop stress amplitude per revolution at rated T"),
        QuantitySpec("cycle_mean_MPa", "MPa", "outer-fibre hoop mean stress per revolution at rated T"),
    ), vtu_fields=("displacement_mm", "von_mises_MPa", "stress_cylindrical_MPa", "hoop_stress_MPa")),
    # The teeth in mesh (issue 48): plane FE flank compliance of the cup's toothed rim and the CS's teeth, the
    # kinematic engagement and the frictional contact solve along 0 -> +T -> -T -> +T (fea/tooth_mesh.py).
    Study("tooth-mesh", "strainwave.fea.tooth_mesh:ToothMesh", "flexspline-cup", None, None, tuple(
        QuantitySpec(name, unit, meaning) for name, unit, meaning in (
            ("pair_compliance_major_mm_per_N", "mm/N", "one FS + CS tooth pair at the major axis, along the flank normal"),
            ("fs_tooth_compliance_major_mm_per_N", "mm/N", "the FS tooth on its rim at the major axis"),
            ("cs_tooth_compliance_major_mm_per_N", "mm/N", "the CS tooth on its rim at the major axis"),
            ("fs_coupling_next_ratio", "1", "the next FS tooth's displacement over the loaded one's (rim coupling)"),
            ("K1_Nmm_per_rad", "N*mm/rad", "mesh K1 (catalogue rules, compare/diagnose/catalogue_values.py)"),
            ("K2_Nmm_per_rad", "N*mm/rad", "mesh K2"), ("K3_Nmm_per_rad", "N*mm/rad", "mesh K3"),
            ("T1_Nmm", "N*mm", "mesh T1"), ("T2_Nmm", "N*mm", "mesh T2"),
            ("secant_stiffness_rated_Nmm_per_rad", "N*mm/rad", "rated torque over the mesh's twist there"),
            ("lost_motion_arcmin", "arcmin", "lost motion at +/-4 % rated torque"),
            ("friction_loss_per_cycle_Nmm", "N*mm", "work flank friction dissipates per +/-rated cycle (loop area)"),
            ("transmission_error_pp_rad", "rad", "peak-to-peak twist at rated torque over one tooth-passing period"),
            ("teeth_in_contact_rated", "1", "flank pairs carrying load at rated torque"),
            ("peak_tooth_share", "1", "largest flank load over the sum at rated torque"),
            ("peak_tooth_load_N", "N", "largest flank normal load at rated torque"),
            ("pair_stiffness_solid_N_per_mm_um", "N/(mm*um)",
             "the cup's tooth and its mirror image on solid bodies (ISO 6336-1's c' problem), per face width"),
            ("pair_stiffness_internal_N_per_mm_um", "N/(mm*um)",
             "the cup's tooth (solid body) and the CS's tooth (its rim), per face width"),
            ("crack_tooth_compliance_ratio", "1", "cracked over uncracked FS tooth compliance (root crack, solid body)"),
            ("crack_te_peak_rad", "rad", "largest twist change at rated torque as the cracked tooth passes the mesh"),
            ("ratcheting_torque_Nmm", "N*mm", "the torque at which the loaded teeth's radial push, against one WG "
             "lobe's K_G, uses up their radial overlap (fea/tooth_mesh.ratcheting_torque_Nmm)"),
            ("ratcheting_lift_rated_mm", "mm", "the overlap the loaded pairs lose at rated (load-weighted)"),
            ("ratcheting_overlap_mm", "mm", "the loaded pairs' radial overlap (load-weighted, kinematic)"),
            ("root_stress_peak_tooth_MPa", "MPa", "peak max-principal stress on the most loaded FS tooth's root "
             "fillets at rated (filleted sector, fea/tooth_root_fe.py)"),
            ("root_stress_per_N_MPa", "MPa/N", "that peak per newton of its flank load"),
            ("root_contact_radius_mm", "mm", "the most loaded tooth's FS contact radius (the load's radius)"))),
          load_inputs="strainwave.analytic.mesh_engagement:study_loads", vtu_fields=("displacement_mm", "von_mises_MPa")),
    # The tooth-root crack as a semi-elliptical surface crack in a block of the band wall, its own sweep of depths;
    # its quantities are named per state and depth (fea.surface_crack.delta_name).
    Study("cup-surface-crack", "strainwave.fea.surface_crack:SurfaceCrack", "flexspline-cup", None, None, (),
          load_inputs="strainwave.analytic.surface_crack:study_loads"),
)}

STUDY_NAMES = tuple(STUDIES)
# Every crack a parameter file can seed, one per crack-bearing component.
CRACK_KEYS = tuple(s.crack_key for s in STUDIES.values() if s.crack_key)


def study(name: str) -> Study:
    """The registry entry of ``name``; InputError (exit 2) naming the known studies otherwise."""
    try:
        return STUDIES[name]
    except KeyError:
        raise InputError("study", name, f"must be one of {', '.join(STUDIES)}") from None


def study_of_component(component: str) -> Study:
    for s in STUDIES.values():
        if s.component == component:
            return s
    raise KeyError(component)


def crack_key_of(component: str) -> str:
    return study_of_component(component).crack_key
