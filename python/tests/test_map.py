# SPDX-License-Identifier: Apache-2.0
"""vdbmap.Map on analytic scenes: a plane and a box seen by a simulated spinning LiDAR, the
mesh checked against the closed-form surfaces; the TSDF query; no copy of float32 scans."""
from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

import vdbmap
from conftest import box_distance, hits_box, hits_plane_z, pose, ray_fan

VOXEL = 0.1


def plane_map(**kwargs) -> vdbmap.Map:
    m = vdbmap.Map(voxel_size_m=VOXEL, **kwargs)
    dirs = ray_fan()
    for k in range(5):
        T = pose(x=1.0 * k, z=1.8)
        m.integrate(hits_plane_z(T, dirs, 0.0, max_range=20.0), T)
    return m


def test_plane_mesh_lies_on_the_plane():
    m = plane_map()
    vertices, triangles = m.extract_triangle_mesh()
    assert vertices.dtype == np.float64 and vertices.shape[1] == 3
    assert triangles.dtype == np.int32 and triangles.shape[1] == 3
    assert len(triangles) > 5000
    assert triangles.min() >= 0 and triangles.max() < len(vertices)
    near = np.hypot(vertices[:, 0] - 2.0, vertices[:, 1]) < 12.0
    # The plane z = 0 in closed form: marching cubes of its sdf puts vertices on it.
    assert np.abs(vertices[near, 2]).max() < 0.25 * VOXEL
    assert m.stats["scans"] == 5
    assert m.stats["points_integrated"] == m.stats["points_in"]


def test_query_gives_the_signed_distance_in_front_of_the_plane():
    m = plane_map()
    # Beyond 4 m of the sensors: the steepest ray (-24 deg from 1.8 m) meets the plane at 4.0 m.
    xy = np.array([[2.0, 6.0], [3.0, -7.0], [9.0, 4.0]])
    for height in (0.1, 0.2, -0.1):
        # voxel centres: (i, j, k) * voxel, so z = height is a centre
        sdf, weight = m.query(np.column_stack([xy, np.full(3, height)]))
        assert np.all(weight > 0)
        np.testing.assert_allclose(sdf, height, atol=0.2 * VOXEL)
    sdf, weight = m.query(np.array([[500.0, 500.0, 500.0]]))
    assert np.isnan(sdf[0]) and weight[0] == 0.0


def test_box_mesh_lies_on_the_box():
    lo, hi = (4.0, -2.0, 0.0), (8.0, 2.0, 3.0)
    m = vdbmap.Map(voxel_size_m=VOXEL)
    dirs = ray_fan(n_azimuth=1440)
    for T in (pose(0.0, 0.0, 1.8), pose(6.0, -6.0, 1.8), pose(12.0, 0.0, 1.8), pose(6.0, 6.0, 1.8)):
        m.integrate(hits_box(T, dirs, lo, hi, z_ground=0.0, max_range=15.0), T)
    vertices, _ = m.extract_triangle_mesh()
    d = box_distance(vertices, lo, hi)
    near = (d < 0.5) & (vertices[:, 2] > 0.05)  # the box, not the ground
    # How far inside its face a vertex is from the nearest edge of the box.
    lo_, hi_ = np.asarray(lo), np.asarray(hi)
    q = np.sort(np.abs(vertices - (lo_ + hi_) / 2) - (hi_ - lo_) / 2, axis=1)
    from_edge = -q[:, 1]
    assert near.sum() > 2000
    # Within a face (half a block from its edges) the mesh is the plane to a tenth of a voxel;
    # at the edges marching cubes of the sampled sdf rounds the box by up to a voxel.
    inner = near & (from_edge > 0.4)
    assert inner.sum() > 1000
    assert d[inner].max() < 0.1 * VOXEL
    assert d[near].max() < 1.05 * VOXEL
    # Each of the four walls has vertices (the roof, 3 m up, is above every sensor).
    v = vertices[inner]
    for axis, value in ((0, 4.0), (0, 8.0), (1, -2.0), (1, 2.0)):
        assert np.sum(np.abs(v[:, axis] - value) < 0.01) > 20, (axis, value)


def test_float64_and_strided_scans_give_the_same_map_as_float32():
    dirs = ray_fan()
    T = pose(z=1.8)
    pts32 = hits_plane_z(T, dirs, 0.0, max_range=20.0)
    a, b, c = vdbmap.Map(), vdbmap.Map(), vdbmap.Map()
    a.integrate(pts32, T)
    b.integrate(pts32.astype(np.float64), T)
    padded = np.zeros((len(pts32), 4), dtype=np.float32)
    padded[:, :3] = pts32
    c.integrate(padded[:, :3], T)  # strided view
    va, ta = a.extract_triangle_mesh()
    for other in (b, c):
        vo, to = other.extract_triangle_mesh()
        np.testing.assert_array_equal(va, vo)
        np.testing.assert_array_equal(ta, to)


def test_a_contiguous_float32_scan_is_not_copied():
    """A 120 k-point float32 scan is read in place: numpy allocates nothing for it (a copy to
    float32 would be 1.44 MB, which tracemalloc sees for the float64 scan)."""
    dirs = ray_fan(n_azimuth=1875)  # 64 x 1875 = 120 k rays
    T = pose(z=1.8)
    pts32 = hits_plane_z(T, dirs, 0.0, max_range=1e9)
    assert len(pts32) > 50_000
    pts64 = pts32.astype(np.float64)
    m = vdbmap.Map()
    m.integrate(pts32, T)  # warm-up
    tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        base = tracemalloc.get_traced_memory()[0]
        m.integrate(pts32, T)
        in_place = tracemalloc.get_traced_memory()[1] - base
        tracemalloc.reset_peak()
        base = tracemalloc.get_traced_memory()[0]
        m.integrate(pts64, T)
        converted = tracemalloc.get_traced_memory()[1] - base
    finally:
        tracemalloc.stop()
    assert in_place < 10_000
    assert converted >= pts32.nbytes


def test_options_are_the_stage_options_with_its_defaults():
    m = vdbmap.Map()
    assert m.voxel_size_m == pytest.approx(0.1)
    assert m.options["truncation_mode"] == "adaptive"
    assert m.options["voxel_size_m"] == pytest.approx(0.1)
    m = vdbmap.Map(voxel_size_m=0.05, truncation_mode="fixed", truncation_max_m=0.3)
    assert m.voxel_size_m == pytest.approx(0.05)
    assert m.options["truncation_mode"] == "fixed"
    assert m.options["truncation_max_m"] == pytest.approx(0.3)


def test_save_vdb_writes_the_grids(tmp_path):
    m = plane_map()
    path = tmp_path / "map.vdb"
    m.save_vdb(str(path))
    data = path.read_bytes()
    assert data[:8] == b"\x20\x42\x44\x56\x00\x00\x00\x00"  # OpenVDB magic 0x56444220
    for grid in (b"surface", b"weight", b"truncation"):
        assert grid in data
    # The map stays usable after saving.
    m.integrate(hits_plane_z(pose(z=1.8), ray_fan(), 0.0, 20.0), pose(z=1.8))
    assert m.stats["scans"] == 6
