#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Prints the tables of docs/benchmarks/scale.md from what bench/scale.sh left in WORK: one row
per run (CPU and wall time per metre of drive, peak memory, faces, tiles), the tiled vs untiled
quality, and issue 13's targets, each figure with the command that produced it.

    bench/scale_table.py WORK

CPU time is user + system of /usr/bin/time -v (all ranks of an mpirun); peak memory is
report.json's peak_memory_bytes (VmHWM of the process; for MPI runs the largest rank's).
Repeated runs (<step>_r2, ...) enter as medians."""
import json
import os
import re
import statistics
import sys


def read_time(path):
    """user + sys seconds, wall seconds, max RSS bytes from /usr/bin/time -v output."""
    text = open(path).read()
    user = float(re.search(r"User time \(seconds\): ([\d.]+)", text).group(1))
    system = float(re.search(r"System time \(seconds\): ([\d.]+)", text).group(1))
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): ([\d:.]+)", text).group(1)
    seconds = 0.0
    for part in wall.split(":"):
        seconds = seconds * 60 + float(part)
    return user + system, seconds


def load_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def peak_bytes(report):
    peaks = [report.get("peak_memory_bytes", 0)]
    for p in (report.get("distributed") or {}).get("process", []):
        peaks.append(p.get("peak_memory_bytes", 0))
    return max(peaks)


def runs(work):
    """name -> dict(size, voxel, kind, cpu, wall, peak, faces, tiles, cmd) with medians."""
    out = {}
    pattern = re.compile(r"^(tiled|untiled|mpi1|mpi2)_(\d+)_([\d.]+)$")
    for entry in sorted(os.listdir(work)):
        m = pattern.match(entry)
        if not m or not os.path.isfile(os.path.join(work, entry + ".done")):
            continue
        kind, size, voxel = m.group(1), int(m.group(2)), m.group(3)
        cpus, walls, peaks = [], [], []
        repeat = 1
        name = entry
        while os.path.isfile(os.path.join(work, name + ".done")):
            cpu, wall = read_time(os.path.join(work, name + ".time"))
            report = load_json(os.path.join(work, name, "report.json")) or {}
            cpus.append(cpu)
            walls.append(wall)
            peaks.append(peak_bytes(report))
            repeat += 1
            name = "%s_r%d" % (entry, repeat)
        report = load_json(os.path.join(work, entry, "report.json")) or {}
        tiling = report.get("tiling") or {}
        counts = report.get("counts") or {}
        out[entry] = {
            "kind": kind, "size": size, "voxel": voxel, "repeats": len(cpus),
            "cpu": statistics.median(cpus), "wall": statistics.median(walls),
            "peak": statistics.median(peaks),
            "faces": tiling.get("faces", counts.get("faces", 0)),
            "tiles": tiling.get("tiles", "-"),
            "cmd": open(os.path.join(work, entry + ".cmd")).read().strip(),
        }
    return out


def quality(work, name):
    e = load_json(os.path.join(work, name + ".eval.json"))
    if not e:
        return None
    q = {}
    for f in (e.get("geometry") or {}).get("fscore", []):
        if abs(f["tau_m"] - 0.05) < 1e-9:
            q["f5"] = f["fscore"]
    s = e.get("semantics") or {}
    q["acc_all"] = s.get("overall_accuracy")
    q["acc_seen"] = (s.get("camera_seen") or {}).get("overall_accuracy")
    q["unlabelled"] = s.get("unlabelled_fraction")
    q["psnr"] = (e.get("texture") or {}).get("psnr_db")
    return q


def gib(b):
    return b / 2 ** 30


def verdict(ok):
    return "yes" if ok else "**no**"


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    work = sys.argv[1]
    rs = runs(work)
    print("## Runs (%s)\n" % work)
    print("| run | drive | voxel | faces | tiles | CPU | CPU per metre | wall | wall per metre | peak memory | repeats |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name, r in sorted(rs.items(), key=lambda kv: (kv[1]["kind"], kv[1]["voxel"], kv[1]["size"])):
        print("| %s | %d m | %s m | %s | %s | %.0f s | %.3f s/m | %.0f s | %.3f s/m | %.2f GiB | %d |" % (
            name, r["size"], r["voxel"], r["faces"], r["tiles"], r["cpu"], r["cpu"] / r["size"],
            r["wall"], r["wall"] / r["size"], gib(r["peak"]), r["repeats"]))
    print("\nCommands:\n")
    for name, r in sorted(rs.items()):
        print("- `%s`: `%s`" % (name, r["cmd"]))

    print("\n## Tiled vs untiled quality\n")
    print("| drive | voxel | F@5cm untiled / tiled | sem. accuracy all faces | camera-seen | PSNR (dB) |")
    print("|---|---|---|---|---|---|")
    deltas = []
    for name, r in sorted(rs.items()):
        if r["kind"] != "untiled":
            continue
        tiled = "tiled_%d_%s" % (r["size"], r["voxel"])
        qu, qt = quality(work, name), quality(work, tiled)
        if not qu or not qt:
            continue

        def pair(key, fmt):
            a, b = qu.get(key), qt.get(key)
            if a is None or b is None:
                return "-"
            return (fmt + " / " + fmt + " (%+.4f)") % (a, b, b - a)
        print("| %d m | %s m | %s | %s | %s | %s |" % (
            r["size"], r["voxel"], pair("f5", "%.4f"), pair("acc_all", "%.4f"),
            pair("acc_seen", "%.4f"), pair("psnr", "%.2f")))
        deltas.append((r["size"], r["voxel"], qu, qt))

    print("\n## Targets (issue 13)\n")
    print("| target | measured | met? |")
    print("|---|---|---|")
    for voxel in sorted({r["voxel"] for r in rs.values()}):
        t = {r["size"]: r for r in rs.values() if r["kind"] == "tiled" and r["voxel"] == voxel}
        if 100 in t and 1600 in t:
            for what in ("cpu", "wall"):
                ratio = (t[1600][what] / 1600) / (t[100][what] / 100)
                print("| %s time per metre at 1600 m <= 1.2 x at 100 m (%s m) | %.3f / %.3f s/m = %.2f | %s |" % (
                    "CPU" if what == "cpu" else "wall", voxel, t[1600][what] / 1600,
                    t[100][what] / 100, ratio, verdict(ratio <= 1.2)))
        if 400 in t and 1600 in t:
            ratio = t[1600]["peak"] / t[400]["peak"]
            print("| peak memory at 1600 m <= 1.3 x at 400 m (%s m) | %.2f / %.2f GiB = %.2f | %s |" % (
                voxel, gib(t[1600]["peak"]), gib(t[400]["peak"]), ratio, verdict(ratio <= 1.3)))
        if 1600 in t and voxel == "0.10":
            print("| peak memory at 1600 m < 4 GiB (0.10 m) | %.2f GiB | %s |" % (
                gib(t[1600]["peak"]), verdict(t[1600]["peak"] < 4 * 2 ** 30)))
    m1 = [r for r in rs.values() if r["kind"] == "mpi1"]
    m2 = [r for r in rs.values() if r["kind"] == "mpi2"]
    if m1 and m2:
        a, b = m1[0], m2[0]
        print("| `mpirun -np 2` >= 1.6 x faster than 1 rank (%d m, wall) | %.0f / %.0f s = %.2f | %s |" % (
            a["size"], a["wall"], b["wall"], a["wall"] / b["wall"], verdict(a["wall"] / b["wall"] >= 1.6)))
        print("| (CPU time of all ranks, 2 vs 1) | %.0f / %.0f s = %.2f | - |" % (
            b["cpu"], a["cpu"], b["cpu"] / a["cpu"]))
    for size, voxel, qu, qt in deltas:
        checks = [("PSNR within 0.3 dB", "psnr", 0.3), ("semantic accuracy (all faces) within 0.005", "acc_all", 0.005),
                  ("semantic accuracy (camera-seen) within 0.005", "acc_seen", 0.005),
                  ("F@5cm within 0.002", "f5", 0.002)]
        for label, key, tol in checks:
            if qu.get(key) is None or qt.get(key) is None:
                continue
            d = qt[key] - qu[key]
            print("| tiled vs untiled %s (%d m, %s m) | %+.4f | %s |" % (
                label, size, voxel, d, verdict(abs(d) <= tol)))


if __name__ == "__main__":
    main()
