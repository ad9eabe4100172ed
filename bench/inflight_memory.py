#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
# Issue 37, "peak memory, 1.6 km against 400 m": where a tiles-in-flight run's memory goes.
# For each report.json: the run's peak, CPU, the memory without tiles (RSS each time a tile was
# launched with none in flight: the compact map, the scan reader, what the allocator kept), its
# first, middle and last samples, the compact map (active voxels x bytes per voxel), and the
# peak as the tiles finished (report.json tiles.<name>.peak_memory_bytes, in finish order), and
# what the allocator keeps: RSS minus its bytes in use at each launch (memory_at_launch_bytes).
#   bench/inflight_memory.py WORK/inflight/report.json [more reports...]
import json
import statistics
import sys

GIB = 1024.0 ** 3


def main():
    for path in sys.argv[1:]:
        r = json.load(open(path))
        f = r["tiling"]["in_flight"]
        atsdf = r["stages"]["integrate.atsdf"]
        base = f.get("memory_without_tiles_bytes", [])
        compact = atsdf["voxels_active"] * atsdf["bytes_per_active_voxel"]
        print(f"{path}: peak {r['peak_memory_bytes'] / GIB:.3f} GiB ({r['peak_memory_bytes']} B), "
              f"CPU {r['timings']['cpu_s']:.1f} s, budget {f['memory_budget_bytes'] / GIB:.1f} GiB, "
              f"most in flight {f['most_tiles_in_flight']}, active voxels {atsdf['voxels_active'] / 1e6:.1f} M "
              f"(compact map {compact / GIB:.3f} GiB)")
        if base:
            n = len(base)
            print(f"  memory without tiles ({n} samples): first {base[0] / GIB:.3f}, "
                  f"middle {base[n // 2] / GIB:.3f}, last {base[-1] / GIB:.3f}, "
                  f"max {max(base) / GIB:.3f} GiB")
        heavy = sum(1 for t in r["tiles"].values() if t["memory_estimate_bytes"] >= 0.75 * GIB)
        print(f"  {len(r['tiles'])} tiles, {heavy} estimated at 0.75 GiB or more")
        launches = f.get("memory_at_launch_bytes", [])
        if launches:
            # [RSS, allocator bytes in use, allocator free bytes, estimates in flight(, base counted)]
            kept = [(x[0] - x[1]) / GIB for x in launches]
            half = kept[len(kept) // 2:]
            print(f"  RSS - allocator bytes in use at the {len(kept)} launches: median "
                  f"{statistics.median(kept):.3f}, max {max(kept):.3f}, second half median "
                  f"{statistics.median(half):.3f} GiB; bytes in use median "
                  f"{statistics.median(x[1] for x in launches) / GIB:.3f}, max "
                  f"{max(x[1] for x in launches) / GIB:.3f} GiB")
        tiles = sorted(r["tiles"].items(), key=lambda kv: (kv[1]["finished_after_frame"] % 10**9, kv[0]))
        steps = []
        for name, t in tiles:
            p = t["peak_memory_bytes"] / GIB
            if not steps or abs(steps[-1][1] - p) > 1e-3:
                steps.append((t["finished_after_frame"], p, name))
        print("  peak so far, as tiles finished: " +
              ", ".join(f"{p:.3f} @{fr} ({n})" for fr, p, n in steps))


if __name__ == "__main__":
    main()
