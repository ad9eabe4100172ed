#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Markdown tables of semantic runs: semantic_table.py NAME=OUTDIR ... (OUTDIR holds the run's
report.json and the `vdbmap eval --json` file eval.json)."""
import json
import sys

rows = []
for arg in sys.argv[1:]:
    name, out = arg.split("=", 1)
    report = json.load(open(out + "/report.json"))
    ev = json.load(open(out + "/eval.json"))["semantics"]
    rows.append((name, report, ev))

print("| run | faces | accuracy | mean class acc. | mIoU | unlabelled (area) "
      "| seen: accuracy | seen: mean class acc. | seen: mIoU | seen: unlabelled | seen area |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for name, report, ev in rows:
    seen = ev.get("camera_seen") or {}
    print("| %s | %d | %.4f | %.4f | %.4f | %.4f | %s | %s | %s | %s | %s |" % (
        name, report["counts"]["faces"], ev["overall_accuracy"], ev["mean_class_accuracy"],
        ev["miou"], ev["unlabelled_fraction"],
        *("%.4f" % seen[k] if seen else "-" for k in
          ("overall_accuracy", "mean_class_accuracy", "miou", "unlabelled_fraction")),
        "%.1f %%" % (100 * seen["seen_fraction"]) if seen else "-"))

print()
print("| run | unlabelled faces next to a labelled face | area within %s m of a class boundary "
      "| accuracy there | accuracy elsewhere | wrong area near a boundary |"
      % rows[0][2]["boundary"]["band_m"])
print("|---|---|---|---|---|---|")
for name, report, ev in rows:
    b = ev["boundary"]
    print("| %s | %d | %.1f %% | %.4f | %.4f | %.1f %% |" % (
        name, ev["unlabelled_faces_next_to_labelled"], 100 * b["near_area_fraction"],
        b["near_accuracy"], b["inside_accuracy"], 100 * b["wrong_near_fraction"]))

print()
print("| run | views | observed faces | filled by MRF | written 255 | integrate s | mesh s "
      "| visibility s | votes s | MRF s | run total s | peak RSS GB |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")
for name, report, ev in rows:
    s = report["stages"]["semantic.mrf"]
    st = {x["stage"]: x["wall_time_s"] for x in report["timings"]["stages"]}
    print("| %s | %d | %d | %d | %d | %.2f | %.2f | %.2f | %.2f | %.2f | %.1f | %.2f |" % (
        name, s["views"], s["observed_faces"], s["filled_faces"], s["unlabelled_faces"],
        st["integrate.atsdf"], st["mesh.marching_cubes"], s["time_visibility_s"],
        s["time_votes_s"], s["time_mrf_s"], report["timings"]["total_s"],
        report["peak_memory_bytes"] / 1e9))
