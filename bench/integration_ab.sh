#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# A/B of the integrate stage between two builds (docs/benchmarks/integration.md): for each pass,
# range and thread count, `bench_integration --pipeline bench/run_integration.yaml` of build A,
# then of build B (interleaved, so that a slow spell of the machine hits both), each with the
# VDBFusion port and the lean projective baseline in the same process. One JSON line per run on
# stdout.
#
#   [SETS="k=v k=v ..."] bench/integration_ab.sh BUILD_A BUILD_B [SEQUENCE] [PASSES]
#     SEQUENCE  a simulated street (default out/sim/street50:
#               vdbmap-sim street -o out/sim/street50 --frames 50 --seed 1 --no-images)
#     PASSES    default 3
#     SETS      options to compare within each build, one run per option, interleaved (e.g.
#               "integrate.atsdf.merge_points=auto integrate.atsdf.merge_points=none"); with
#               BUILD_A = BUILD_B each build runs once
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
[ $# -ge 2 ] || { echo "usage: $0 BUILD_A BUILD_B [SEQUENCE] [PASSES]" >&2; exit 2; }
a=$1 b=$2 seq=${3:-$root/out/sim/street50} passes=${4:-3}
for exe in "$a/bin/bench_integration" "$b/bin/bench_integration"; do
    [ -x "$exe" ] || { echo "integration_ab.sh: $exe missing" >&2; exit 1; }
done
[ -d "$seq" ] || { echo "integration_ab.sh: sequence $seq missing" >&2; exit 1; }
builds=("$a")
[ "$b" != "$a" ] && builds+=("$b")
read -r -a sets <<< "${SETS:-}"
[ ${#sets[@]} -gt 0 ] || sets=("")
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for ((pass = 1; pass <= passes; ++pass)); do
    for range in "0.4 0.8" "0.1 0.3"; do
        set -- $range
        for threads in 2 1; do
            for build in "${builds[@]}"; do for kv in "${sets[@]}"; do
                extra=()
                [ -n "$kv" ] && extra=(--set "$kv")
                "$build/bin/bench_integration" --pipeline "$root/bench/run_integration.yaml" \
                    --set "dataset.path=$seq" --set dataset.num_frames=30 "${extra[@]}" \
                    --set "integrate.atsdf.truncation_min_m=$1" --set "integrate.atsdf.truncation_max_m=$2" \
                    --threads "$threads" --repeat 5 --out "$out/run" 2>/dev/null | tail -1 |
                    python3 -c "import json, sys
d = json.loads(sys.stdin.read())
print(json.dumps({'build': '$build', 'set': '$kv', 'pass': $pass, 'range': [$1, $2], 'threads': $threads,
                  'ours_s_median': d['integrate_s_median'], 'baseline_s_median': d['baseline_s_median'],
                  'speedup_of_medians': d['speedup_of_medians'],
                  'lean_baseline_s_median': d['lean_baseline_s_median'],
                  'lean_speedup_of_medians': d['lean_speedup_of_medians'],
                  'updates_per_point': d['updates_per_point']}))"
            done; done
        done
    done
done
