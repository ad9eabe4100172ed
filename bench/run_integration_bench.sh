#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Runs bench_integration over voxel sizes, modes and thread counts; prints one JSON line per run
# (bench/integration_table.py turns them into the table of docs/benchmarks/integration.md).
# Usage: bench/run_integration_bench.sh <build-dir> [scans] [repeats at 0.10 m] [repeats otherwise]
set -euo pipefail
BUILD=${1:?build dir}
SCANS=${2:-100}
REPEATS_010=${3:-5}
REPEATS=${4:-3}
CACHE=${TMPDIR:-/tmp}/vdbmap_bench_street_${SCANS}.bin
BIN="$BUILD/bin/bench_integration"
for voxel in 0.10 0.05 0.20; do
  n=$REPEATS
  [ "$voxel" = 0.10 ] && n=$REPEATS_010
  for ((r = 0; r < n; ++r)); do        # interleaved: a slow spell hits every setting alike
    for mode in adaptive fixed; do
      for threads in 1 2; do
        "$BIN" --scans "$SCANS" --threads "$threads" --voxel "$voxel" --mode "$mode" \
               --eps-min 0.10 --eps-max 0.30 --cache "$CACHE"
      done
    done
  done
done
