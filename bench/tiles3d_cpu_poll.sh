#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The CPU time of a running process (utime + stime from /proc/PID/stat, in clock ticks) once
# a second, "epoch_seconds ticks" per line, until it exits: the parents' CPU time of a run
# whose report.json has no finish_run_cpu_s (docs/benchmarks/tiles3d.md, the 1.6 km drive;
# bench/tiles3d_poll_share.py reads it).
# Usage: bench/tiles3d_cpu_poll.sh PID > poll.txt
set -euo pipefail
pid=${1:?usage: bench/tiles3d_cpu_poll.sh PID}
echo "# clock ticks per second: $(getconf CLK_TCK)"
while [ -e "/proc/$pid/stat" ]; do
    echo "$(date -u +%s.%N) $(awk '{print $14 + $15}' "/proc/$pid/stat")"
    sleep 1
done
