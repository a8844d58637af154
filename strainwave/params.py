"""The parameter schema: TOML parsed once, at the boundary, into frozen dataclasses.

Units live in the field names (as in the TOML). Everything past ``load_params`` is
plain floats, ints, bools, tuples and enums. Impossible values raise
``InputError(key, value, allowed)``; values that are possible but outside a seed's
recommended range emit a ``RangeWarning`` naming the range and its source.
"""
from __future__ import annotations

import dataclasses
import enum
import math
import tomllib
import typing
import warnings
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from strainwave.errors import InputError, MaterialWarning, RangeWarning
from strainwave.params_bounds import check_bounds


class CupShape(enum.Enum):
    CYLINDRICAL = "cylindrical"
    BELL = "bell"


class WaveGeneratorKind(enum.Enum):
    CAM = "cam"
    ROLLERS = "rollers"


class EwgGenerator(enum.Enum):
    ROLLERS = "rollers"
    CAM_RING = "cam_ring"


class ToothProfile(enum.Enum):
    """The flank form of the flexspline/circular-spline pair (one vocabulary; a new profile is a new member)."""
    INVOLUTE = "involute"


def _positive(key: str, value: float) -> None:
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
        raise InputError(key, value, "must be a finite number > 0")


def _in_open(key: str, value: float, lo: float, hi: float, why: str = "") -> None:
    if not (math.isfinite(value) and lo < value < hi):
        raise InputError(key, value, f"must lie in ({lo:g}, {hi:g}){why}")


def _crack_in_wall(key: str, depth_mm: float, wall_name: str, wall_mm: float) -> None:
    """A crack must be deeper than zero and shallower than the wall it cuts."""
    _positive(key, depth_mm)
    if depth_mm >= wall_mm:
        raise InputError(key, depth_mm, f"must be < {wall_name} = {wall_mm:g} mm")


# Keys that were removed, with what replaces them: refused with a message naming the new keys.
REMOVED_KEYS = {
    "cracks.depth_mm": "was one depth for every part; set the crack of each component instead: "
                       "output_shaft.crack_depth_mm, flexspline_cup.root_crack_depth_mm, "
                       "wave_generator.bearing_crack_depth_mm",
}


def refuse_removed(dotted_key: str, value: object) -> None:
    if dotted_key in REMOVED_KEYS:
        raise InputError(dotted_key, value, REMOVED_KEYS[dotted_key])


def _recommend(key: str, value: float, lo: float, hi: float, source: str) -> None:
    if not lo <= value <= hi:
        warnings.warn(f"{key} = {value:g} is outside the recommended {lo:g}..{hi:g} ({source}); running anyway",
                      RangeWarning, stacklevel=3)


@dataclass(frozen=True)
class Material:
    youngs_modulus_MPa: float
    shear_modulus_MPa: float
    poisson_ratio: float
    fatigue_limit_MPa: float
    ultimate_strength_MPa: float    # Goodman's mean-stress line ends at it
    yield_strength_MPa: float       # R_p0.2: the static check beside every fatigue factor
    name: str                       # the flexspline's (and shaft's) steel, as the materials table shows it
    source: str                     # where its strengths come from

    def __post_init__(self):
        _positive("material.youngs_modulus_MPa", self.youngs_modulus_MPa)
        _positive("material.yield_strength_MPa", self.yield_strength_MPa)
        if self.yield_strength_MPa > self.ultimate_strength_MPa:
            raise InputError("material.yield_strength_MPa", self.yield_strength_MPa,
                             f"must be <= ultimate_strength_MPa = {self.ultimate_strength_MPa:g}")
        _positive("material.shear_modulus_MPa", self.shear_modulus_MPa)
        _positive("material.fatigue_limit_MPa", self.fatigue_limit_MPa)
        _positive("material.ultimate_strength_MPa", self.ultimate_strength_MPa)
        if self.ultimate_strength_MPa <= self.fatigue_limit_MPa:
            raise InputError("material.ultimate_strength_MPa", self.ultimate_strength_MPa,
                             f"must exceed fatigue_limit_MPa = {self.fatigue_limit_MPa:g} (a steel's sigma_-1 ~ 0.5 R_m)")
        _in_open("material.poisson_ratio", self.poisson_ratio, 0.0, 0.5)
        check_bounds("material", self)   # before the warning: a refused material needs no comparison
        implied = self.implied_shear_modulus_MPa
        if abs(implied / self.shear_modulus_MPa - 1.0) > 0.005:
            warnings.warn(
                f"material: E/(2(1+nu)) = {implied:.0f} MPa differs from shear_modulus_MPa = "
                f"{self.shear_modulus_MPa:g} by {100 * (implied / self.shear_modulus_MPa - 1):+.2f} %; "
                "seed-000 closed forms use mu = shear_modulus_MPa, FEA uses E and nu",
                MaterialWarning, stacklevel=3)

    @property
    def implied_shear_modulus_MPa(self) -> float:
        return self.youngs_modulus_MPa / (2.0 * (1.0 + self.poisson_ratio))


