#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Calibrates the tile cost estimate of the MPI split (TilePlan.cpp, tileCostEstimate) on the
measured CPU time of each tile (docs/benchmarks/scale.md, issue 37).

    bench/mpi_split_calibrate.py REPORT.json [REPORT.json ...]

Each report is of a run whose tiles ran one at a time on one thread (`vdbmap run --threads 1`,
or `vdbmap-mpi run --threads 1` ranks), so that a tile's `cpu_time_s` is its own. Its
`tiling.plan` gives each tile's pose-based features (weighted_frames, views). Prints the
least-squares fits cpu = a + b * weighted_frames + c * views and the others below, with the
relative error of each tile, and the error of the estimate the run itself used."""
import json
import sys


def solve(rows, ys):
    """Least squares of ys ~ rows (lists of features) by the normal equations."""
    n = len(rows[0])
    a = [[sum(r[i] * r[j] for r in rows) for j in range(n)] for i in range(n)]
    b = [sum(r[i] * y for r, y in zip(rows, ys)) for i in range(n)]
    for c in range(n):  # Gauss-Jordan with partial pivoting
        p = max(range(c, n), key=lambda k: abs(a[k][c]))
        a[c], a[p], b[c], b[p] = a[p], a[c], b[p], b[c]
        for k in range(n):
            if k != c and a[c][c] != 0:
                f = a[k][c] / a[c][c]
                a[k] = [x - f * y for x, y in zip(a[k], a[c])]
                b[k] -= f * b[c]
    return [b[i] / a[i][i] if a[i][i] else 0.0 for i in range(n)]


def samples(paths):
    out = []
    for path in paths:
        with open(path) as f:
            report = json.load(f)
        plan = {t["name"]: t for t in report["tiling"]["plan"]}
        for name, tile in report["tiles"].items():
            p = plan[name]
            out.append({"name": name, "cpu": tile["cpu_time_s"], "w": p["weighted_frames"],
                        "v": p["views"], "used": p["cost_estimate_s"], "faces": tile["faces"],
                        "run": path})
    return out


MODELS = {
    "a + b w + c v": lambda s: [1.0, s["w"], s["v"]],
    "a + b w": lambda s: [1.0, s["w"]],
    "a + c v": lambda s: [1.0, s["v"]],
    "a + d w v": lambda s: [1.0, s["w"] * s["v"] / 100.0],
}


def main():
    tiles = samples(sys.argv[1:])
    total = sum(s["cpu"] for s in tiles)
    print("%d tiles, %.1f CPU-s in all" % (len(tiles), total))
    for name, feat in MODELS.items():
        coef = solve([feat(s) for s in tiles], [s["cpu"] for s in tiles])
        err = [abs(sum(c * x for c, x in zip(coef, feat(s))) - s["cpu"]) for s in tiles]
        print("%-16s coefficients %s; |error| summed %.1f s (%.0f %% of the CPU), largest %.1f s" % (
            name, ", ".join("%.4g" % c for c in coef), sum(err), 100 * sum(err) / total, max(err)))
    # The estimate the run used, scaled to the CPU (only its proportions matter to the split).
    scale = total / sum(s["used"] for s in tiles)
    err = [abs(s["used"] * scale - s["cpu"]) for s in tiles]
    print("%-16s scaled by %.3g; |error| summed %.1f s (%.0f %% of the CPU), largest %.1f s" % (
        "used by the run", scale, sum(err), 100 * sum(err) / total, max(err)))
    print("| tile | CPU (s) | weighted frames | views | faces | estimate used (scaled, s) |")
    print("|---|---|---|---|---|---|")
    for s in sorted(tiles, key=lambda s: -s["cpu"]):
        print("| %s | %.1f | %.1f | %d | %d | %.1f |" % (s["name"], s["cpu"], s["w"], s["v"], s["faces"],
                                                       s["used"] * scale))


if __name__ == "__main__":
    main()
