# SPDX-License-Identifier: Apache-2.0
"""The writer's CPU share of a run from a poll of its CPU time (bench/tiles3d_cpu_poll.sh),
for a report.json without finish_run_cpu_s: the parents' CPU is the CPU spent in the last
finish_run_s seconds before report.json was written (finishRun of export.3dtiles is the last
step; the poll's resolution is 1 s), the leaves' is at most their wall time (one thread each).
Usage: python3 bench/tiles3d_poll_share.py RUN_DIR POLL_FILE"""
import json
import os
import sys


def main():
    run, poll = sys.argv[1], sys.argv[2]
    report = os.path.join(run, "report.json")
    r = json.load(open(report))
    st = r["stages"]["export.3dtiles"]
    ticks = 100.0
    samples = []
    for line in open(poll):
        if line.startswith("#"):
            ticks = float(line.split(":")[1])
            continue
        t, c = line.split()
        samples.append((float(t), float(c) / ticks))
    end = os.path.getmtime(report)
    start = end - st["finish_run_s"]
    before = max((s for s in samples if s[0] <= start), key=lambda s: s[0])
    last = samples[-1]
    lod_cpu = last[1] - before[1]
    leaves_wall = sum(t["stages"]["export.3dtiles"]["wall_time_s"] for t in r["tiles"].values())
    cpu = r["timings"]["cpu_s"]
    print(f"parents: {st['finish_run_s']:.1f} s wall, {lod_cpu:.1f} s CPU (poll {before[0]:.0f} -> {last[0]:.0f}, "
          f"finishRun from {start:.0f}); leaves: {leaves_wall:.1f} s wall (>= their CPU)")
    print(f"run: {r['timings']['total_s']:.1f} s wall, {cpu:.1f} s CPU; writer's CPU share <= "
          f"{100 * (lod_cpu + leaves_wall) / cpu:.1f} %")


main()