@dataclass(frozen=True)
class Gear:
    wave_number: int
    gear_ratio: float
    radial_deformation_mm: float
    force_coefficient: float
    output_torque_Nmm: float
    rated_output_torque_Nmm: float   # the load the report's stress pictures and safety factors are drawn at

    def __post_init__(self):
        if self.wave_number < 1:
            raise InputError("gear.wave_number", self.wave_number, "must be an integer >= 1")
        for name in ("gear_ratio", "radial_deformation_mm", "force_coefficient", "output_torque_Nmm",
                     "rated_output_torque_Nmm"):
            _positive(f"gear.{name}", getattr(self, name))
        check_bounds("gear", self)   # after the checks above, whose messages are more specific


@dataclass(frozen=True)
class FlexsplineCup:
    pitch_diameter_mm: float
    wall_thickness_mm: float
    length_mm: float
    shape: CupShape
    cup: bool
    teeth: int
    module_mm: float
    root_crack_depth_mm: float      # depth of the tooth-root crack (seed 000's a, for the flexspline)

    def __post_init__(self):
        for name in ("pitch_diameter_mm", "wall_thickness_mm", "length_mm", "module_mm"):
            _positive(f"flexspline_cup.{name}", getattr(self, name))
        if self.wall_thickness_mm >= self.pitch_diameter_mm / 2:
            raise InputError("flexspline_cup.wall_thickness_mm", self.wall_thickness_mm,
                             f"must be < pitch_diameter_mm/2 = {self.pitch_diameter_mm / 2:g}")
        _crack_in_wall("flexspline_cup.root_crack_depth_mm", self.root_crack_depth_mm,
                       "flexspline_cup.wall_thickness_mm", self.wall_thickness_mm)
        if self.teeth < 4:
            raise InputError("flexspline_cup.teeth", self.teeth, "must be an integer >= 4")
        from strainwave.geometry.flexspline_cup import BAND_RATIO, BOSS_HEIGHT_WALLS
        band, z_end = BAND_RATIO * self.pitch_diameter_mm, (BOSS_HEIGHT_WALLS - 0.5) * self.wall_thickness_mm
        if self.length_mm <= band + z_end:   # the tooth band would run into the diaphragm (fea/wg_band's tube)
            from strainwave.fea.wg_band import shortest_cup_message
            raise InputError("flexspline_cup.length_mm", self.length_mm, shortest_cup_message(z_end, band))
        if self.module_mm * 2.35 >= self.pitch_diameter_mm / 2 - self.wall_thickness_mm:
            raise InputError("flexspline_cup.module_mm", self.module_mm,
                             "teeth taller than the cup radius: need 2.35 module < d1/2 - delta")
        _recommend("flexspline_cup.wall_thickness_mm / pitch_diameter_mm",
                   self.wall_thickness_mm / self.pitch_diameter_mm, 0.005, 0.03, "usual thin flexspline range")
        check_bounds("flexspline_cup", self)   # after the checks above, whose messages are more specific


