"""What every catalogue effect provides: a model in normalised units, bounded parameters, a reading in SI units.

Normalisation (``Context``): load u = x/X with X = max|x|, response in units of Y = c0 X, so the
baseline is y = u and every parameter is O(1). An effect adds ``contribution(ctx, theta)`` to
y = b0 + b1 t + s u, where b0, b1 (zero offset, drift) and s (stiffness scale, prior 1 +/- uncertainty)
are the always-fitted nuisance parameters.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np


@dataclass(frozen=True)
class Param:
    """One free parameter in normalised units: bounds and a few starting values for multistart."""

    name: str
    lo: float
    hi: float
    starts: tuple[float, ...]


@dataclass(frozen=True)
class Context:
    """A recording in normalised form plus what the models need about its history and specimen."""

    u: np.ndarray            # load / X
    y: np.ndarray            # response / Y
    t: np.ndarray            # acquisition time (or sample index) scaled to [0, 1]
    X: float                 # load scale, N*mm or N
    Y: float                 # response scale c0 X, rad or mm
    c0: float                # baseline compliance
    load_unit: str
    response_unit: str
    direction: np.ndarray    # +1 while the load increases, -1 while it decreases
    segments: tuple[tuple[int, int, int], ...]   # (start, stop, direction) between load reversals
    geometry: dict = field(default_factory=dict)
    uncertainty: float = 0.02  # relative 1-sigma uncertainty of the baseline compliance
    angle: np.ndarray | None = None   # wave generator input angle, rad (optional column input_angle_rad)
    # per-context memo of history bases that are linear in their parameters (e.g. the Preisach relay states);
    # not an init field, so dataclasses.replace (a new load history) starts with an empty one
    cache: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    @property
    def two_sided(self) -> bool:
        return bool(self.u.min() < -0.2 and self.u.max() > 0.2)

    @property
    def reversals(self) -> int:
        return max(len(self.segments) - 1, 0)


@dataclass(frozen=True)
class RivalReading:
    """A model outside the catalogue heard against a named effect (its rival draws the same data)."""

    margin_bic: float        # BIC(rival) - BIC(named model): negative when the rival fits better
    decisive: bool           # the recording can tell the two apart (a rival better by > 10 then wins)
    unexplained_note: str    # why the answer is unexplained when the rival wins
    label: str               # the rival as a runner-up when the two tie


@dataclass(frozen=True)
class Effect:
    """A catalogue entry: stable id, model, parameters, and the sentence the report quotes."""

    id: str
    kinds: tuple[str, ...]
    params: tuple[Param, ...]
    contribution: Callable[[Context, np.ndarray], np.ndarray]
    report: Callable[[Context, np.ndarray, float], dict]   # (ctx, theta, s) -> {name: (value, unit)}
    explanation: str
    applicable: Callable[[Context], bool] = lambda ctx: True
    variant: str = ""          # a second, smaller model of the same effect (BIC picks between them)
    # forms of one law class differ in detail, not in what they can draw beside another effect (a friction loop
    # from one internal state vs from a density of elements, which can also bend the elastic line): a pair
    # tries the best form of each class, not the two best forms of one class. "" = a class of its own
    law_class: str = ""
    # for a form linear in its parameters: ctx -> its columns (contribution = basis @ theta), so the fit solves its
    # weights by bounded linear least squares instead of searching them (a relay density has 20)
    basis: Callable[[Context], np.ndarray] | None = None
    # where the fitted effect acts: (ranges of u in normalised units, branch/side text); None = everywhere
    where: Callable[[Context, np.ndarray], tuple[tuple[tuple[float, float], ...], str]] | None = None
    # physical plausibility of fitted values: (ctx, theta, s) -> list of warnings (empty when plausible)
    plausible: Callable[[Context, np.ndarray, float], list[str]] | None = None
    # False for a form free enough that, beside another effect, the two draw a rig artefact between them (a free
    # one-sided curve beside a free odd one spans every even curve: a sensor's even nonlinearity)
    pairs: bool = True
    # the part of the contribution that makes the effect what it is (a backlash's clearance band, not its flanks'
    # contact stiffening): (ctx, theta) -> twist; None: the whole contribution
    signature: Callable[[Context, np.ndarray], np.ndarray] | None = None
    # another reading of the stated stiffness by the form of variant ``rereads`` (the same span, a different
    # stiffness under the prior): fitted only where that form's stiffness is off its prior by more than
    # candidates.REREAD_PRIOR_SIGMAS (closer, the prior costs it under one BIC unit, which no decision turns on)
    rereads: str | None = None
    # False for an effect driven by something other than the load history (the wave generator's input angle, the
    # measured angle): it has no part in a loop drawn against the load, and the reference cycle carries no angle
    load_path: bool = True
    # a friction loop: its width at zero load is the hysteresis loss, its stiffness the loop's secant and elastic
    loop: bool = False
    # a band at zero load (a backlash): where a loop's width is read, so beside it the data cannot read that width
    zero_load_band: bool = False
    # a linear compliance in series with the specimen: the pair partner of a stiffness outside its prior
    series_compliance: bool = False
    # effect ids this one cannot be told apart from (both a pure linear compliance change): never paired
    degenerate_with: tuple[str, ...] = ()
    # (specimen, effect id) pairs that are the normal model of that specimen, not a second effect to earn its place
    normal_with: tuple[tuple[str, str], ...] = ()
    # (specimen, every effect id of the model) for a model of three effects that is that specimen's normal model:
    # a real drive's stiffening, lost motion and loop; each effect still earns its place by BIC
    normal_model: tuple[tuple[str, tuple[str, ...]], ...] = ()
    # False for a form that draws another member of the normal model as well (a backlash's Hertzian flanks: a
    # stiffening), so beside that member the two would draw one curve twice: left out of the normal model's fits
    in_normal_model: bool = True
    # a model outside the catalogue that draws what this effect draws, heard whenever it is named:
    # (ctx, kept effects, their thetas, BIC of the named model, sigma, uncertainty, noise, stride) -> RivalReading
    rival: Callable[..., RivalReading] | None = None

    def signature_of(self, ctx: Context, theta: np.ndarray) -> np.ndarray:
        return (self.signature or self.contribution)(ctx, theta)

    @property
    def label(self) -> str:
        return f"{self.id}[{self.variant}]" if self.variant else self.id

    @property
    def n_params(self) -> int:
        return len(self.params)

    def degenerate(self, other: "Effect") -> bool:
        """The two effects draw the same curve (declared on either)."""
        return other.id in self.degenerate_with or self.id in other.degenerate_with

    def normal_beside(self, other: "Effect", specimen: str) -> bool:
        """The pair is the specimen's normal model (declared on either)."""
        return (specimen, other.id) in self.normal_with or (specimen, self.id) in other.normal_with

    def normal_among(self, others: tuple["Effect", ...], specimen: str) -> bool:
        """The model of this effect and ``others`` is the specimen's normal model (declared on any of them)."""
        ids = frozenset((self.id,) + tuple(e.id for e in others))
        return any(sp == specimen and frozenset(model) == ids
                   for e in (self,) + tuple(others) for sp, model in e.normal_model)
