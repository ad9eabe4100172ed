#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Runs bench_integration over modes, thread counts and voxel sizes; prints one JSON line per run.
# Usage: bench/run_integration_bench.sh <build-dir> [scans] [repeats]
set -euo pipefail
BUILD=${1:?build dir}
SCANS=${2:-100}
REPEATS=${3:-3}
CACHE=${TMPDIR:-/tmp}/vdbmap_bench_street_${SCANS}.bin
BIN="$BUILD/bin/bench_integration"
for voxel in 0.10 0.05 0.20; do
  for mode in adaptive fixed; do
    for threads in 1 2; do
      for ((r = 0; r < REPEATS; ++r)); do
        "$BIN" --scans "$SCANS" --threads "$threads" --voxel "$voxel" --mode "$mode" \
               --eps-min 0.10 --eps-max 0.30 --cache "$CACHE"
      done
    done
  done
done
