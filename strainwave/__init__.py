"""strainwave: design, mesh, solve and validate strain wave gears (harmonic drives) against their closed forms.

The Python face (``strainwave.api``), loaded lazily so that ``import strainwave`` and the command line start
fast::

    import strainwave as sw
    params = sw.load_params(overrides={"gear": {"rated_output_torque_Nmm": 5e5}})
    result = sw.run_study("shaft-torsion", params, quick=True)
    outcome = sw.validate("reports/validate", quick=True)    # .passed (validation), .design (design verdict)

``sw.__version__``, ``sw.load_params``, ``sw.build_part``, ``sw.export_part``, ``sw.run_study``, ``sw.validate``,
``sw.diagnose``, ``sw.sweep``: see each one's docstring, and examples/ for short scripts.
"""
from __future__ import annotations

__all__ = ["__version__", "load_params", "build_part", "export_part", "run_study", "validate", "diagnose", "sweep"]

_API = frozenset(__all__) - {"__version__"}


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version
    try:
        return version("strainwave")
    except PackageNotFoundError:   # a source tree that was never installed
        return "0+unknown"


def __getattr__(name: str):
    """PEP 562: the API functions and ``__version__`` load on first use, not at import."""
    if name == "__version__":
        value = _version()
    elif name in _API:
        from strainwave import api
        value = getattr(api, name)
    else:
        raise AttributeError(f"module 'strainwave' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