@dataclass(frozen=True)
class OutputShaft:
    outer_diameter_mm: float
    inner_diameter_mm: float
    length_mm: float
    crack_depth_mm: float           # depth of the circumferential shaft crack (seed 000's a, for the shaft)

    def __post_init__(self):
        _positive("output_shaft.outer_diameter_mm", self.outer_diameter_mm)
        _positive("output_shaft.length_mm", self.length_mm)
        if not (isinstance(self.inner_diameter_mm, float) and 0.0 <= self.inner_diameter_mm < self.outer_diameter_mm):
            raise InputError("output_shaft.inner_diameter_mm", self.inner_diameter_mm,
                             f"must be >= 0 and < outer_diameter_mm = {self.outer_diameter_mm:g}")
        _crack_in_wall("output_shaft.crack_depth_mm", self.crack_depth_mm,
                       "the output_shaft wall (outer_diameter_mm - inner_diameter_mm)/2", self.wall_mm)
        check_bounds("output_shaft", self)   # after the checks above, whose messages are more specific

    @property
    def wall_mm(self) -> float:
        return 0.5 * (self.outer_diameter_mm - self.inner_diameter_mm)


@dataclass(frozen=True)
class WaveGenerator:
    kind: WaveGeneratorKind
    bearing_inner_ring_thickness_mm: float
    contact_semi_axes_mm: tuple[float, float]
    beta: float
    uncracked_radial_stiffness_N_per_mm: float
    bearing_crack_depth_mm: float   # depth of the inner ring's race crack (seed 000's a, for the bearing)
    ball_count: int                 # Z: balls of the wave generator bearing (chosen; the seed gives none)
    ball_diameter_mm: float         # D_w of the flexible bearing's balls
    outer_ring_thickness_mm: float  # radial thickness of the flexible outer ring (under the flexspline)
    groove_radius_ratio: float      # f = groove radius / D_w (Harris: 0.515..0.53 for deep-groove raceways)
    bearing_width_mm: float         # B: the rings' axial width, seed 000's t_i (the race crack's front runs across it)
    input_speed_rpm: float          # the wave generator's speed for the bearing's L10 life in hours

    def __post_init__(self):
        _positive("wave_generator.bearing_width_mm", self.bearing_width_mm)
        _positive("wave_generator.input_speed_rpm", self.input_speed_rpm)
        _positive("wave_generator.bearing_inner_ring_thickness_mm", self.bearing_inner_ring_thickness_mm)
        _positive("wave_generator.ball_diameter_mm", self.ball_diameter_mm)
        _positive("wave_generator.outer_ring_thickness_mm", self.outer_ring_thickness_mm)
        _in_open("wave_generator.groove_radius_ratio", self.groove_radius_ratio, 0.5, 1.0,
                 ": a groove wider than the ball (> 0.5) that still conforms (< 1)")
        if len(self.contact_semi_axes_mm) != 2:
            raise InputError("wave_generator.contact_semi_axes_mm", list(self.contact_semi_axes_mm),
                             "must be two numbers [a', b'] > 0")
        for v in self.contact_semi_axes_mm:
            _positive("wave_generator.contact_semi_axes_mm", v)
        _positive("wave_generator.beta", self.beta)
        _positive("wave_generator.uncracked_radial_stiffness_N_per_mm", self.uncracked_radial_stiffness_N_per_mm)
        _recommend("wave_generator.beta", self.beta, 0.4278, 0.5, "seed 000, from a'/b'")
        _crack_in_wall("wave_generator.bearing_crack_depth_mm", self.bearing_crack_depth_mm,
                       "wave_generator.bearing_inner_ring_thickness_mm", self.bearing_inner_ring_thickness_mm)
        if not isinstance(self.ball_count, int) or self.ball_count < 3:
            raise InputError("wave_generator.ball_count", self.ball_count, "must be an integer >= 3")
        check_bounds("wave_generator", self)   # after the checks above, whose messages are more specific


