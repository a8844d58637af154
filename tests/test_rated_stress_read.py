"""rated_stress.read_vtu: inside ``shared_reads`` (the images stage) one read per unchanged field; outside it every
call reads the file (write_at_rated rewrites fields in place, within the file system's time stamp resolution)."""
from __future__ import annotations

import numpy as np
import pyvista as pv

from strainwave.rated_stress import read_vtu, scaled_to_rated, shared_reads


def _write(path, stress: float) -> None:
    grid = pv.ImageData(dimensions=(3, 3, 3)).cast_to_unstructured_grid()
    grid.point_data["von_mises_MPa"] = np.full(grid.n_points, stress)
    grid.save(str(path))


def _stress(mesh) -> float:
    return float(np.unique(mesh.point_data["von_mises_MPa"])[0])


def test_one_read_per_unchanged_file_while_shared_and_every_rewrite_seen_outside(tmp_path):
    vtu = tmp_path / "field.vtu"
    _write(vtu, 10.0)
    with shared_reads():
        first = read_vtu(vtu)
        assert read_vtu(tmp_path / "." / "field.vtu") is first          # the same file, read once
        assert _stress(scaled_to_rated(first, 2.0)) == 20.0
        assert _stress(read_vtu(vtu)) == 10.0                             # the shared mesh is left as read
    assert read_vtu(vtu) is not first
    _write(vtu, 30.0)                      # same size, possibly the same time stamp: read again outside
    assert _stress(read_vtu(vtu)) == 30.0
