# SPDX-License-Identifier: Apache-2.0
"""The Python integrator against `vdbmap run` on the same real scans (face for face),
vdbmap.run() with its report and log lines, the readers on a run's outputs, and Open3D on our
arrays and our PLY."""
from __future__ import annotations

import logging
import subprocess

import numpy as np
import pytest

import vdbmap
from conftest import TEST_DATA, hits_plane_z, pose, ray_fan

CONFIG = """\
dataset: {{format: generic, path: {seq}, scans_dir: scans, poses_file: poses.txt,
          pose_format: kitti, min_range_m: 0.001, max_range_m: 1000}}
stages:
  - stage: integrate.atsdf
  - stage: mesh.marching_cubes
"""

# Poses T_W_L of the three scans: exact in binary, so the file and numpy hold the same numbers.
POSES = [pose(0.0, 0.0, 0.0), pose(1.25, 0.125, 0.0, yaw=0.0), pose(2.5, 0.25, 0.0, yaw=0.0)]


@pytest.fixture
def generic_sequence(tmp_path, kitti_scans):
    """Three real KITTI scans in the generic layout (docs/DATA.md), with known poses."""
    seq = tmp_path / "seq"
    (seq / "scans").mkdir(parents=True)
    for i in range(3):
        raw = np.fromfile(TEST_DATA / "kitti_scans_real" / f"{i:06d}.bin", dtype=np.float32)
        raw.tofile(seq / "scans" / f"{i:06d}.bin")
    with open(seq / "poses.txt", "w") as f:
        for T in POSES:
            f.write(" ".join(repr(float(v)) for v in T[:3].reshape(-1)) + "\n")
    cfg = tmp_path / "map.yaml"
    cfg.write_text(CONFIG.format(seq=seq))
    return cfg, kitti_scans[:3]


def python_mesh(scans):
    m = vdbmap.Map()
    for scan, T in zip(scans, POSES):
        m.integrate(scan, T)
    return m.extract_triangle_mesh()


def test_python_map_equals_vdbmap_run_face_for_face(tmp_path, bin_dir, generic_sequence):
    cfg, scans = generic_sequence
    out = tmp_path / "cli"
    subprocess.run([str(bin_dir / "vdbmap"), "run", str(cfg), "-o", str(out), "--quiet"], check=True)
    cli = vdbmap.read_mesh(out / "mesh.ply")
    vertices, triangles = python_mesh(scans)
    assert len(triangles) > 10_000
    np.testing.assert_array_equal(cli["faces"], triangles)
    np.testing.assert_array_equal(cli["vertices"], vertices.astype(np.float32))


def test_run_returns_the_report_and_logs_to_python(tmp_path, generic_sequence, caplog):
    cfg, scans = generic_sequence
    with caplog.at_level(logging.INFO, logger="vdbmap"):
        report = vdbmap.run(cfg, tmp_path / "py", threads=1)
    stage = report["stages"]["integrate.atsdf"]
    assert stage["scans"] == 3
    assert stage["points_integrated"] == sum(len(s) for s in scans)
    assert any("integrate.atsdf: 3 scans" in r.getMessage() for r in caplog.records)
    mesh = vdbmap.read_mesh(tmp_path / "py" / "mesh.ply")
    assert report["stages"]["mesh.marching_cubes"]["faces"] == len(mesh["faces"])
    assert mesh["normals"].shape == mesh["vertices"].shape
    # Overrides are --set paths with values of any JSON type.
    report = vdbmap.run(cfg, tmp_path / "py2", overrides={"integrate.atsdf.voxel_size_m": 0.2,
                                                          "dataset.num_frames": 2})
    assert report["stages"]["integrate.atsdf"]["scans"] == 2
    assert report["config"]["stages"][0]["options"]["voxel_size_m"] == pytest.approx(0.2)


