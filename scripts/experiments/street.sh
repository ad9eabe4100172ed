#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Street experiment: the simulated street (HDL-64E, 40 frames over 80 m) reconstructed at voxel
# 5, 10, 15 and 20 cm with adaptive truncation [40, 80] cm, and the same voxel sizes with a
# fixed truncation of 40 cm (= eps_min) and 80 cm (= eps_max) as baselines: every row is
# config/experiments/street.yaml varied with --set. Prints a Markdown table
# (docs/results/geometry.md).
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
CONFIG=$ROOT/config/experiments/street.yaml
ROWS=()
for mode in $MODES; do
    case $mode in  # the adaptive base file, or the fixed baseline at eps_min / eps_max
        adaptive) extra=() ;;
        fixed) extra=(--set integrate.atsdf.truncation_mode=fixed --set integrate.atsdf.truncation_min_m=0
                      --set integrate.atsdf.truncation_max_m=0.4) ;;
        fixed80) extra=(--set integrate.atsdf.truncation_mode=fixed --set integrate.atsdf.truncation_min_m=0
                        --set integrate.atsdf.truncation_max_m=0.8) ;;
        *) echo "street.sh: MODES are adaptive, fixed, fixed80; got '$mode'" >&2; exit 2 ;;
    esac
    for voxel in $VOXELS; do
        name=street_${mode}_$(printf %.0f "$(echo "$voxel * 100" | bc)")cm
        start=$(date +%s.%N)
        "$BIN/vdbmap" run "$CONFIG" -o "$OUT/$name" \
            --set dataset.path="$SEQ" --set integrate.atsdf.voxel_size_m="$voxel" "${extra[@]}" --quiet
        seconds=$(echo "$(date +%s.%N) - $start" | bc)
        "$BIN/vdbmap" eval --gt "$SEQ/gt" --run "$OUT/$name" --tau 0.05,0.1,0.2 \
            --json "$OUT/$name/eval.json" --quiet
        ROWS+=("$name=$OUT/$name/eval.json:$(printf %.1f "$seconds")")
    done
done
python3 "$ROOT/scripts/experiments/table.py" "${ROWS[@]}"
