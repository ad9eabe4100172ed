#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Python's Map.integrate against `vdbmap run`'s integration of the same scans, in one script
(docs/benchmarks/python.md). Usage:
    PYTHONPATH=build/python /usr/bin/python3 bench/python_integrate.py [--frames 50] [--repeat 3]
Simulates a KITTI-layout street (vdbmap-sim), then alternates: `vdbmap run` with only
integrate.atsdf (its integration time: stages.integrate.atsdf.seconds minus the time it waited
for the reader), and a Python loop of Map.integrate over the scans already in memory. Prints
medians and their ratio, and the memory a 120 k-point scan costs in the call."""
import argparse
import json
import statistics
import subprocess
import tempfile
import time
import tracemalloc
from pathlib import Path

import numpy as np
import vdbmap
from vdbmap.vdbfusion import VDBVolume

ROOT = Path(__file__).resolve().parents[1]
BIN = ROOT / "build" / "bin"


def read_kitti(seq: Path):
    poses = [np.vstack([np.array(l.split(), float).reshape(3, 4), [0, 0, 0, 1]]) for l in open(seq / "poses.txt")]
    tr = next(l.split()[1:] for l in open(seq / "calib.txt") if l.startswith("Tr:"))
    T_C0_L = np.vstack([np.array(tr, float).reshape(3, 4), [0, 0, 0, 1]])
    scans = [np.ascontiguousarray(np.fromfile(f, np.float32).reshape(-1, 4)[:, :3])
             for f in sorted((seq / "velodyne").glob("*.bin"))]
    return scans, [T @ T_C0_L for T in poses]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--frames", type=int, default=50)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--threads", type=int, default=0)
    a = ap.parse_args()
    work = Path(tempfile.mkdtemp(prefix="vdbmap_py_bench_"))
    seq = work / "seq"
    subprocess.run([str(BIN / "vdbmap-sim"), "street", "--frames", str(a.frames), "--no-images",
                    "--gt-views", "0", "--quiet", "-o", str(seq)], check=True)
    cfg = work / "integrate.yaml"
    cfg.write_text(f"dataset: {{format: kitti, path: {seq}, min_range_m: 0.001, max_range_m: 1000}}\n"
                   "stages:\n  - stage: integrate.atsdf\noutput: {write_map: false}\n")
    scans, poses = read_kitti(seq)
    threads = ["--threads", str(a.threads)] if a.threads else []
    cpp, py, vdbf = [], [], []
    for r in range(a.repeat):
        out = work / f"run{r}"
        subprocess.run([str(BIN / "vdbmap"), "run", str(cfg), "-o", str(out), "--quiet", *threads], check=True)
        st = json.load(open(out / "report.json"))["stages"]["integrate.atsdf"]
        cpp.append(st["seconds"] - st["read_wait_s"])
        m = vdbmap.Map()
        t0 = time.perf_counter()
        for points, T in zip(scans, poses):
            m.integrate(points, T)
        py.append(time.perf_counter() - t0)
        assert m.stats["points_integrated"] == st["points_integrated"], (m.stats, st)
        # The VDBFusion-style script of docs/python.md (voxel 0.1 m, sdf_trunc 0.3 m).
        vol = VDBVolume(voxel_size=0.1, sdf_trunc=0.3, space_carving=False)
        t0 = time.perf_counter()
        for points, T in zip(scans, poses):
            vol.integrate(points, T)
        vdbf.append(time.perf_counter() - t0)
    # Memory of one call on a 120 k-point float32 scan (numpy's allocations, tracemalloc).
    big = np.ascontiguousarray(np.resize(scans[0], (120_000, 3)))
    big64 = big.astype(np.float64)
    m = vdbmap.Map()
    m.integrate(big, poses[0])
    tracemalloc.start()
    base = tracemalloc.get_traced_memory()[0]
    m.integrate(big, poses[0])
    extra32 = tracemalloc.get_traced_memory()[1] - base
    tracemalloc.reset_peak()
    base = tracemalloc.get_traced_memory()[0]
    m.integrate(big64, poses[0])
    extra64 = tracemalloc.get_traced_memory()[1] - base
    tracemalloc.stop()
    c, p = statistics.median(cpp), statistics.median(py)
    print(json.dumps({"frames": len(scans), "points": int(sum(len(s) for s in scans)),
                      "cpp_integrate_s": cpp, "python_integrate_s": py,
                      "median_cpp_s": round(c, 3), "median_python_s": round(p, 3),
                      "python_over_cpp": round(p / c, 3),
                      "vdbfusion_style_script_s": vdbf,
                      "median_vdbfusion_style_script_s": round(statistics.median(vdbf), 3),
                      "scan_bytes_float32": big.nbytes, "extra_bytes_float32_call": extra32,
                      "extra_bytes_float64_call": extra64}, indent=1))


if __name__ == "__main__":
    main()
