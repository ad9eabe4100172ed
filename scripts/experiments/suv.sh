#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Paper Sec. 6.1 (LGSVL SUV): a vehicle circles an SUV at 10 m, 5 m/s, 10 Hz, VLS-128 LiDAR
# 2.3 m above the ground, 1 cm range noise; voxel 2.5 cm; truncation fixed 10 cm, fixed 30 cm,
# adaptive [10, 30] cm: config/experiments/suv.yaml, varied with --set for the fixed rows.
# Prints a Markdown table (docs/results/geometry.md).
# Usage: scripts/experiments/suv.sh   (env: BUILD=build dir, OUT=output root, FRAMES=126)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BIN=${BUILD:-$ROOT/build}/bin
OUT=${OUT:-$ROOT/out}
FRAMES=${FRAMES:-126}
SEQ=$OUT/sim/suv
if [ ! -f "$SEQ/gt/mesh.ply" ]; then
    "$BIN/vdbmap-sim" suv -o "$SEQ" --frames "$FRAMES" --seed 1 --no-images --quiet
fi
CONFIG=$ROOT/config/experiments/suv.yaml
# The fixed baselines: the base file's adaptive-only settings back at their defaults.
FIXED=(--set integrate.atsdf.truncation_mode=fixed --set integrate.atsdf.truncation_max_voxels=8
       --set integrate.atsdf.truncation_max_along_ray_m=0 --set integrate.atsdf.falloff_voxels=1)
ROWS=()
SUV_ROWS=()
for cfg in suv_fixed_10cm suv_fixed_30cm suv_adaptive; do
    case $cfg in
        suv_fixed_10cm) extra=("${FIXED[@]}" --set integrate.atsdf.truncation_max_m=0.10) ;;
        suv_fixed_30cm) extra=("${FIXED[@]}" --set integrate.atsdf.truncation_max_m=0.30) ;;
        suv_adaptive) extra=() ;;
    esac
    start=$(date +%s.%N)
    "$BIN/vdbmap" run "$CONFIG" -o "$OUT/$cfg" --set dataset.path="$SEQ" "${extra[@]}" --quiet
    seconds=$(echo "$(date +%s.%N) - $start" | bc)
    "$BIN/vdbmap" eval --gt "$SEQ/gt" --run "$OUT/$cfg" --tau 0.02,0.05,0.1 --cutoff 0.3 \
        --sample-spacing 0.01 --json "$OUT/$cfg/eval.json" --error-ply "$OUT/$cfg/error.ply" --quiet
    # The SUV alone (class 13): samples and observed points nearest to an SUV face.
    "$BIN/vdbmap" eval --gt "$SEQ/gt" --run "$OUT/$cfg" --tau 0.02,0.05,0.1 --cutoff 0.3 \
        --sample-spacing 0.01 --classes 13 --json "$OUT/$cfg/eval_suv.json" --quiet
    ROWS+=("$cfg=$OUT/$cfg/eval.json:$(printf %.1f "$seconds")")
    SUV_ROWS+=("$cfg=$OUT/$cfg/eval_suv.json:$(printf %.1f "$seconds")")
done
echo "Whole scene (SUV + ground plane):"
python3 "$ROOT/scripts/experiments/table.py" "${ROWS[@]}"
echo
echo "SUV only (--classes 13):"
python3 "$ROOT/scripts/experiments/table.py" "${SUV_ROWS[@]}"
