#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Issue 16's speed table (docs/benchmarks/integration.md): the integrate.atsdf stage's wall time
# in `vdbmap run` (scan reading included, report.json), merge_points auto (the default) and none,
# five runs of each case interleaved, at [0.4, 0.8] and [0.1, 0.3] on 2 and 1 threads; then the
# VDBFusion port five times per range (`bench_integration --pipeline`, single-threaded). Prints
# the medians and the ratios to the port's median.
#
#   bench/speed_targets.sh BUILD SEQUENCE [RUNS]
#     SEQUENCE  a simulated street, e.g. vdbmap-sim street -o OUT --frames 50 --seed 7 --no-images
#     RUNS      runs per case, default 5
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
[ $# -ge 2 ] || { echo "usage: $0 BUILD SEQUENCE [RUNS]" >&2; exit 2; }
build=$1 seq=$2 runs=${3:-5}
for exe in vdbmap bench_integration; do
    [ -x "$build/bin/$exe" ] || { echo "speed_targets.sh: $build/bin/$exe missing" >&2; exit 1; }
done
[ -d "$seq" ] || { echo "speed_targets.sh: sequence $seq missing" >&2; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
ranges=("0.4 0.8" "0.1 0.3")
for ((rep = 1; rep <= runs; ++rep)); do
    for range in "${ranges[@]}"; do
        read -r lo hi <<< "$range"
        for threads in 2 1; do
            for merge in auto none; do
                "$build/bin/vdbmap" run "$root/config/experiments/truncation.yaml" -o "$out/run" \
                    --set dataset.path="$seq" --set integrate.atsdf.truncation_min_m="$lo" \
                    --set integrate.atsdf.truncation_max_m="$hi" \
                    --set integrate.atsdf.merge_points="$merge" --threads "$threads" --quiet
                python3 -c "import json,sys; r=json.load(open(sys.argv[1]))['stages']['integrate.atsdf']; print(sys.argv[2], r['wall_time_s'])" \
                    "$out/run/report.json" "run $lo-$hi $threads $merge" >> "$out/times"
            done
        done
    done
done
for range in "${ranges[@]}"; do
    read -r lo hi <<< "$range"
    "$build/bin/bench_integration" --pipeline "$root/bench/run_integration.yaml" \
        --set dataset.path="$seq" --set integrate.atsdf.truncation_min_m="$lo" \
        --set integrate.atsdf.truncation_max_m="$hi" --threads 2 --repeat "$runs" --out "$out/bench" \
        2>/dev/null | tail -1 |
        python3 -c "import json,sys; print('port', sys.argv[1], json.loads(sys.stdin.read())['baseline_s_median'])" "$lo-$hi" >> "$out/times"
done
python3 - "$out/times" <<'PY'
import statistics, sys
runs, port = {}, {}
for line in open(sys.argv[1]):
    f = line.split()
    if f[0] == "port":
        port[f[1]] = float(f[2])
    else:
        runs.setdefault((f[1], int(f[2]), f[3]), []).append(float(f[4]))
print("| range | threads | merge_points | vdbmap run median [s] | VDBFusion port median [s] | ratio |")
print("|---|---|---|---|---|---|")
for (rng, threads, merge), times in runs.items():
    m = statistics.median(times)
    print(f"| [{rng.replace('-', ', ')}] | {threads} | {merge} | {m:.3f} | {port[rng]:.3f} | {port[rng] / m:.2f}x |")
PY