@dataclass(frozen=True)
class CircularSpline:
    """The rigid internal gear: Z_c = flexspline_cup.teeth + gear.wave_number teeth (a dual wave: Z_f + 2)."""

    profile: ToothProfile            # flank form of both toothed parts
    profile_source: str              # where the profile comes from (a standard, a patent, a drawing)
    pressure_angle_deg: float        # alpha of the basic rack (both parts)
    addendum_coefficient: float      # h_a / m of the circular spline's teeth
    backlash_mm: float               # circumferential clearance per flank pair at the pitch circle, unloaded
    outer_diameter_mm: float         # the spline's rim
    face_width_mm: float             # b: the teeth's axial length (the flexspline's toothed rim is as wide)
    flank_friction_coefficient: float   # mu of the flanks (boundary lubrication)
    flank_friction_source: str       # where mu comes from

    def __post_init__(self):
        _in_open("circular_spline.pressure_angle_deg", self.pressure_angle_deg, 0.0, 45.0)
        _in_open("circular_spline.addendum_coefficient", self.addendum_coefficient, 0.0, 2.0)
        if not (math.isfinite(self.backlash_mm) and self.backlash_mm >= 0.0):
            raise InputError("circular_spline.backlash_mm", self.backlash_mm, "must be a finite number >= 0")
        for name in ("outer_diameter_mm", "face_width_mm"):
            _positive(f"circular_spline.{name}", getattr(self, name))
        if not (math.isfinite(self.flank_friction_coefficient) and 0.0 <= self.flank_friction_coefficient < 1.0):
            raise InputError("circular_spline.flank_friction_coefficient", self.flank_friction_coefficient,
                             "must lie in [0, 1): a lubricated steel flank")
        check_bounds("circular_spline", self)


@dataclass(frozen=True)
class BearingMaterial:
    """The wave generator bearing's steel (rings and balls): its own strengths, not the flexspline's."""

    name: str
    fatigue_limit_MPa: float        # sigma_-1, fully reversed bending
    yield_strength_MPa: float       # R_p0.2
    ultimate_strength_MPa: float    # R_m
    static_contact_limit_MPa: float  # Hertz p0 at which ISO 76 sets the static load rating C0 (balls: 4200)
    source: str

    def __post_init__(self):
        for key in ("fatigue_limit_MPa", "yield_strength_MPa", "ultimate_strength_MPa", "static_contact_limit_MPa"):
            _positive(f"bearing_material.{key}", getattr(self, key))
        if not self.fatigue_limit_MPa < self.ultimate_strength_MPa:
            raise InputError("bearing_material.fatigue_limit_MPa", self.fatigue_limit_MPa,
                             f"must be < ultimate_strength_MPa = {self.ultimate_strength_MPa:g}")
        if self.yield_strength_MPa > self.ultimate_strength_MPa:
            raise InputError("bearing_material.yield_strength_MPa", self.yield_strength_MPa,
                             f"must be <= ultimate_strength_MPa = {self.ultimate_strength_MPa:g}")
        check_bounds("bearing_material", self)


