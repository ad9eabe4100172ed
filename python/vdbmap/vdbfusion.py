# SPDX-License-Identifier: Apache-2.0
"""VDBFusion's names on vdbmap's integrator: a VDBFusion script switches by changing its
import and its constructor line (docs/python.md):

    from vdbmap.vdbfusion import VDBVolume       # was: from vdbfusion import VDBVolume
    vdb_volume = VDBVolume(voxel_size=0.1, sdf_trunc=0.3, space_carving=False)
    for scan, pose in dataset:
        vdb_volume.integrate(scan, pose)
    vertices, triangles = vdb_volume.extract_triangle_mesh()

sdf_trunc sets vdbmap's truncation bound eps_max (truncation_max_m); the truncation stays
adaptive (paper Eq. 4) unless truncation_mode="fixed" is given. Any other integrate.atsdf option
can be passed as a keyword argument.
"""
from __future__ import annotations

from typing import Any

import numpy as np

from ._vdbmap import Map


class VDBVolume:
    """VDBFusion's VDBVolume(voxel_size, sdf_trunc, space_carving) on vdbmap.Map."""

    def __init__(self, voxel_size: float, sdf_trunc: float, space_carving: bool = False,
                 **atsdf_options: Any) -> None:
        self.voxel_size = float(voxel_size)
        self.sdf_trunc = float(sdf_trunc)
        self.space_carving = bool(space_carving)
        self._map = Map(voxel_size_m=self.voxel_size, truncation_max_m=self.sdf_trunc,
                        space_carving=self.space_carving, **atsdf_options)

    @property
    def map(self) -> Map:
        """The vdbmap.Map underneath (query, save_vdb, stats)."""
        return self._map

    def integrate(self, points: np.ndarray, extrinsic: np.ndarray) -> None:
        """VDBFusion's integrate(points, extrinsic): points in the sensor frame, extrinsic the
        4x4 sensor pose in the world (VDBFusion's T_W_L). The 3-vector origin form of VDBFusion
        (points already in the world) is accepted too."""
        extrinsic = np.asarray(extrinsic)
        if extrinsic.shape == (3,):
            pts = np.asarray(points, dtype=np.float64) - extrinsic
            pose = np.eye(4)
            pose[:3, 3] = extrinsic
            self._map.integrate(pts, pose)
            return
        self._map.integrate(points, extrinsic)

    def extract_triangle_mesh(self, fill_holes: bool = True, min_weight: float = 0.0):
        """(vertices, triangles) as VDBFusion returns them. fill_holes is accepted for
        compatibility: vdbmap meshes only cubes whose 8 corners were observed (weight > 0)."""
        del fill_holes
        return self._map.extract_triangle_mesh(min_weight=float(min_weight))

    def extract_vdb_grids(self, out_file: str) -> None:
        """VDBFusion's name for writing the grids: vdbmap's map.vdb."""
        self._map.save_vdb(out_file)
