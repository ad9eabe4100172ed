#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
"""Open3D (python3-open3d) reads a leaf GLB of export.3dtiles (written with `compression: none`:
Open3D's glTF reader does not decode EXT_meshopt_compression) and finds the faces of its
tile.json, with texture coordinates. Usage: scripts/tiles3d_open3d_check.py TILE.glb"""
import json
import os
import sys

import open3d as o3d

glb = sys.argv[1]
side = json.load(open(os.path.join(os.path.dirname(glb), "tile.json")))
mesh = o3d.io.read_triangle_mesh(glb, enable_post_processing=False)
faces = len(mesh.triangles)
print(f"open3d {o3d.__version__}: {glb}: {len(mesh.vertices)} vertices, {faces} triangles, "
      f"uvs {len(mesh.triangle_uvs)}, textures {len(mesh.textures)}; tile.json faces {side['faces']}")
ok = faces == side["faces"] and len(mesh.triangle_uvs) == 3 * faces
print("open3d check:", "OK" if ok else "FAILED")
sys.exit(0 if ok else 1)