@dataclass(frozen=True)
class Cracks:
    """Seed 000's crack factors; each component's crack depth is a key of its own section."""

    surface_crack_shape_factor: float
    stress_nonuniformity: float
    dynamic_load_factor: float
    flexspline_crack_angle_deg: float

    def __post_init__(self):
        if not (math.isfinite(self.surface_crack_shape_factor) and self.surface_crack_shape_factor >= 1.0):
            raise InputError("cracks.surface_crack_shape_factor", self.surface_crack_shape_factor,
                             "Q = 1 + 1.464 (a/c)^1.65 must be >= 1")
        _positive("cracks.stress_nonuniformity", self.stress_nonuniformity)
        _positive("cracks.dynamic_load_factor", self.dynamic_load_factor)
        _in_open("cracks.flexspline_crack_angle_deg", self.flexspline_crack_angle_deg, 0.0, 90.0)
        check_bounds("cracks", self)   # after the checks above, whose messages are more specific


@dataclass(frozen=True)
class EwgDrive:
    tooth_difference: int
    flexspline_teeth: int
    module_mm: float
    rim_thickness_ratio: float
    face_width_mm: float
    dedendum_coefficient: float
    pressure_angle_deg: float
    root_fillet_coefficient: float
    tooth_influence: float
    stress_concentration: float
    mean_stress_influence: float
    permissible_safety: float
    generator: EwgGenerator

    def __post_init__(self):
        if self.tooth_difference < 1:
            raise InputError("ewg_drive.tooth_difference", self.tooth_difference, "must be an integer >= 1")
        if self.flexspline_teeth < 2 * self.tooth_difference:
            raise InputError("ewg_drive.flexspline_teeth", self.flexspline_teeth,
                             f"must be >= 2 x tooth_difference = {2 * self.tooth_difference}")
        for name in ("module_mm", "rim_thickness_ratio", "face_width_mm", "dedendum_coefficient",
                     "root_fillet_coefficient", "tooth_influence", "stress_concentration", "permissible_safety"):
            _positive(f"ewg_drive.{name}", getattr(self, name))
        _in_open("ewg_drive.pressure_angle_deg", self.pressure_angle_deg, 0.0, 45.0)
        if not 0.0 <= self.mean_stress_influence < 1.0:
            raise InputError("ewg_drive.mean_stress_influence", self.mean_stress_influence, "must lie in [0, 1)")
        if self.root_fillet_coefficient > 0.5:
            raise InputError("ewg_drive.root_fillet_coefficient", self.root_fillet_coefficient,
                             "must be <= 0.5 (fillet radius / module; ISO 53 basic racks use 0.25..0.39)")
        if self.rim_thickness_ratio >= 0.5:
            raise InputError("ewg_drive.rim_thickness_ratio", self.rim_thickness_ratio,
                             "must be < 0.5 (the rim would close the bore)")
        _recommend("ewg_drive.rim_thickness_ratio", self.rim_thickness_ratio, 0.01, 0.015, "seed 003, eq 6 text")
        _recommend("ewg_drive.tooth_influence", self.tooth_influence, 1.05, 1.10, "seed 003, eq 10")
        _recommend("ewg_drive.stress_concentration", self.stress_concentration, 1.8, 2.0, "seed 003, eq 13")
        _recommend("ewg_drive.mean_stress_influence", self.mean_stress_influence, 0.10, 0.15, "seed 003, eq 13")
        _recommend("ewg_drive.permissible_safety", self.permissible_safety, 1.3, 1.5, "seed 003, eq 12")
        check_bounds("ewg_drive", self)   # after the checks above, whose messages are more specific

    @property
    def reference_diameter_mm(self) -> float:
        return self.module_mm * self.flexspline_teeth

    @property
    def rim_thickness_mm(self) -> float:
        return self.rim_thickness_ratio * self.reference_diameter_mm


