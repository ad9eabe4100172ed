#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Compares texture.mrf's exposure gains (report.json) with the simulator's (SEQ/exposure.txt).

Usage: exposure_check.py RUN_DIR SEQ_DIR
Only views whose gain was estimated (not kept at 1 for lack of overlap) count; both sets are
normalised to a geometric mean of 1 over them (the gauge of the estimate). One view per frame
(one camera) is assumed, as `vdbmap-sim street` writes it.
"""
import json
import math
import sys

run, seq = sys.argv[1], sys.argv[2]
stage = json.load(open(f"{run}/report.json"))["stages"]["texture.mrf"]
est = stage["exposure_gains"]
truth = [float(l) for l in open(f"{seq}/exposure.txt") if l.strip() and not l.startswith("#")]
if len(est) != len(truth):
    sys.exit(f"{len(est)} estimated gains but {len(truth)} frames (one camera expected)")
used = [v for v in range(len(est)) if est[v] != 1.0]
def norm(g):
    m = sum(math.log(g[v]) for v in used) / len(used)
    return {v: g[v] / math.exp(m) for v in used}
e, t = norm(est), norm(truth)
err = [abs(e[v] / t[v] - 1) for v in used]
print(f"views estimated {len(used)} of {len(est)}; relative gain error max {max(err):.4f} "
      f"mean {sum(err) / len(err):.4f}")
