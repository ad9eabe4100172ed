#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""The table of bench/mpi_split.sh: per rank CPU, frames and points integrated, from each run's
report.json (WORK/np<N>/report.json); np1 is the single process run."""
import json
import os
import sys


def ranks(report):
    procs = (report.get("distributed") or {}).get("process")
    if procs:
        return procs
    stage = report["stages"]["integrate.atsdf"]
    return [{"cpu_time_s": report["timings"]["cpu_s"],
             "frames_integrated": stage.get("scans"), "integrate_points_integrated": stage["points_integrated"],
             "tiles": len(report.get("tiles", {})),
             "integrate_seconds": stage["seconds"]}]


def main():
    work, counts = sys.argv[1], [int(n) for n in sys.argv[2:]]
    one = None
    print("| ranks | CPU per rank (s) | tiles per rank | frames per rank | points integrated per rank (M) | sum / one | predicted speed-up | efficiency |")
    print("|---|---|---|---|---|---|---|---|")
    for n in counts:
        with open(os.path.join(work, "np%d" % n, "report.json")) as f:
            report = json.load(f)
        procs = ranks(report)
        # A rank's own work, before it waited for the others (MPI busy-polls while waiting).
        cpu = [p.get("own_work_cpu_time_s", p["cpu_time_s"]) for p in procs]
        if one is None:
            one = sum(cpu)
        pts = [(p.get("integrate_points_integrated") or 0) / 1e6 for p in procs]
        print("| %d | %s | %s | %s | %s | %.2f | %.2f | %.2f |" % (
            n, ", ".join("%.0f" % c for c in cpu), ", ".join(str(p.get("tiles")) for p in procs),
            ", ".join(str(p.get("frames_integrated")) for p in procs),
            ", ".join("%.1f" % p for p in pts), sum(cpu) / one, one / max(cpu), one / max(cpu) / n))


if __name__ == "__main__":
    main()
