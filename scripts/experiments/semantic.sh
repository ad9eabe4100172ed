#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Semantic experiment (paper Sec. 6, issue #6): naive voting vs the MRF at 5, 10 and 15 cm on
# the simulated street with boundary label noise, seen (a) by the forward KITTI camera and
# (b) by the surround rig. Writes the two sequences (out/sim/street_noise,
# out/sim/street_rig_noise) if they are missing, runs each row from its base file
# (config/experiments/semantic.yaml, semantic_rig.yaml) varied with --set, scores each with
# `vdbmap eval` and prints the Markdown tables of docs/results/semantic.md.
# A row is named semantic_[rig_]{naive,mrf}_<voxel>cm: naive = lambda 0, mrf = lambda 0.5.
# Usage: scripts/experiments/semantic.sh
#   env: BUILD, OUT, THREADS=2, RUNS="..." (row names), FRAMES (of the simulated street; the
#        simulator's default when empty)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BIN=${BUILD:-$ROOT/build}/bin
OUT=${OUT:-$ROOT/out}
THREADS=${THREADS:-2}
FRAMES=${FRAMES:-}
frames=(${FRAMES:+--frames "$FRAMES"})
SEQ=$OUT/sim/street_noise
SEQ_RIG=$OUT/sim/street_rig_noise
if [ ! -f "$SEQ/gt/mesh.ply" ]; then
    "$BIN/vdbmap-sim" street --label-noise 3 --seed 1 "${frames[@]}" -o "$SEQ" --quiet
fi
if [ ! -f "$SEQ_RIG/dataset.yaml" ]; then
    "$BIN/vdbmap-sim" street --rig surround --label-noise 3 --seed 1 "${frames[@]}" -o "$SEQ_RIG" \
        --quiet
fi
RUNS=${RUNS:-"semantic_naive_5cm semantic_mrf_5cm semantic_naive_10cm semantic_mrf_10cm
semantic_naive_15cm semantic_mrf_15cm semantic_rig_naive_5cm semantic_rig_mrf_5cm
semantic_rig_naive_10cm semantic_rig_mrf_10cm semantic_rig_naive_15cm semantic_rig_mrf_15cm"}
ARGS=()
for name in $RUNS; do
    if [[ ! $name =~ ^semantic_(rig_)?(naive|mrf)_([0-9]+)cm$ ]]; then
        echo "semantic.sh: a run is named semantic_[rig_]{naive,mrf}_<voxel>cm, got '$name'" >&2
        exit 2
    fi
    if [ -n "${BASH_REMATCH[1]}" ]; then
        base=semantic_rig seq=$SEQ_RIG
    else
        base=semantic seq=$SEQ
    fi
    lambda=0.5
    [ "${BASH_REMATCH[2]}" = naive ] && lambda=0
    voxel=$(printf '%.2f' "$(echo "${BASH_REMATCH[3]} / 100" | bc -l)")
    "$BIN/vdbmap" run "$ROOT/config/experiments/$base.yaml" -o "$OUT/$name" \
        --set dataset.path="$seq" --set integrate.atsdf.voxel_size_m="$voxel" \
        --set semantic.mrf.lambda="$lambda" --threads "$THREADS" --quiet
    "$BIN/vdbmap" eval --gt "$seq/gt" --run "$OUT/$name" --json "$OUT/$name/eval.json" --quiet
    ARGS+=("$name=$OUT/$name")
done
python3 "$ROOT/scripts/experiments/semantic_table.py" "${ARGS[@]}"
