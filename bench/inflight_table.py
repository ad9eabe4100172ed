#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""The table of bench/inflight.sh: per run, wall (report.json timings.total_s), CPU (user + sys
of /usr/bin/time -v: every rank's for MPI), cores busy = CPU / wall, peak memory (report.json;
MPI: the largest rank's), the memory budget, the most tiles in flight; medians over repeats."""
import json
import pathlib
import re
import statistics
import sys

work = pathlib.Path(sys.argv[1])
rows = {}
for report in sorted(work.glob("*_*/report.json")):
    step, k = report.parent.name.rsplit("_", 1)
    r = json.loads(report.read_text())
    t = (work / f"{step}_{k}.time").read_text() if (work / f"{step}_{k}.time").exists() else ""
    user = re.search(r"User time \(seconds\): ([\d.]+)", t)
    sys_ = re.search(r"System time \(seconds\): ([\d.]+)", t)
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): ([\d:.]+)", t)
    cpu = float(user.group(1)) + float(sys_.group(1)) if user else r["timings"]["cpu_s"]
    if wall:
        parts = [float(p) for p in wall.group(1).split(":")]
        wall_s = sum(p * 60 ** i for i, p in enumerate(reversed(parts)))
    else:
        wall_s = r["timings"]["total_s"]
    peak = r.get("peak_memory_bytes", 0)
    procs = r.get("distributed", {}).get("process", [])
    if procs:
        peak = max(p["peak_memory_bytes"] for p in procs)
    inflight = r.get("tiling", {}).get("in_flight", {})
    rows.setdefault(step, []).append(dict(wall=wall_s, cpu=cpu, busy=cpu / wall_s, peak=peak / 2**30,
                                          budget=inflight.get("memory_budget_bytes", 0) / 2**30,
                                          most=inflight.get("most_tiles_in_flight", "-"),
                                          est=inflight.get("largest_estimate_in_flight_bytes", 0) / 2**30))
print("| run | runs | wall (s) | CPU (s) | cores busy | peak (GiB) | budget (GiB) | most in flight | largest estimate in flight (GiB) |")
print("|---|---|---|---|---|---|---|---|---|")
for step, rs in rows.items():
    med = lambda key: statistics.median(x[key] for x in rs)
    print(f"| {step} | {len(rs)} | {med('wall'):.1f} | {med('cpu'):.1f} | {med('busy'):.2f} | {med('peak'):.2f} | "
          f"{med('budget'):.1f} | {rs[0]['most']} | {med('est'):.2f} |")
