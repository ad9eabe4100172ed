#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Medians of bench_integration JSON lines (one per run), as the Markdown table of
docs/benchmarks/integration.md. Usage: bench/integration_table.py runs.jsonl"""
import json
import statistics
import sys
from collections import defaultdict


def main(path):
    groups = defaultdict(list)
    with open(path) as f:
        for line in f:
            line = line.strip()
            if line.startswith("{"):
                j = json.loads(line)
                groups[(j["voxel_m"], j["mode"], j["threads"])].append(j)
    cols = [
        ("Mpts/s", "mpts_per_s", "{:.2f}"),
        ("ms/scan (median scan)", "ms_per_scan_median", "{:.1f}"),
        ("ns/voxel update", "ns_per_voxel_update", "{:.1f}"),
        ("meshing s", "mesh_s", "{:.2f}"),
        ("faces", "faces", "{:.0f}"),
        ("peak RSS MB", "peak_rss_mb", "{:.0f}"),
        ("B/active voxel (at rest)", "bytes_per_active_voxel", "{:.1f}"),
        ("B/active voxel (last scan, working set dense)", "bytes_per_active_voxel_before_finalize", "{:.1f}"),
        ("peak TSDF MB", "peak_tsdf_mb", "{:.1f}"),
        ("B/leaf (at rest)", "bytes_per_leaf_grids", "{:.0f}"),
        ("mean leaf fill", "mean_leaf_fill", "{:.0f}"),
        ("B/leaf stats", "bytes_per_leaf_stats", "{:.0f}"),
    ]
    print("| voxel m | mode | threads | runs | " + " | ".join(c[0] for c in cols) + " |")
    print("|---" * (4 + len(cols)) + "|")
    order = {"adaptive": 0, "fixed": 1}
    for key in sorted(groups, key=lambda k: (k[0] != 0.1, k[0], order.get(k[1], 2), k[2])):
        runs = groups[key]
        cells = [fmt.format(statistics.median(r[field] for r in runs)) for _, field, fmt in cols]
        print(f"| {key[0]:.2f} | {key[1]} | {key[2]} | {len(runs)} | " + " | ".join(cells) + " |")
    # Phase split of the 0.10 m runs (seconds over all scans, medians).
    print()
    print("| voxel m | mode | threads | bin s | stats s | alloc s | update s | retire s | CPU s | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for key in sorted(groups, key=lambda k: (k[0] != 0.1, k[0], order.get(k[1], 2), k[2])):
        runs = groups[key]
        med = lambda f: statistics.median(r.get(f, float("nan")) for r in runs)
        print(f"| {key[0]:.2f} | {key[1]} | {key[2]} | {med('phase_bin_s'):.3f} | "
              f"{med('phase_stats_s'):.3f} | {med('phase_alloc_s'):.3f} | {med('phase_update_s'):.3f} | "
              f"{med('phase_retire_s'):.3f} | "
              f"{med('cpu_s'):.2f} | {med('seconds'):.2f} |")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: integration_table.py runs.jsonl")
    main(sys.argv[1])
