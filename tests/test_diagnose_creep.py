"""Creep under a held load behind a wandering sensor is a mismatch, not noise (issue 12: 'agrees' is the most
dangerous answer). The creep here follows Andrade's law, growing as the cube root of the time under load and
not recovered, a law the structure test's exponential lags do not share."""

import numpy as np
import pytest

from strainwave.compare.diagnose.baseline import analytic_baseline
from strainwave.compare.diagnose.context import build_context
from strainwave.compare.diagnose.pipeline import Verdict, diagnose
from strainwave.compare.diagnose.recording import RecordingKind, format_recording, parse_text

X = 1e6              # N*mm full scale
SIGMA = 2e-3         # white noise, normalised twist
HOLD = (0, 1, 1, -1, -1, 0)   # up, hold at +T, down, hold at -T, back: equal numbers of samples


def _load(n):
    return np.interp(np.linspace(0, len(HOLD) - 1, n), np.arange(len(HOLD)), HOLD)


def andrade_creep(u: np.ndarray, t: np.ndarray, amplitude: float) -> np.ndarray:
    """Creep while |u| is held at full scale: amplitude sign(u) ((t - t_start)/duration)^(1/3) within a hold,
    kept after it (not recovered)."""
    held = np.abs(u) == 1.0
    out = np.zeros_like(u)
    done = 0.0
    edges = np.diff(np.concatenate([[0], held.astype(int), [0]]))
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    for a, b in zip(starts, stops):
        span = t[b - 1] - t[a]
        out[a:b] = done + amplitude * np.sign(u[a]) * ((t[a:b] - t[a]) / span) ** (1.0 / 3.0)
        done += amplitude * np.sign(u[a])
        out[b:] = done
    return out


def _recording(params, creep_sigmas: float, seed: int, n: int = 400):
    """White noise plus a random walk as large (std about its mean: a wandering sensor, as in family 2), and
    Andrade creep of creep_sigmas white sigmas per hold."""
    rng = np.random.default_rng(seed)
    u = _load(n)
    t = np.linspace(0.0, 1.0, n)
    probe = parse_text(format_recording(RecordingKind.TORSION, "output_shaft", u * X, u))
    ctx = build_context(probe, analytic_baseline(probe, params))
    walk = np.cumsum(rng.standard_normal(n))
    noise = SIGMA * (rng.standard_normal(n) + (walk - walk.mean()) / np.std(walk))
    y = u + 0.01 + andrade_creep(u, t, creep_sigmas * SIGMA) + noise
    rec = parse_text(format_recording(RecordingKind.TORSION, "output_shaft", u * X, y * ctx.Y, time_s=t * 60.0))
    return diagnose(rec, params)[0]


def test_andrade_creep_grows_under_load_and_is_kept():
    u = _load(400)
    t = np.linspace(0.0, 1.0, 400)
    c = andrade_creep(u, t, 1.0)
    assert np.all(np.diff(c)[np.abs(u[1:]) < 1.0] == 0.0)       # no creep while the load moves
    assert c[np.argmax(u == 1.0) + 79] == pytest.approx(1.0)      # one amplitude by the end of the first hold
    assert c[-1] == pytest.approx(0.0)                            # the hold at -T creeps back by as much


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_same_sensor_without_creep_agrees(params, seed):
    """The holds switch the creep structure on (structure._load_held); a wandering sensor alone is no creep."""
    diag = _recording(params, 0.0, seed)
    assert diag.verdict is Verdict.AGREES, diag.explanation


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_creep_of_twenty_sigmas_is_never_agreement(params, seed):
    # never a silent agreement: unexplained, or the creep named beside the rest's verdict
    diag = _recording(params, 20.0, seed)
    named = any(e.startswith("creep under a hold") for e in diag.events)
    assert diag.verdict is not Verdict.AGREES or named, diag.explanation


def test_creep_under_two_holds_behind_a_wandering_sensor_is_named_not_agreement(params, monkeypatch):
    """benchmark-diagnose family 2, seed 0, creep_hold-005: 412 rows, two holds of 90 samples at +-T, the twist
    creeping 12-23 white sigmas in each. Its slow part made the residual look like a random walk, which became
    the noise model, and the recording read "agrees". With the lags fitted away among the generic structures
    the sensor's own noise is left (ARMA phi 0.95, theta 0.5): unexplained by the catalogue, so the creep under
    each hold is named and taken out (decision 067). Without the lags: "agrees" again, silently."""
    from pathlib import Path
    from strainwave.compare.diagnose import structure
    path = Path(__file__).parent / "data" / "family2_creep_hold.csv"
    rec = parse_text(path.read_text(), path.name)
    diag = diagnose(rec, params)[0]
    # the catalogue cannot draw it (unexplained), so the creep under each hold is named and taken out
    # (time_events.py): the rest agrees, the creep said beside it
    creep = [e for e in diag.events if e.startswith("creep under a hold")]
    assert diag.verdict is Verdict.AGREES and len(creep) == 2, diag.events
    monkeypatch.setattr(structure, "_load_held", lambda ctx: False)
    assert diagnose(rec, params)[0].verdict is Verdict.AGREES
