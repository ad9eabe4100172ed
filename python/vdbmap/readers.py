# SPDX-License-Identifier: Apache-2.0
"""Readers of vdbmap's outputs into numpy arrays (formats: docs/DATA.md)."""
from __future__ import annotations

import json
import os
from typing import Any, Dict

import numpy as np

from . import _vdbmap
from ._vdbmap import DataError


def read_ply(path: "str | os.PathLike[str]") -> Dict[str, Any]:
    """Every element of a triangle PLY: {"vertices": (n, 3) float32, "faces": (m, 3) int64,
    "vertex": {property: (n,) float64}, "face": {property: (m,) float64}}."""
    return _vdbmap._read_ply(os.fspath(path))


def read_obj(path: "str | os.PathLike[str]") -> Dict[str, Any]:
    """An OBJ with its materials: positions, uvs, faces, face_uvs, face_material, materials."""
    return _vdbmap._read_obj(os.fspath(path))


def read_mesh(path: "str | os.PathLike[str]") -> Dict[str, Any]:
    """One of vdbmap's meshes as arrays, by extension:

    .ply (mesh.ply, semantic/mesh.ply): vertices (n, 3) float32, faces (m, 3) int64, and when
    present normals (n, 3), face_labels (m,) uint8, face_confidence (m,) float32,
    face_colors (m, 3) uint8, vertex_colors (n, 3) uint8.
    .obj (textured/mesh.obj): vertices, faces, uvs (k, 2) float32 (v up), face_uvs (m, 3),
    face_material (m,), materials [{name, diffuse, texture}] with texture paths made absolute.
    """
    path = os.fspath(path)
    ext = os.path.splitext(path)[1].lower()
    if ext == ".obj":
        obj = read_obj(path)
        base = os.path.dirname(os.path.abspath(path))
        for m in obj["materials"]:
            if m["texture"]:
                m["texture"] = os.path.join(base, m["texture"])
        return {"vertices": obj["positions"], "faces": obj["faces"], "uvs": obj["uvs"],
                "face_uvs": obj["face_uvs"], "face_material": obj["face_material"],
                "materials": obj["materials"]}
    if ext != ".ply":
        raise DataError(f"{path}: not a mesh vdbmap reads (expected .ply or .obj)")
    ply = read_ply(path)
    out: Dict[str, Any] = {"vertices": ply["vertices"], "faces": ply["faces"]}
    v, f = ply["vertex"], ply["face"]
    if all(k in v for k in ("nx", "ny", "nz")):
        out["normals"] = np.stack([v["nx"], v["ny"], v["nz"]], axis=1).astype(np.float32)
    if "label" in f:
        out["face_labels"] = f["label"].astype(np.uint8)
    if "confidence" in f:
        out["face_confidence"] = f["confidence"].astype(np.float32)
    if all(k in f for k in ("red", "green", "blue")):
        out["face_colors"] = np.stack([f["red"], f["green"], f["blue"]], axis=1).astype(np.uint8)
    if all(k in v for k in ("red", "green", "blue")):
        out["vertex_colors"] = np.stack([v["red"], v["green"], v["blue"]], axis=1).astype(np.uint8)
    return out


def read_tile_index(run_dir: "str | os.PathLike[str]") -> Dict[str, Any]:
    """A tiled run's tiles.json, checked, with each tile's files as absolute paths
    (tile["paths"]) and its bounds as numpy arrays (tile["bounds_W"]: (2, 3), min and max)."""
    run_dir = os.fspath(run_dir)
    path = os.path.join(run_dir, "tiles.json")
    try:
        with open(path, encoding="utf-8") as f:
            index = json.load(f)
    except FileNotFoundError:
        raise DataError(f"{path}: no tiles.json (not a tiled run, or the run did not finish)") from None
    except json.JSONDecodeError as e:
        raise DataError(f"{path}: not valid JSON ({e})") from None
    if index.get("format") != "vdbmap-tiles":
        raise DataError(f"{path}: 'format' is {index.get('format')!r}, expected 'vdbmap-tiles'")
    for tile in index.get("tiles", []):
        # "files" are relative to the run folder (tiles/<ix>_<iy>/mesh.ply ...)
        tile["paths"] = [os.path.join(run_dir, f) for f in tile.get("files", [])]
        for key in ("bounds_W", "halo_bounds_W"):
            if key in tile:
                box = tile[key]
                tile[key] = np.array([box["min"], box["max"]], dtype=np.float64)
    return index