@dataclass(frozen=True)
class CrackGeometry:
    slot_width_mm: float
    shaft_axial_position_ratio: float
    shaft_arc_deg: float
    flexspline_tooth_index: int
    flexspline_axial_position_ratio: float

    def __post_init__(self):
        _positive("crack_geometry.slot_width_mm", self.slot_width_mm)
        _in_open("crack_geometry.shaft_axial_position_ratio", self.shaft_axial_position_ratio, 0.0, 1.0)
        if not 0.0 < self.shaft_arc_deg <= 360.0:
            raise InputError("crack_geometry.shaft_arc_deg", self.shaft_arc_deg, "must lie in (0, 360]")
        if self.flexspline_tooth_index < 0:
            raise InputError("crack_geometry.flexspline_tooth_index", self.flexspline_tooth_index, "must be >= 0")
        _in_open("crack_geometry.flexspline_axial_position_ratio", self.flexspline_axial_position_ratio, 0.0, 1.0)
        check_bounds("crack_geometry", self)   # after the checks above, whose messages are more specific


@dataclass(frozen=True)
class Params:
    material: Material
    gear: Gear
    flexspline_cup: FlexsplineCup
    output_shaft: OutputShaft
    wave_generator: WaveGenerator
    circular_spline: CircularSpline
    cracks: Cracks
    ewg_drive: EwgDrive
    crack_geometry: CrackGeometry
    bearing_material: BearingMaterial

    def __post_init__(self):
        # Checks that need two sections (each crack against its own wall is checked in its section).
        key, a = min(self.crack_depths_mm().items(), key=lambda kv: kv[1])
        if self.crack_geometry.slot_width_mm > a / 5:
            raise InputError("crack_geometry.slot_width_mm", self.crack_geometry.slot_width_mm,
                             f"must be <= {key}/5 = {a / 5:g} mm (a slot, not a notch)")
        if self.crack_geometry.flexspline_tooth_index >= self.flexspline_cup.teeth:
            raise InputError("crack_geometry.flexspline_tooth_index", self.crack_geometry.flexspline_tooth_index,
                             f"must be < flexspline_cup.teeth = {self.flexspline_cup.teeth}")
        self._check_teeth()

    def _check_teeth(self) -> None:
        """Both toothed parts drawable (geometry/involute.py check_teeth): every command refuses the same."""
        from strainwave.geometry.involute import check_teeth, cup_tooth_spec, ewg_tooth_spec   # numpy only: no CAD kernel
        check_teeth(cup_tooth_spec(self), "flexspline_cup.module_mm", self.flexspline_cup.module_mm,
                    "flexspline cup")
        check_teeth(ewg_tooth_spec(self), "ewg_drive.flexspline_teeth", self.ewg_drive.flexspline_teeth,
                    "EWG flexspline ring")

    def crack_depths_mm(self) -> dict[str, float]:
        """{dotted key: depth} of every component's crack."""
        return {"output_shaft.crack_depth_mm": self.output_shaft.crack_depth_mm,
                "flexspline_cup.root_crack_depth_mm": self.flexspline_cup.root_crack_depth_mm,
                "wave_generator.bearing_crack_depth_mm": self.wave_generator.bearing_crack_depth_mm}

    def crack_depth_mm(self, dotted_key: str) -> float:
        """The depth under one of the crack keys of ``crack_depths_mm``."""
        return self.crack_depths_mm()[dotted_key]

    # Modifiers return copies (the dataclasses are frozen).
    def with_value(self, dotted_key: str, value: object) -> "Params":
        """A copy with one dotted key (``section.key``) replaced, validated like a file value."""
        return params_from_dict(_set_dotted(self.to_dict(), dotted_key, value))

    def with_values(self, values: dict[str, object]) -> "Params":
        """A copy with several dotted keys replaced at once, validated together: keys checked against each
        other (a tooth count and its module) may pass only as a pair."""
        data = self.to_dict()
        for dotted_key, value in values.items():
            data = _set_dotted(data, dotted_key, value)
        return params_from_dict(data)

    def to_dict(self) -> dict:
        """Plain TOML-like dict (enums as their strings, tuples as lists)."""
        out = {}
        for f in dataclasses.fields(self):
            section = getattr(self, f.name)
            out[f.name] = {k.name: _plain(getattr(section, k.name)) for k in dataclasses.fields(section)}
        return out


