#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Prints a Markdown table from `vdbmap eval --json` files: table.py NAME=EVAL.json[:SECONDS] ..."""
import json
import sys

print("| run | faces | acc. mean [cm] | acc. median [cm] | acc. p90 [cm] | acc. max [cm] "
      "| compl. mean [cm] | compl. p90 [cm] | Chamfer-L1 [cm] | F-scores | time [s] |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for arg in sys.argv[1:]:
    name, rest = arg.split("=", 1)
    path, _, seconds = rest.partition(":")
    g = json.load(open(path))["geometry"]
    a, c = g["accuracy"], g["completeness"]
    f = ", ".join("F@%gcm %.3f" % (100 * x["tau_m"], x["fscore"]) for x in g["fscore"])
    print("| %s | %d | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %s | %s |" % (
        name, g["faces"], 100 * a["mean_m"], 100 * a["median_m"], 100 * a["p90_m"],
        100 * a["max_m"], 100 * c["mean_m"], 100 * c["p90_m"], 100 * g["chamfer_l1_m"], f,
        seconds or "-"))
