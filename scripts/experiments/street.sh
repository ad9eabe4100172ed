#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Street experiment: the simulated street (HDL-64E, 40 frames over 80 m) reconstructed at voxel
# 5, 10, 15 and 20 cm with adaptive truncation [40, 80] cm, and the same voxel sizes with a
# fixed truncation of 40 cm (= eps_min) and 80 cm (= eps_max) as baselines. Prints a Markdown
# table (docs/results/geometry.md).
# Usage: scripts/experiments/street.sh
#   env: BUILD, OUT, FRAMES=40, SIZE=80, VOXELS="0.05 0.1 0.15 0.2",
#        MODES="adaptive fixed fixed80"
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BIN=${BUILD:-$ROOT/build}/bin
OUT=${OUT:-$ROOT/out}
FRAMES=${FRAMES:-40}
SIZE=${SIZE:-80}
VOXELS=${VOXELS:-"0.05 0.1 0.15 0.2"}
MODES=${MODES:-"adaptive fixed fixed80"}
SEQ=$OUT/sim/street
if [ ! -f "$SEQ/gt/mesh.ply" ]; then
    "$BIN/vdbmap-sim" street -o "$SEQ" --frames "$FRAMES" --size "$SIZE" --seed 1 --quiet
fi
ROWS=()
for mode in $MODES; do
    config=street_$mode
    extra=()
    if [ "$mode" = fixed80 ]; then
        config=street_fixed
        extra=(--set stages.0.truncation_max_m=0.8)
    fi
    for voxel in $VOXELS; do
        name=street_${mode}_$(printf %.0f "$(echo "$voxel * 100" | bc)")cm
        start=$(date +%s.%N)
        "$BIN/vdbmap" run "$ROOT/config/$config.yaml" -o "$OUT/$name" \
            --set dataset.path="$SEQ" --set stages.0.voxel_size_m="$voxel" "${extra[@]}" --quiet
        seconds=$(echo "$(date +%s.%N) - $start" | bc)
        "$BIN/vdbmap" eval --gt "$SEQ/gt" --run "$OUT/$name" --tau 0.05,0.1,0.2 \
            --json "$OUT/$name/eval.json" --quiet
        ROWS+=("$name=$OUT/$name/eval.json:$(printf %.1f "$seconds")")
    done
done
python3 "$ROOT/scripts/experiments/table.py" "${ROWS[@]}"