def test_tiled_run_index_and_tile_meshes(tmp_path, generic_sequence):
    cfg, _ = generic_sequence
    report = vdbmap.run(cfg, tmp_path / "tiled", overrides={"tiling.tile_size_m": 40, "tiling.halo_m": 2})
    index = vdbmap.read_tile_index(tmp_path / "tiled")
    assert index["counts"]["tiles"] == len(index["tiles"]) > 1
    faces = 0
    for tile in index["tiles"]:
        assert tile["bounds_W"].shape == (2, 3)
        meshes = [p for p in tile["paths"] if p.endswith("mesh.ply")]
        assert len(meshes) == 1
        faces += len(vdbmap.read_mesh(meshes[0])["faces"])
    assert faces == index["counts"]["faces"]
    assert report["stages"]["integrate.atsdf"]["scans"] == 3


def test_readers_return_labels_confidences_and_uvs(tmp_path):
    # A PLY and an OBJ written by hand with known values (the formats of docs/DATA.md).
    ply = tmp_path / "semantic.ply"
    header = ("ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
              "property float y\nproperty float z\nelement face 2\n"
              "property list uchar int vertex_indices\nproperty uchar label\n"
              "property float confidence\nend_header\n").encode()
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
    body = v.tobytes()
    for tri, label, conf in (((0, 1, 2), 7, 0.25), ((0, 2, 3), 200, 1.0)):
        body += np.uint8(3).tobytes() + np.array(tri, "<i4").tobytes()
        body += np.uint8(label).tobytes() + np.float32(conf).tobytes()
    ply.write_bytes(header + body)
    mesh = vdbmap.read_mesh(ply)
    np.testing.assert_array_equal(mesh["vertices"], v)
    np.testing.assert_array_equal(mesh["faces"], [[0, 1, 2], [0, 2, 3]])
    np.testing.assert_array_equal(mesh["face_labels"], [7, 200])
    np.testing.assert_allclose(mesh["face_confidence"], [0.25, 1.0])

    (tmp_path / "mesh.mtl").write_text("newmtl page0\nKd 1 1 1\nmap_Kd page0.png\n")
    (tmp_path / "mesh.obj").write_text(
        "mtllib mesh.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nusemtl page0\nf 1/1 2/2 3/3\n")
    obj = vdbmap.read_mesh(tmp_path / "mesh.obj")
    np.testing.assert_array_equal(obj["faces"], [[0, 1, 2]])
    np.testing.assert_array_equal(obj["face_uvs"], [[0, 1, 2]])
    np.testing.assert_allclose(obj["uvs"], [[0, 0], [1, 0], [1, 1]])
    assert obj["materials"][0]["texture"] == str(tmp_path / "page0.png")


def test_open3d_builds_a_mesh_from_the_arrays_and_reads_our_ply(tmp_path, generic_sequence):
    import open3d as o3d  # python3-open3d: a test dependency (scripts/install-deps.sh)
    m = vdbmap.Map()
    T = pose(z=1.8)
    m.integrate(hits_plane_z(T, ray_fan(), 0.0, max_range=10.0), T)
    vertices, triangles = m.extract_triangle_mesh()
    mesh = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(vertices),
                                     o3d.utility.Vector3iVector(triangles))
    # The observed disc of the plane z = 0: its area is below pi * 10^2 and most of it.
    area = mesh.get_surface_area()
    assert 0.6 * np.pi * 100 < area < np.pi * 100 * 1.02
    cfg, _ = generic_sequence
    vdbmap.run(cfg, tmp_path / "run")
    ours = vdbmap.read_mesh(tmp_path / "run" / "mesh.ply")
    theirs = o3d.io.read_triangle_mesh(str(tmp_path / "run" / "mesh.ply"))
    assert len(theirs.triangles) == len(ours["faces"])
    np.testing.assert_array_equal(np.asarray(theirs.triangles), ours["faces"])
    np.testing.assert_allclose(np.asarray(theirs.vertices), ours["vertices"], atol=1e-6)
