"""results.json: assembled from a run's parts, validated against results_schema.json, written atomically."""
from __future__ import annotations

import json
import math
import platform
import sys
from datetime import datetime, timezone
from importlib import metadata
from pathlib import Path

from strainwave.io_atomic import atomic_write_text
from strainwave.cache import code_version

SCHEMA_PATH = Path(__file__).with_name("results_schema.json")
LIBRARIES = ("numpy", "scipy", "scikit-fem", "gmsh", "pyamg", "pyvista", "vtk", "build123d", "matplotlib", "meshio",
             "rich")


def versions() -> dict[str, str | None]:
    def version(name: str) -> str | None:
        try:
            return metadata.version(name)
        except metadata.PackageNotFoundError:
            return None

    return {"strainwave": version("strainwave"), "code_version": code_version(),
            "python": sys.version.split()[0], "platform": platform.platform(),
            **{name: version(name) for name in LIBRARIES}}


def now_utc() -> str:
    return datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")


def plain(value):
    """JSON-safe copy: NaN/inf -> None, paths -> str, tuples -> lists."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if isinstance(value, Path):
        return value.as_posix()
    if value is None or isinstance(value, (bool, int, str)):
        return value
    if hasattr(value, "item"):  # numpy scalars
        return plain(value.item())
    return str(value)


def load_schema() -> dict:
    """The results schema; a check's component is one of the check list's (``check_list.CHECKS``) and a case's
    study one of the registry's."""
    from strainwave import registry
    from strainwave.compare.validate.check_list import current
    schema = json.loads(SCHEMA_PATH.read_text(encoding="utf-8"))
    schema["$defs"]["check"]["properties"]["component"]["enum"] = sorted({s.component for s in current()})
    schema["$defs"]["case"]["properties"]["study"]["enum"] = sorted(registry.STUDIES)
    return schema


def validate_results(document: dict) -> None:
    """Raise jsonschema.ValidationError if ``document`` does not follow the schema."""
    import jsonschema

    jsonschema.validate(document, load_schema(), cls=jsonschema.Draft202012Validator)


def write_results(path: Path, document: dict) -> Path:
    """Validate first, then write under a temporary name and rename: never a half or invalid file."""
    document = plain(document)
    validate_results(document)
    return atomic_write_text(path, json.dumps(document, indent=2, allow_nan=False) + "\n")
