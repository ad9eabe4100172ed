# SPDX-License-Identifier: Apache-2.0
"""Every error path of the module: C++ errors arrive as vdbmap.Error subclasses with their
message, bad arrays as ValueError naming the argument and what it got."""
from __future__ import annotations

import numpy as np
import pytest

import vdbmap


def test_error_classes_derive_from_one_base():
    for cls in (vdbmap.ConfigError, vdbmap.PluginError, vdbmap.DataError, vdbmap.InvalidInputError):
        assert issubclass(cls, vdbmap.Error)
    assert issubclass(vdbmap.Error, RuntimeError)
    assert vdbmap.IoError is vdbmap.DataError


@pytest.mark.parametrize("points, shape, dtype", [
    (np.zeros((5, 2), np.float32), "(5, 2)", "float32"),
    (np.zeros((5,), np.float64), "(5,)", "float64"),
    (np.zeros((5, 3), np.int32), "(5, 3)", "int32"),
])
def test_bad_points_name_the_argument_and_what_they_got(points, shape, dtype):
    m = vdbmap.Map()
    with pytest.raises(ValueError) as e:
        m.integrate(points, np.eye(4))
    assert "points" in str(e.value) and shape in str(e.value) and dtype in str(e.value)
    with pytest.raises(ValueError, match="points"):
        m.query(points)


@pytest.mark.parametrize("T, why", [
    (np.eye(3), "shape (3, 3)"),
    (np.eye(4)[:3], "shape (3, 4)"),
    (np.diag([2.0, 2.0, 2.0, 1.0]), "not orthonormal"),
    (np.diag([1.0, 1.0, -1.0, 1.0]), "determinant"),
    (np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]], float), "last row"),
    (np.full((4, 4), np.nan), "non-finite"),
])
def test_bad_poses_name_the_argument(T, why):
    with pytest.raises(ValueError) as e:
        vdbmap.Map().integrate(np.zeros((3, 3), np.float32), T)
    assert "T_W_L" in str(e.value) and why in str(e.value)


def test_unknown_option_is_a_config_error_listing_the_keys():
    with pytest.raises(vdbmap.ConfigError) as e:
        vdbmap.Map(voxel_sise_m=0.1)
    assert "voxel_sise_m" in str(e.value) and "voxel_size_m" in str(e.value)


def test_bad_option_values_are_config_errors():
    with pytest.raises(vdbmap.ConfigError, match="voxel_size_m"):
        vdbmap.Map(voxel_size_m=-1.0)
    with pytest.raises(vdbmap.ConfigError, match="truncation_mode"):
        vdbmap.Map(truncation_mode="wide")
    with pytest.raises(vdbmap.ConfigError, match="max_weight"):
        vdbmap.Map(max_weight="heavy")
    with pytest.raises(ValueError, match="voxel_size_m"):
        vdbmap.Map(voxel_size_m=object())


def test_run_errors(tmp_path):
    with pytest.raises(vdbmap.ConfigError, match="nope.yaml"):
        vdbmap.run(tmp_path / "nope.yaml", tmp_path / "out")
    cfg = tmp_path / "c.yaml"
    cfg.write_text("dataset: {format: kitti, path: missing_seq}\nstages:\n  - stage: integrate.atsdf\n")
    with pytest.raises(vdbmap.DataError, match="missing_seq"):
        vdbmap.run(cfg, tmp_path / "out")
    cfg.write_text("stages:\n  - stage: integrate.atsdf\n    voxel_size_m: fast\n")
    with pytest.raises(vdbmap.ConfigError, match="voxel_size_m"):
        vdbmap.run(cfg, tmp_path / "out")
    with pytest.raises(ValueError, match="threads"):
        vdbmap.run(cfg, tmp_path / "out", threads=0)
    with pytest.raises(ValueError, match="overrides"):
        vdbmap.run(cfg, tmp_path / "out", overrides={"dataset.path": object()})


def test_reader_errors(tmp_path):
    with pytest.raises(vdbmap.DataError, match="missing.ply"):
        vdbmap.read_mesh(tmp_path / "missing.ply")
    bad = tmp_path / "bad.ply"
    bad.write_bytes(b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nend_header\n1\n")
    with pytest.raises(vdbmap.DataError, match="bad.ply"):
        vdbmap.read_mesh(bad)
    with pytest.raises(vdbmap.DataError, match="expected .ply or .obj"):
        vdbmap.read_mesh(tmp_path / "mesh.stl")
    with pytest.raises(vdbmap.DataError, match="tiles.json"):
        vdbmap.read_tile_index(tmp_path)
    (tmp_path / "tiles.json").write_text('{"format": "other"}')
    with pytest.raises(vdbmap.DataError, match="vdbmap-tiles"):
        vdbmap.read_tile_index(tmp_path)
