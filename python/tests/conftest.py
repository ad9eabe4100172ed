# SPDX-License-Identifier: Apache-2.0
"""Shared fixtures of the Python tests: where the build and the test data are, and analytic
LiDAR scans (a ray fan against a plane or a box, hit points in closed form)."""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

SOURCE_DIR = Path(os.environ.get("VDBMAP_SOURCE_DIR", Path(__file__).resolve().parents[2]))
BIN_DIR = Path(os.environ.get("VDBMAP_BIN_DIR", SOURCE_DIR / "build" / "bin"))
TEST_DATA = SOURCE_DIR / "tests" / "data"


@pytest.fixture
def bin_dir() -> Path:
    return BIN_DIR


@pytest.fixture
def kitti_scans() -> list:
    """The six real KITTI scans of tests/data/kitti_scans_real, (N, 3) float32 in L."""
    scans = []
    for i in range(6):
        raw = np.fromfile(TEST_DATA / "kitti_scans_real" / f"{i:06d}.bin", dtype=np.float32)
        scans.append(np.ascontiguousarray(raw.reshape(-1, 4)[:, :3]))
    return scans


def ray_fan(n_azimuth: int = 720, elevations_deg=None) -> np.ndarray:
    """Unit ray directions of a spinning LiDAR in L: rings at the given elevations."""
    if elevations_deg is None:
        elevations_deg = np.linspace(-24.0, 2.0, 64)
    az = np.linspace(0.0, 2.0 * np.pi, n_azimuth, endpoint=False)
    el = np.radians(np.asarray(elevations_deg))
    A, E = np.meshgrid(az, el)
    d = np.stack([np.cos(E) * np.cos(A), np.cos(E) * np.sin(A), np.sin(E)], axis=-1)
    return d.reshape(-1, 3)


def pose(x: float = 0.0, y: float = 0.0, z: float = 0.0, yaw: float = 0.0) -> np.ndarray:
    T = np.eye(4)
    c, s = np.cos(yaw), np.sin(yaw)
    T[:2, :2] = [[c, -s], [s, c]]
    T[:3, 3] = [x, y, z]
    return T


def hits_plane_z(T_W_L: np.ndarray, dirs_L: np.ndarray, z0: float, max_range: float = 40.0) -> np.ndarray:
    """Points in L where the rays meet the plane z = z0 of W (closed form)."""
    o = T_W_L[:3, 3]
    d_W = dirs_L @ T_W_L[:3, :3].T
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (z0 - o[2]) / d_W[:, 2]
    ok = np.isfinite(t) & (t > 0.0) & (t < max_range)
    return (dirs_L[ok] * t[ok, None]).astype(np.float32)


def hits_box(T_W_L: np.ndarray, dirs_L: np.ndarray, lo, hi, z_ground=None, max_range: float = 40.0) -> np.ndarray:
    """Points in L where the rays first meet an axis-aligned box [lo, hi] of W (slab method),
    or the ground plane z = z_ground when given and nearer."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    o = T_W_L[:3, 3]
    d = dirs_L @ T_W_L[:3, :3].T
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = (lo - o) / d
        t2 = (hi - o) / d
    tmin = np.nanmax(np.minimum(t1, t2), axis=1)
    tmax = np.nanmin(np.maximum(t1, t2), axis=1)
    t = np.where((tmax >= tmin) & (tmin > 0.0), tmin, np.inf)
    if z_ground is not None:
        with np.errstate(divide="ignore", invalid="ignore"):
            tg = (z_ground - o[2]) / d[:, 2]
        t = np.minimum(t, np.where(tg > 0.0, tg, np.inf))
    ok = np.isfinite(t) & (t < max_range)
    return (dirs_L[ok] * t[ok, None]).astype(np.float32)


def box_distance(p: np.ndarray, lo, hi) -> np.ndarray:
    """Unsigned distance of points to the surface of the box [lo, hi] (closed form)."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    c, h = (lo + hi) / 2.0, (hi - lo) / 2.0
    q = np.abs(p - c) - h
    outside = np.linalg.norm(np.maximum(q, 0.0), axis=1)
    inside = np.minimum(np.max(q, axis=1), 0.0)
    return np.abs(outside + inside)