def schema_types() -> dict[str, type]:
    """Dotted key -> the type the schema declares (float, int, bool, str for enums, list for tuples):
    what a value must be, whatever literal the default file happens to use (``gear_ratio = 100``)."""
    out = {}
    for name, cls in typing.get_type_hints(Params).items():
        for key, hint in typing.get_type_hints(cls).items():
            if isinstance(hint, type) and issubclass(hint, enum.Enum):
                hint = str
            elif typing.get_origin(hint) is tuple:
                hint = list
            out[f"{name}.{key}"] = hint
    return out


def _plain(value):
    if isinstance(value, enum.Enum):
        return value.value
    if isinstance(value, tuple):
        return list(value)
    return value


def _set_dotted(data: dict, dotted_key: str, value: object) -> dict:
    refuse_removed(dotted_key, value)
    section, _, key = dotted_key.partition(".")
    if section not in data or not key:
        raise InputError(dotted_key, value, f"unknown key; sections are {', '.join(data)}")
    if key not in data[section]:
        raise InputError(dotted_key, value, f"unknown key; {section} has {', '.join(data[section])}")
    new = {s: dict(v) for s, v in data.items()}
    new[section][key] = value
    return new


_MAX_MAGNITUDE = 1e12


def _coerce(key: str, value: object, annotation: object):
    """Check one TOML value against the field's annotation and convert it."""
    if isinstance(annotation, type) and issubclass(annotation, enum.Enum):
        allowed = [m.value for m in annotation]
        if value not in allowed:
            raise InputError(key, value, f"must be one of {', '.join(map(repr, allowed))}")
        return annotation(value)
    if annotation is bool:
        if not isinstance(value, bool):
            raise InputError(key, value, "must be true or false")
        return value
    if annotation is int:
        if isinstance(value, float) and value.is_integer():
            value = int(value)
        if isinstance(value, bool) or not isinstance(value, int):
            raise InputError(key, value, "must be an integer")
        if abs(value) > _MAX_MAGNITUDE:   # as for floats: the closed forms overflow beyond it
            raise InputError(key, value, f"magnitude must be <= {_MAX_MAGNITUDE:g}")
        return value
    if annotation is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise InputError(key, value, "must be a number")
        if isinstance(value, int) and abs(value) > _MAX_MAGNITUDE:   # before float(): 1e400 overflows it
            raise InputError(key, value, f"magnitude must be <= {_MAX_MAGNITUDE:g}")
        value = float(value)
        if not math.isfinite(value):
            raise InputError(key, value, "must be a finite number")
        if abs(value) > _MAX_MAGNITUDE:
            # The closed forms raise lengths to the 6th power: beyond this magnitude float arithmetic
            # overflows before any physics is computed.
            raise InputError(key, value, f"magnitude must be <= {_MAX_MAGNITUDE:g}")
        return value
    if typing.get_origin(annotation) is tuple:
        if not isinstance(value, (list, tuple)):
            raise InputError(key, value, "must be a list of numbers")
        return tuple(_coerce(key, v, float) for v in value)
    if annotation is str:
        if not isinstance(value, str) or len(value) > 500 or not value.isprintable():
            raise InputError(key, value if isinstance(value, str) else type(value).__name__,
                             "must be one line of text (<= 500 characters)")
        return value
    raise TypeError(f"no coercion for {annotation!r}")  # a schema bug, not user input


def params_from_dict(data: dict) -> Params:
    """Build validated ``Params`` from a complete TOML-like dict."""
    if not isinstance(data, dict):
        raise InputError("<file>", type(data).__name__, "must be a TOML table")
    sections = {}
    for name, cls in typing.get_type_hints(Params).items():
        table = data.get(name)
        if not isinstance(table, dict):
            raise InputError(name, table, "must be a [section] table")
        hints = typing.get_type_hints(cls)
        kwargs = {}
        for f in dataclasses.fields(cls):
            if f.name not in table:
                raise InputError(f"{name}.{f.name}", None, "missing")
            kwargs[f.name] = _coerce(f"{name}.{f.name}", table[f.name], hints[f.name])
        sections[name] = cls(**kwargs)
    return Params(**sections)


