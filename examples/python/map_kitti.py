#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Maps a KITTI odometry sequence with vdbmap and renders the mesh to a PNG with Open3D.
Usage: map_kitti.py dataset/sequences/00 [--frames 100] [--png mesh.png] (docs/python.md).
Without a display: xvfb-run -a python3 map_kitti.py ... (Debian's Open3D has no EGL headless
renderer; its hidden-window Visualizer renders under Xvfb)."""
import argparse
from pathlib import Path

import numpy as np
import open3d as o3d
import vdbmap

args = argparse.ArgumentParser()
args.add_argument("sequence", type=Path)
args.add_argument("--frames", type=int, default=100)
args.add_argument("--png", default="mesh.png")
args = args.parse_args()

seq = args.sequence
poses_file = seq / "poses.txt" if (seq / "poses.txt").exists() else seq.parents[1] / "poses" / f"{seq.name}.txt"
T_W_C0 = [np.vstack([np.array(l.split(), float).reshape(3, 4), [0, 0, 0, 1]]) for l in open(poses_file)]
Tr = next(l.split()[1:] for l in open(seq / "calib.txt") if l.startswith("Tr:"))
T_C0_L = np.vstack([np.array(Tr, float).reshape(3, 4), [0, 0, 0, 1]])

m = vdbmap.Map(voxel_size_m=0.1)
for i, scan in enumerate(sorted((seq / "velodyne").glob("*.bin"))[: args.frames]):
    points_L = np.fromfile(scan, dtype=np.float32).reshape(-1, 4)[:, :3]
    m.integrate(points_L, T_W_C0[i] @ T_C0_L)
vertices, triangles = m.extract_triangle_mesh()
print(f"{m.stats['scans']} scans, {len(triangles)} faces")

mesh = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(vertices), o3d.utility.Vector3iVector(triangles))
mesh.compute_vertex_normals()
vis = o3d.visualization.Visualizer()
vis.create_window(width=1280, height=720, visible=False)
vis.add_geometry(mesh)
view = vis.get_view_control()
view.set_front([-0.5, -0.3, 0.45])  # W is KITTI camera 0 of frame 0: y down, z forward
view.set_up([0, -1, 0])
view.set_zoom(0.45)
vis.capture_screen_image(args.png, do_render=True)
print("wrote", args.png)
