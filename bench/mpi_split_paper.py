#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Issue 37's MPI split on paper: a longer drive and more ranks, from the measured per-tile CPU
times of one vdbmap-mpi run (docs/benchmarks/scale.md).

    bench/mpi_split_paper.py BUILD REPORT.json ONE_CPU_S COPIES RANKS

REPORT.json: a `vdbmap-mpi run --threads 1` run of K ranks (tiles one at a time on one thread,
so each tile's `cpu_time_s` is its own); ONE_CPU_S: one rank's CPU time on the same drive.
The drive is made COPIES times as long: its first and last 200 frames' tiles once, its middle
tiles repeated in between (each with its scan frames shifted), and one rank's CPU scaled with
the frames; its tiles split over RANKS by the ranks' own code
(BUILD/bin/mpi_split_partition: partitionContiguous of each tile's cost_estimate_s, the
estimate the ranks split on). A rank's CPU is then the measured CPU of its tiles plus the rest
of a rank's work (reading and integrating its scans, deciding its share of the moving points,
setup), fitted on the K measured ranks as a + b * frames integrated. The fit holds when each
rank decides as many frames as in the measured run (drive frames * COPIES / RANKS = frames / K).
Prints the measured ranks against the model, then the prediction. OLD_ESTIMATE=1 in the
environment splits on the estimate before issue 37's calibration (the weighted frames + 0.05)."""
import json
import os
import subprocess
import sys

EDGE_FRAMES = 200  # the start and end of the measured drive, kept once (not repeated)


def fit_line(xs, ys):
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    b = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx else 0.0
    return my - b * mx, b


def union_length(intervals):
    total, end = 0, None
    for lo, hi in sorted(intervals):
        if end is None or lo > end:
            total += hi - lo + 1
            end = hi
        elif hi > end:
            total += hi - end
            end = hi
    return total


def partition(build, costs, parts):
    out = subprocess.run([build + "/bin/mpi_split_partition", str(parts)], check=True,
                         input="\n".join("%.17g" % c for c in costs), capture_output=True, text=True)
    return [int(line) for line in out.stdout.split()]


def main():
    build, report_path, one_cpu, copies, ranks = sys.argv[1], sys.argv[2], float(sys.argv[3]), \
        int(sys.argv[4]), int(sys.argv[5])
    with open(report_path) as f:
        report = json.load(f)
    frames = report["counts"]["frames"]
    plan = report["tiling"]["plan"]
    cpu_of = {name: t["cpu_time_s"] for name, t in report["tiles"].items()}
    procs = report["distributed"]["process"]
    k = len(procs)
    tile_cpu = [0.0] * k
    for t in plan:
        tile_cpu[t["process"]] += cpu_of.get(t["name"], 0.0)
    # A rank's own work, before it waited for the others (MPI busy-polls while waiting).
    own = [p.get("own_work_cpu_time_s", p["cpu_time_s"]) for p in procs]
    rest = [o - c for o, c in zip(own, tile_cpu)]
    xs = [p["frames_integrated"] for p in procs]
    a, b = fit_line(xs, rest)
    print("measured: %d ranks, %d frames, %d planned tiles; rest of a rank = %.1f s + %.4f s per frame integrated"
          % (k, frames, len(plan), a, b))
    print("| rank | tiles' CPU (s) | frames integrated | rest (s) | rest, model (s) | CPU (s) |")
    print("|---|---|---|---|---|---|")
    for r in range(k):
        print("| %d | %.1f | %d | %.1f | %.1f | %.1f |" % (r, tile_cpu[r], xs[r], rest[r], a + b * xs[r],
                                                         own[r]))
    if abs(frames * copies / ranks - frames / k) > 0.05 * frames / k:
        print("warning: a rank decides %.0f frames here, %.0f in the measured run: the fit's "
              "constant does not carry over" % (frames * copies / ranks, frames / k))
    # A drive COPIES times as long: the measured drive's start (tiles finished in its first
    # EDGE frames) and end (its last EDGE frames) once, its middle repeated in between, each
    # tile shifted with its scan frames, in finish order.
    edge = EDGE_FRAMES
    middle = frames - 2 * edge
    repeats = (frames * copies - 2 * edge) // middle

    def tile(t, shift):
        # OLD_ESTIMATE=1: the estimate before the calibration (the weighted frames + 0.05).
        cost = t["weighted_frames"] + 0.05 if os.environ.get("OLD_ESTIMATE") else t["cost_estimate_s"]
        return {"cost": cost, "cpu": cpu_of.get(t["name"], 0.0), "finish": t["finish_frame"] + shift,
                "frames": (t["first_scan_frame"] + shift, t["last_scan_frame"] + shift)}

    tiles = [tile(t, 0) for t in plan if t["finish_frame"] < edge]
    for k in range(repeats):
        tiles += [tile(t, k * middle) for t in plan if edge <= t["finish_frame"] < frames - edge]
    tiles += [tile(t, (repeats - 1) * middle) for t in plan if t["finish_frame"] >= frames - edge]
    tiles.sort(key=lambda t: t["finish"])  # stable: the plan's order within a frame
    parts = partition(build, [t["cost"] for t in tiles], ranks)
    cpu = []
    for r in range(ranks):
        mine = [t for t, p in zip(tiles, parts) if p == r]
        n = union_length([t["frames"] for t in mine])
        cpu.append(sum(t["cpu"] for t in mine) + (a + b * n if mine else 0.0))
    one = one_cpu * (2 * edge + repeats * middle) / frames
    print("\npredicted: %d ranks on %d copies of the drive (%d tiles); one rank %.0f s" % (
        ranks, copies, len(tiles), one))
    print("CPU per rank (s): " + ", ".join("%.0f" % c for c in cpu))
    print("| ranks | largest rank (s) | sum / one | predicted speed-up | efficiency |")
    print("|---|---|---|---|---|")
    print("| %d | %.0f | %.2f | %.2f | %.2f |" % (ranks, max(cpu), sum(cpu) / one, one / max(cpu),
                                                one / max(cpu) / ranks))


if __name__ == "__main__":
    main()