def default_dict() -> dict:
    text = resources.files("strainwave").joinpath("data/defaults.toml").read_text(encoding="utf-8")
    return tomllib.loads(text)


def merge_overrides(base: dict, overrides: dict, source: str = "params") -> dict:
    """Deep-merge a partial user table into the defaults, refusing unknown sections and keys."""
    merged = {s: dict(v) for s, v in base.items()}
    if not isinstance(overrides, dict):
        raise InputError(source, overrides, "must be a TOML table of [sections]")
    for section, table in overrides.items():
        if section not in merged:
            raise InputError(f"[{section}]", "section", f"unknown section; allowed: {', '.join(merged)}")
        if not isinstance(table, dict):
            raise InputError(section, table, "must be a [section] table")
        for key, value in table.items():
            refuse_removed(f"{section}.{key}", value)
            if key not in merged[section]:
                raise InputError(f"{section}.{key}", value,
                                 f"unknown key; {section} has {', '.join(merged[section])}")
            merged[section][key] = value
    return merged


# The default file is 4 KiB; a parameter file 250x that is not a parameter file (e.g. /dev/zero, a log),
# and reading it whole would take the memory a mistaken path can point at.
MAX_PARAMS_BYTES = 1 << 20


def read_limited(path: Path, limit: int, what: str) -> bytes:
    """The bytes of ``path``, refused (InputError naming ``what``) if not a readable regular file or above
    ``limit`` bytes (strainwave.input_guard: FIFOs and devices are refused without being opened)."""
    from strainwave.input_guard import read_regular
    return read_regular(path, limit, what)


def parse_toml_text(text: str, where: str) -> dict:
    """tomllib, with every way it can fail on user text turned into one InputError naming ``where``."""
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(where, "malformed TOML", str(exc)) from None
    except RecursionError:
        raise InputError(where, "nested arrays or tables", "nested too deeply to be a parameter value") from None
    except ValueError as exc:   # an integer literal beyond Python's 4300-digit conversion limit
        raise InputError(where, "a number", f"not a usable TOML number ({exc})") from None


def read_toml(path: Path) -> dict:
    raw = read_limited(Path(path), MAX_PARAMS_BYTES, "--params")
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise InputError("--params", str(path), "must be a UTF-8 TOML text file") from None
    return parse_toml_text(text, f"{path}")


def _given(key: str, overrides: dict) -> bool:
    """True if ``key`` (dotted, or a [section]) is set by ``overrides``."""
    section, _, name = str(key).strip("[]").partition(".")
    table = overrides.get(section)
    return isinstance(table, dict) and (not name or name in table) or (not name and section in overrides)


def load_params(path: Path | str | None = None, overrides: dict | None = None, origin: str = "params") -> Params:
    """The embedded default, updated by an optional partial TOML file and an optional dict.

    Range warnings are held back until every key has passed: a refused file gets its one error line,
    not a warning about another key printed before it."""
    from strainwave.drive_guard import check_drive
    data = default_dict()
    with warnings.catch_warnings(record=True) as held:
        warnings.simplefilter("always")
        if path is not None:
            data = merge_overrides(data, read_toml(Path(path)), str(path))
        try:
            if overrides:
                data = merge_overrides(data, overrides, origin)
            params = params_from_dict(data)
            check_drive(params)   # the parts inside each other, before any command works on them
        except InputError as exc:   # the key as the user gave it: in the recording's header, not --params
            if overrides and origin != "params" and _given(exc.key, overrides):
                raise InputError(f"{origin} {exc.key}", exc.value, exc.allowed) from None
            raise
    for w in held:
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    return params
