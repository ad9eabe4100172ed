#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""The table of bench/mpi_balance.sh: for each run WORK/<name>/report.json, per rank CPU time
(its own work, before it waited for the others), the tiles and pieces it wrote and the frames it
integrated; the predicted speed-up is the first run's CPU time (one process, whole tiles) over
the largest rank's, the efficiency that over the ranks; "sum / one" the ranks' CPU over it."""
import json
import os
import sys


def ranks(report):
    procs = (report.get("distributed") or {}).get("process")
    if procs:
        return procs
    stage = report["stages"]["integrate.atsdf"]
    return [{"cpu_time_s": report["timings"]["cpu_s"], "frames_integrated": stage.get("scans"),
             "tiles": len(report.get("tiles", {}))}]


def main():
    work, names = sys.argv[1], sys.argv[2:]
    one = None
    print("| run | ranks | units planned (pieces) | CPU per rank (s) | tiles written per rank | frames per rank | sum / one | predicted speed-up | efficiency |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name in names:
        with open(os.path.join(work, name, "report.json")) as f:
            report = json.load(f)
        procs = ranks(report)
        cpu = [p.get("own_work_cpu_time_s", p["cpu_time_s"]) for p in procs]
        if one is None:
            one = sum(cpu)
        plan = report.get("tiling", {}).get("plan", [])
        pieces = report.get("tiling", {}).get("balance_pieces", 0)
        n = len(procs)
        print("| %s | %d | %d (%d) | %s | %s | %s | %.2f | %.2f | %.2f |" % (
            name, n, len(plan), pieces, ", ".join("%.1f" % c for c in cpu),
            ", ".join(str(p.get("tiles")) for p in procs),
            ", ".join(str(p.get("frames_integrated")) for p in procs),
            sum(cpu) / one, one / max(cpu), one / max(cpu) / n))


if __name__ == "__main__":
    main()
