"""The documented Python face of strainwave: ``import strainwave as sw`` and then ``sw.<name>``.

Each function is a thin layer over the one library function the command line calls too, so a script and
``strainwave <command>`` give the same numbers. ``params`` may be a ``Params`` (``sw.load_params()``), a
path to a partial TOML file, or None for the embedded default. Heavy libraries (gmsh, scikit-fem, pyvista,
Dask) load on the first call, never at ``import strainwave``.
"""
from __future__ import annotations

from pathlib import Path
from typing import Callable

__all__ = ["load_params", "build_part", "export_part", "run_study", "validate", "diagnose", "sweep"]


def _params(params):
    from strainwave.params import Params, load_params as _load
    return params if isinstance(params, Params) else _load(params)


def load_params(path: str | Path | None = None, overrides: dict | None = None):
    """The parameters: the embedded default, updated by an optional partial TOML file and an optional dict of
    sections (``{"gear": {"rated_output_torque_Nmm": 5e5}}``). Bad input raises ``strainwave.errors.InputError``.

    >>> sw.load_params().gear.rated_output_torque_Nmm
    """
    from strainwave.params import load_params as _load
    return _load(path, overrides=overrides)


def build_part(name: str, params=None, *, crack_depth_mm: float | None = None, teeth: bool = True):
    """Build one part (``output-shaft``, ``flexspline-cup``, ``wg-bearing-ring``, ``ewg-flexspline-ring``, ...)
    in mm with named faces; returns a ``strainwave.geometry.part.Part`` (its ``.shape`` is a build123d solid)."""
    from strainwave.geometry.parts import build_part as _build
    return _build(name, _params(params), crack_depth_mm=crack_depth_mm, teeth=teeth)


def export_part(name: str, out_path: str | Path, params=None, *, crack_depth_mm: float | None = None,
                teeth: bool = True, png: str | Path | None = None) -> list[Path]:
    """Build ``name`` (or ``assembly``) and write it as STEP (mm, named faces) to ``out_path``, with a face-name
    sidecar ``<file>.faces.json``; ``png`` adds an off-screen preview. Returns the written paths."""
    from strainwave.geometry.export import export_part as _export
    return _export(name, _params(params), Path(out_path), crack_depth_mm=crack_depth_mm, teeth=teeth,
                   png=None if png is None else Path(png))


def run_study(study: str, params=None, *, mesh_size_mm: float | None = None, order: int = 2,
              crack_depth_mm: float | None = None, vtu: str | Path | None = None, quick: bool = False,
              progress: Callable[[str], None] | None = None):
    """Mesh and solve one FEA study (``shaft-torsion``, ``cup-torsion``, ``bearing-ring``, ``ring-compression``)
    on three meshes; returns a ``StudyResult`` (``result["flexibility_rad_per_Nmm"].value``, its ``.convergence``
    with the GCI). ``vtu`` writes the finest mesh's fields (at the solved load; ``strainwave solve --vtu`` writes
    them at the rated load). Three meshes that come out identical are refused (InputError), never a 0 % GCI."""
    from strainwave.fea.studies import run_study as _run
    return _run(study, _params(params), mesh_size_mm=mesh_size_mm, order=order, crack_depth_mm=crack_depth_mm,
                vtu=None if vtu is None else Path(vtu), quick=quick, progress=progress)


def validate(out_dir: str | Path = "reports/validate", params=None, *, quick: bool = False,
             progress: Callable[[str], None] | None = None, step: bool | None = None):
    """Every study against both seeds' closed forms, into ``out_dir`` (report.html/.pdf, results.json, CSVs,
    STEP unless quick (``step`` overrides), VTU). Returns the outcome: ``.passed`` is the validation verdict,
    ``.design`` the design verdict."""
    from strainwave.compare.validate.pipeline import run_validate
    return run_validate(_params(params), Path(out_dir), quick=quick, progress=progress or (lambda msg: None),
                        step=step)


def diagnose(recording: str | Path, *, params: str | Path | None = None, baseline: str = "analytic",
             plot: str | Path | None = None):
    """Locate, name and model the mismatch between a recording (docs/recordings.md) and the model; returns a
    ``Diagnosis`` (``.summary()``, ``.to_dict()``). ``params``: a partial TOML file (the recording's own header
    overrides apply on top)."""
    from strainwave.compare.diagnose.pipeline import diagnose_file
    return diagnose_file(Path(recording), params_path=params, baseline=baseline,
                         plot_out=None if plot is None else Path(plot))


def sweep(study: str, vary: list[str], *, out_dir: str | Path = "reports/sweep", params: str | Path | None = None,
          samples: str | Path | None = None, quick: bool = False, workers: int | None = None,
          scheduler: str | None = None, tolerance: float = 0.05, progress: Callable[[str], None] | None = None):
    """Solve ``study`` at every point of a grid (``vary``: ``["KEY=START:STOP:N", "KEY=v1,v2"]``) or of a sample
    file, on Dask (a local cluster unless ``scheduler``); returns the sweep outcome with one row per point."""
    from strainwave.compare.sweep.pipeline import run_sweep
    return run_sweep(study, vary=list(vary), params_path=params, sample_file=samples, scheduler=scheduler,
                     workers=workers, out_dir=Path(out_dir), quick=quick, tolerance=tolerance, progress=progress)
