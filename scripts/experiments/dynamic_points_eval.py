#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Moving-point recall and precision of a run's dynamic_points.ply (issue 33).

Usage: dynamic_points_eval.py SEQ RUN
  SEQ  a simulated sequence with labels/NNNNNN.label (vdbmap-sim street --traffic N)
  RUN  a vdbmap run folder with dynamic_points.ply and report.json
A point is moving when its label's class (lower 16 bits) is a SemanticKITTI moving class,
252..259. Recall = removed moving / moving points of the frames the run tested (those within
the dataset's range filter: report.json points_in counts them); precision = removed moving /
removed. Prints one JSON line, with the recall per instance id (the label's upper 16 bits)
and per frame.
"""
import array
import json
import os
import struct
import sys


def read_removed(path):
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode()
    assert "property float x\nproperty float y\nproperty float z\nproperty uint frame\nproperty uint index\n" in header, header
    n = (len(data) - end) // 20
    out = {}
    for k in range(n):
        frame, index = struct.unpack_from("<II", data, end + 20 * k + 12)
        out.setdefault(frame, []).append(index)
    return out, n


def main():
    seq, run = sys.argv[1], sys.argv[2]
    report = json.load(open(os.path.join(run, "report.json")))
    dyn = report["stages"]["integrate.atsdf"]["dynamic_removal"]
    removed, n_removed = read_removed(os.path.join(run, "dynamic_points.ply"))
    labels_dir = os.path.join(seq, "labels")
    scans_dir = os.path.join(seq, "velodyne")
    moving = removed_moving = 0
    by_instance = {}  # instance id (upper 16 bits) -> [moving, removed]
    by_frame = {}
    min_r2 = report["config"]["dataset"].get("min_range_m", 1.0) ** 2
    max_r2 = report["config"]["dataset"].get("max_range_m", 200.0) ** 2
    for name in sorted(os.listdir(labels_dir)):
        frame = int(name.split(".")[0])
        lab = array.array("I")
        lab.frombytes(open(os.path.join(labels_dir, name), "rb").read())
        pts = array.array("f")
        pts.frombytes(open(os.path.join(scans_dir, name.replace(".label", ".bin")), "rb").read())
        rem = set(removed.get(frame, []))
        for i, v in enumerate(lab):
            if 252 <= (v & 0xFFFF) <= 259:
                x, y, z = pts[4 * i], pts[4 * i + 1], pts[4 * i + 2]
                r2 = x * x + y * y + z * z
                if r2 < min_r2 or r2 > max_r2:
                    continue
                moving += 1
                hit = i in rem
                removed_moving += hit
                inst = by_instance.setdefault(v >> 16, [0, 0])
                inst[0] += 1
                inst[1] += hit
                fr = by_frame.setdefault(frame, [0, 0])
                fr[0] += 1
                fr[1] += hit
    out = {
        "moving_points": moving,
        "removed": n_removed,
        "removed_moving": removed_moving,
        "recall": removed_moving / moving if moving else None,
        "precision": removed_moving / n_removed if n_removed else None,
        "points_in": dyn.get("points_in"),
        "removal_s": dyn.get("seconds"),
        "integrate_s": report["stages"]["integrate.atsdf"].get("seconds"),
        "static_removed": n_removed - removed_moving,
        "recall_by_instance": {str(k): round(v[1] / v[0], 3) for k, v in sorted(by_instance.items())},
        "recall_by_frame": [round(by_frame[f][1] / by_frame[f][0], 3) for f in sorted(by_frame)],
    }
    print(json.dumps(out))


if __name__ == "__main__":
    main()
