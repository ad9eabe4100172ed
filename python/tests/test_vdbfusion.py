# SPDX-License-Identifier: Apache-2.0
"""The VDBFusion-style script of docs/python.md on the real KITTI scans of tests/data: only
the import and the constructor line differ from a VDBFusion script."""
from __future__ import annotations

import numpy as np

from vdbmap.vdbfusion import VDBVolume  # was: from vdbfusion import VDBVolume


def test_vdbfusion_style_script_maps_the_real_scans(kitti_scans):
    vdb_volume = VDBVolume(voxel_size=0.1, sdf_trunc=0.3, space_carving=False)
    for scan in kitti_scans[:1]:
        vdb_volume.integrate(scan, np.eye(4))
    vertices, triangles = vdb_volume.extract_triangle_mesh()
    assert len(triangles) > 20_000
    assert vdb_volume.map.options["truncation_max_m"] == 0.3
    # The KITTI Velodyne is mounted 1.73 m above the road: the commonest height of the mesh
    # within 4-12 m of the sensor is the road.
    r = np.hypot(vertices[:, 0], vertices[:, 1])
    z = vertices[(r > 4.0) & (r < 12.0), 2]
    hist, edges = np.histogram(z, bins=np.arange(-3.0, 3.0, 0.05))
    road = edges[np.argmax(hist)] + 0.025
    assert -1.9 < road < -1.55


def test_vdbfusion_origin_form_equals_the_pose_form(kitti_scans):
    """VDBFusion's integrate(points_W, origin) form: the same map as (points_L, T_W_L) with
    T_W_L a pure translation."""
    scan = kitti_scans[0]
    origin = np.array([2.0, -1.0, 0.5])
    T = np.eye(4)
    T[:3, 3] = origin
    a = VDBVolume(voxel_size=0.1, sdf_trunc=0.3)
    a.integrate(scan, T)
    b = VDBVolume(voxel_size=0.1, sdf_trunc=0.3)
    b.integrate(scan.astype(np.float64) + origin, origin)
    va, ta = a.extract_triangle_mesh()
    vb, tb = b.extract_triangle_mesh()
    assert len(ta) == len(tb)
    np.testing.assert_allclose(va, vb, atol=1e-4)
