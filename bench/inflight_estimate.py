#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""A tile's estimated peak (report.json tiles.<name>.memory_estimate_bytes) against its real
one (memory_added_bytes: its window's peak over the RSS before it; only when tiles ran one at a
time, tiling.max_tiles_in_flight=1), with a least-squares refit of estimateTilePeakBytes's
coefficients (fixed, per face, per occluder face, per view).

    bench/inflight_estimate.py RUN/report.json
"""
import json
import sys


def lstsq(a, b):
    """Least squares by the normal equations (no numpy on the machine)."""
    n = len(a[0])
    m = [[sum(r[i] * r[j] for r in a) for j in range(n)] + [sum(r[i] * y for r, y in zip(a, b))]
         for i in range(n)]
    for i in range(n):
        p = max(range(i, n), key=lambda k: abs(m[k][i]))
        m[i], m[p] = m[p], m[i]
        for k in range(n):
            if k != i and m[i][i] != 0:
                f = m[k][i] / m[i][i]
                m[k] = [x - f * y for x, y in zip(m[k], m[i])]
    return [m[i][n] / m[i][i] if m[i][i] else 0.0 for i in range(n)]


r = json.load(open(sys.argv[1]))
rows = []
print("| tile | faces | occluder faces | views | estimate (MiB) | real (MiB) | real / estimate |")
print("|---|---|---|---|---|---|---|")
for name, t in sorted(r["tiles"].items()):
    if "memory_added_bytes" not in t:
        continue
    mc = t["stages"].get("mesh.marching_cubes", {})
    faces = mc.get("faces", 0)
    occ = mc.get("occluder_faces", faces)
    est, real = t["memory_estimate_bytes"], t["memory_added_bytes"]
    rows.append((faces, occ, t["views"], real))
    print(f"| {name} | {faces} | {occ} | {t['views']} | {est / 2**20:.0f} | {real / 2**20:.0f} | {real / est:.2f} |")
if len(rows) >= 4:
    a = [[1.0, f, o, v] for f, o, v, _ in rows]
    b = [float(x[3]) for x in rows]
    coef = lstsq(a, b)
    print("least squares: fixed %.0f MiB, %.0f B/face, %.0f B/occluder face, %.2f MiB/view" %
          (coef[0] / 2**20, coef[1], coef[2], coef[3] / 2**20))
