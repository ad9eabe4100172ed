#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Writes the hand-made seed inputs of tests/fuzz/corpus/ (small on purpose: libFuzzer mutates
short inputs fastest) from tests/data and config/. Run from the repository root; liblzf
(Debian liblzf-dev) compresses the binary_compressed PCD seeds. Findings are added to the
corpus folders by hand (crash-*/leak-*/timeout-* files) and are never regenerated."""
import ctypes
import os
import struct

root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
corpus = os.path.join(root, "tests", "fuzz", "corpus")
data = os.path.join(root, "tests", "data")
lzf = ctypes.CDLL("liblzf.so.1")


def put(target, name, content):
    d = os.path.join(corpus, target)
    os.makedirs(d, exist_ok=True)
    if isinstance(content, str):
        content = content.encode()
    with open(os.path.join(d, name), "wb") as f:
        f.write(content)


def compress(raw):
    out = ctypes.create_string_buffer(len(raw) * 2 + 64)
    n = lzf.lzf_compress(raw, len(raw), out, len(out))
    assert n > 0
    return out.raw[:n]


pts = [(1.0, 2.0, 3.0, 0.5), (-1.5, 0.25, 10.0, 0.0), (4.0, 4.0, -2.0, 1.0)]

# KITTI .bin: the first 100 points of a real scan, 3 points, a truncated scan, empty.
with open(os.path.join(data, "kitti_scans_real", "000000.bin"), "rb") as f:
    put("bin", "real_100_points.bin", f.read(1600))
put("bin", "three_points.bin", b"".join(struct.pack("<4f", *p) for p in pts))
put("bin", "truncated.bin", struct.pack("<4f", *pts[0])[:13])
put("bin", "empty.bin", b"")

# PCD: the real (PCL) header, and ascii / binary / binary_compressed with several types.
with open(os.path.join(data, "lidar_camera_real", "1", "calib.pcd"), "rb") as f:
    real = f.read(4096)
put("pcd", "real_header_compressed_cut.pcd", real)
head = ("# .PCD v0.7\nVERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\n"
        "COUNT 1 1 1 1\nWIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\n")
put("pcd", "ascii.pcd", head + "DATA ascii\n" + "".join("%g %g %g %g\n" % p for p in pts))
put("pcd", "binary.pcd", head.encode() + b"DATA binary\n" +
    b"".join(struct.pack("<4f", *p) for p in pts))
cols = b"".join(struct.pack("<3f", *[p[k] for p in pts]) for k in range(4))
packed = compress(cols)
put("pcd", "binary_compressed.pcd", head.encode() + b"DATA binary_compressed\n" +
    struct.pack("<II", len(packed), len(cols)) + packed)
mixed = ("VERSION 0.7\nFIELDS rgb x y z ring t\nSIZE 4 8 4 4 2 8\nTYPE U F F F U I\n"
         "COUNT 1 1 1 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA binary\n")
rec = lambda p: struct.pack("<IdffHq", 7, p[0], p[1], p[2], 3, -5)
put("pcd", "binary_mixed_types.pcd", mixed.encode() + rec(pts[0]) + rec(pts[1]))
put("pcd", "counts.pcd", "VERSION 0.7\nFIELDS x y z n\nSIZE 4 4 4 4\nTYPE F F F F\n"
    "COUNT 1 1 1 3\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3 0 0 1\n")

# LZF: streams liblzf wrote, each with the two-byte claimed size the target expects.
for name, raw in [("text", b"PCD binary_compressed x x x x x x y y y y y y"),
                  ("columns", cols), ("run", b"\0" * 300)]:
    put("lzf", name + ".lzf", struct.pack("<H", len(raw)) + compress(raw))

# PLY: the real CloudCompare binary header + 20 points, ascii mesh with labels, big endian.
with open(os.path.join(data, "scan_pair_real", "source.ply"), "rb") as f:
    real = f.read()
end = real.index(b"end_header\n") + len(b"end_header\n")
put("ply", "real_binary_points.ply",
    real[:end].replace(b"element vertex 69792", b"element vertex 20") + real[end:end + 320])
put("ply", "ascii_labelled_mesh.ply",
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
    "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
    "element face 3\nproperty list uchar int vertex_indices\nproperty uchar label\n"
    "end_header\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n1 1 0 0 0 1\n"
    "3 0 1 2 7\n3 1 3 2 8\n4 0 1 3 2 9\n")
verts = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
put("ply", "binary_big_endian_tetra.ply",
    b"ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty float x\n"
    b"property float y\nproperty float z\nelement face 4\n"
    b"property list uchar uint vertex_indices\nend_header\n" +
    b"".join(struct.pack(">3f", *v) for v in verts) +
    b"".join(struct.pack(">B3I", 3, *f) for f in [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]))
put("ply", "nonmanifold_ascii.ply",
    "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
    "property float z\nelement face 3\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n3 0 1 4\n")

# OBJ + MTL (separator "\n#--MTL--\n"): the first lines of Spot, a textured quad.
with open(os.path.join(data, "meshes", "spot_triangulated.obj")) as f:
    lines = f.read().splitlines()
v = [l for l in lines if l.startswith("v ")][:6]
vt = [l for l in lines if l.startswith("vt ")][:6]
put("obj", "spot_head.obj", "mtllib mesh.mtl\n" + "\n".join(v + vt) +
    "\nusemtl spot\nf 1/1 2/2 3/3\nf 4/4 5/5 6/6\nf 1/1 3/3 5/5\n"
    "\n#--MTL--\nnewmtl spot\nKd 1 1 1\nmap_Kd spot_texture.png\n")
put("obj", "quad_negative_indices.obj",
    "mtllib mesh.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "vn 0 0 1\nusemtl a\nf -4/-4/1 -3/-3/1 -2/-2/1 -1/-1/1\nusemtl b\nf 1 2 3\n"
    "\n#--MTL--\nnewmtl a\nKd 0.5 0.25 1\nnewmtl b\nmap_Kd tex.png\n")

# calib: the real generic file, a KITTI calib.txt, a rectified KITTI one.
with open(os.path.join(data, "lidar_camera_real", "1", "calib.txt")) as f:
    put("calib", "real_generic.txt", f.read())
P = "7.215377e+02 0 6.095593e+02 0 0 7.215377e+02 1.728540e+02 0 0 0 1 0"
Tr = "4.27e-04 -9.99e-01 -8.08e-03 -1.19e-02 -7.21e-03 8.08e-03 -9.99e-01 -5.40e-02 " \
     "9.99e-01 4.85e-04 -7.20e-03 -2.92e-01"
put("calib", "kitti.txt", "".join("P%d: %s\n" % (i, P) for i in range(4)) + "Tr: " + Tr + "\n")
put("calib", "kitti_velo.txt", "P0: %s\nP2: %s\nTr_velo_to_cam: %s\n" % (P, P, Tr))

# poses: KITTI rows and TUM lines.
put("poses", "kitti.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n"
    "0.99 -0.01 0.1 1.5 0.01 1 0 0.2 -0.1 0 0.99 3\n")
put("poses", "tum.txt", "# timestamp tx ty tz qx qy qz qw\n0.0 0 0 0 0 0 0 1\n"
    "0.1 1 2 3 0 0 0.7071 0.7071\n")

# label set: the default file and a small one.
with open(os.path.join(root, "config", "labels_default.txt")) as f:
    put("labelset", "labels_default.txt", f.read())
put("labelset", "small.txt", "0, road, 128 64 128\n7, car, 0 0 142\n")

# SemanticKITTI .label (+ "\n#--MAP--\n" and a label map file): raw ids with instance bits
# through the built-in map, through a small map file and the shipped one, an id the map does
# not know, a truncated file, empty.
raw = [40, 48, 10 | (3 << 16), 50, 0, 70, 81 | (1 << 16), 252]
labels = struct.pack("<%dI" % len(raw), *raw)
put("lidar_labels", "semantickitti_ids.label", labels)
put("lidar_labels", "small_map.label", labels[:12] + b"\n#--MAP--\n" +
    b"40 0\n48 1 # sidewalk\n10 7\n")
with open(os.path.join(root, "config", "label_maps", "semantickitti.txt"), "rb") as f:
    put("lidar_labels", "shipped_map.label", labels + b"\n#--MAP--\n" + f.read())
put("lidar_labels", "unknown_id.label", struct.pack("<2I", 40, 9999) + b"\n#--MAP--\n40 0\n")
put("lidar_labels", "truncated.label", labels[:7])
put("lidar_labels", "empty.label", b"")

# pipeline YAML (+ "\n#--SET--\n" overrides): small configs of the built-in stages.
put("pipeline_yaml", "atsdf_mesh.yaml",
    "stages:\n  - stage: integrate.atsdf\n    voxel_size_m: 0.1\n    truncation_mode: adaptive\n"
    "  - stage: mesh.marching_cubes\n    min_weight: 0.5\noutput: {dir: out, write_map: true}\n"
    "\n#--SET--\nintegrate.atsdf.voxel_size_m=0.05\n#--SET--\nstages.1.min_weight=[1, 2]")
put("pipeline_yaml", "dataset_flow.yaml",
    "dataset:\n  format: generic\n  path: .\n  scans_dir: scans\n  poses_file: poses.txt\n"
    "  cameras:\n    - {name: front, image_dir: img, intrinsics: [500, 500, 320, 240]}\n"
    "stages: [{stage: integrate.atsdf}, {stage: mesh.marching_cubes}]\n"
    "\n#--SET--\ndataset.first_frame=3\n#--SET--\noutput.write_mesh=false")
put("pipeline_yaml", "bad_anchor.yaml", "stages: &a [*a, {stage: integrate.atsdf, x: !!binary 'AAA='}]\n")
