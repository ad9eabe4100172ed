#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Merges the tiles of a tiled `vdbmap run` (tiles.json) into the single outputs of docs/DATA.md:
mesh.ply, semantic/mesh.ply (face labels and colours) and textured/mesh.obj (+ mesh.mtl whose
materials point at the tiles' atlas pages). Faces are concatenated tile by tile (no tile owns a
face twice, so nothing is dropped); vertices on tile borders appear once per tile.

    scripts/merge_tiles.py OUT_DIR [--to MERGED_DIR]   (default: OUT_DIR/merged)

Needs only the Python standard library. Exit 1 on a missing or malformed file."""
import argparse
import json
import os
import struct
import sys


def read_ply(path):
    """Binary little-endian PLY as written by vdbmap: vertices (x y z [nx ny nz]), faces
    (uchar count + int indices [+ uchar label red green blue])."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    nv = nf = 0
    vprops, fprops, current = [], [], None
    for line in header:
        parts = line.split()
        if parts[:2] == ["element", "vertex"]:
            nv, current = int(parts[2]), vprops
        elif parts[:2] == ["element", "face"]:
            nf, current = int(parts[2]), fprops
        elif parts and parts[0] == "property" and current is not None:
            # (name, type): the face list first, then per-face scalars (label, colour, ...)
            current.append((parts[-1], parts[1] if parts[1] != "list" else "list"))
    if any(t != "float" for _, t in vprops) or len(vprops) not in (3, 6):
        raise ValueError(f"{path}: unexpected vertex properties {vprops}")
    vprops = [name for name, _ in vprops]
    vsize = 4 * len(vprops)
    verts = data[end:end + nv * vsize]
    # After vertex_indices: uchar label red green blue, float confidence, ...
    sizes = {"char": 1, "uchar": 1, "short": 2, "ushort": 2, "int": 4, "uint": 4, "float": 4,
             "double": 8}
    if any(t not in sizes for _, t in fprops[1:]):
        raise ValueError(f"{path}: unexpected face properties {fprops}")
    extras = sum(sizes[t] for _, t in fprops[1:])
    fsize = 1 + 12 + extras
    off = end + nv * vsize
    faces = []
    for i in range(nf):
        base = off + i * fsize
        if data[base] != 3:
            raise ValueError(f"{path}: face {i} is not a triangle")
        idx = struct.unpack_from("<3i", data, base + 1)
        extra = data[base + 13:base + 13 + extras]
        faces.append((idx, extra))
    return vprops, verts, faces, fprops


def write_ply(path, vprops, chunks, fprops):
    nv = sum(len(v) // (4 * len(vprops)) for v, _ in chunks)
    nf = sum(len(f) for _, f in chunks)
    lines = ["ply", "format binary_little_endian 1.0", "comment vdbmap merge_tiles.py",
             f"element vertex {nv}"] + [f"property float {p}" for p in vprops] + \
            [f"element face {nf}", "property list uchar int vertex_indices"] + \
            [f"property {t} {name}" for name, t in fprops[1:]] + ["end_header"]
    with open(path + ".tmp", "wb") as out:
        out.write(("\n".join(lines) + "\n").encode("ascii"))
        for v, _ in chunks:
            out.write(v)
        base = 0
        for v, faces in chunks:
            for idx, extra in faces:
                out.write(struct.pack("<B3i", 3, idx[0] + base, idx[1] + base, idx[2] + base))
                out.write(extra)
            base += len(v) // (4 * len(vprops))
    os.replace(path + ".tmp", path)


def merge_ply(out_dir, tiles, rel, dest):
    chunks, vprops, fprops = [], None, None
    for t in tiles:
        path = os.path.join(out_dir, "tiles", t["name"], rel)
        if not os.path.exists(path):
            continue
        vp, verts, faces, fp = read_ply(path)
        vprops, fprops = vp, fp
        chunks.append((verts, faces))
    if chunks:
        os.makedirs(os.path.dirname(dest) or ".", exist_ok=True)
        write_ply(dest, vprops, chunks, fprops)
    return sum(len(f) for _, f in chunks)


def merge_obj(out_dir, tiles, dest_dir):
    os.makedirs(dest_dir, exist_ok=True)
    obj, mtl = ["# vdbmap merge_tiles.py", "mtllib mesh.mtl"], ["# vdbmap merge_tiles.py"]
    v_base = vt_base = 0
    faces = 0
    for t in tiles:
        tdir = os.path.join(out_dir, "tiles", t["name"], "textured")
        if not os.path.exists(os.path.join(tdir, "mesh.obj")):
            continue
        nv = nvt = 0
        for line in open(os.path.join(tdir, "mesh.mtl")):
            parts = line.split()
            if parts and parts[0] == "newmtl":
                mtl.append(f"newmtl {t['name']}_{parts[1]}")
            elif parts and parts[0] == "map_Kd":
                rel = os.path.relpath(os.path.join(tdir, parts[1]), dest_dir)
                mtl.append(f"map_Kd {rel}")
            elif parts:
                mtl.append(line.rstrip("\n"))
        for line in open(os.path.join(tdir, "mesh.obj")):
            parts = line.split()
            if not parts or parts[0] in ("#", "mtllib"):
                continue
            if parts[0] == "v":
                nv += 1
                obj.append(line.rstrip("\n"))
            elif parts[0] == "vt":
                nvt += 1
                obj.append(line.rstrip("\n"))
            elif parts[0] == "usemtl":
                obj.append(f"usemtl {t['name']}_{parts[1]}")
            elif parts[0] == "f":
                corners = []
                for c in parts[1:]:
                    v, vt = c.split("/")[:2]
                    corners.append(f"{int(v) + v_base}/{int(vt) + vt_base}")
                obj.append("f " + " ".join(corners))
                faces += 1
            else:
                obj.append(line.rstrip("\n"))
        v_base += nv
        vt_base += nvt
    for name, lines in (("mesh.mtl", mtl), ("mesh.obj", obj)):
        path = os.path.join(dest_dir, name)
        with open(path + ".tmp", "w") as f:
            f.write("\n".join(lines) + "\n")
        os.replace(path + ".tmp", path)
    return faces


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out_dir")
    ap.add_argument("--to", default=None)
    a = ap.parse_args()
    try:
        index = json.load(open(os.path.join(a.out_dir, "tiles.json")))
        tiles = index["tiles"]
        dest = a.to or os.path.join(a.out_dir, "merged")
        os.makedirs(dest, exist_ok=True)
        n = merge_ply(a.out_dir, tiles, "mesh.ply", os.path.join(dest, "mesh.ply"))
        s = merge_ply(a.out_dir, tiles, "semantic/mesh.ply", os.path.join(dest, "semantic", "mesh.ply"))
        t = merge_obj(a.out_dir, tiles, os.path.join(dest, "textured"))
    except (OSError, ValueError, KeyError, json.JSONDecodeError) as e:
        print(f"merge_tiles.py: {e}", file=sys.stderr)
        return 1
    print(f"merged {len(tiles)} tiles into {dest}: mesh {n} faces, semantic {s}, textured {t}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
