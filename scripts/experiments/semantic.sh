#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Semantic experiment (paper Sec. 6, issue #6): naive voting vs the MRF at 5, 10 and 15 cm on
# the simulated street with boundary label noise, seen (a) by the forward KITTI camera and
# (b) by the surround rig. Writes the sequences the configs expect (data/sim/street_noise,
# data/sim/street_rig_noise) if they are missing, runs config/semantic_{,rig_}{naive,mrf}_*cm,
# scores each with `vdbmap eval` and prints the Markdown tables of docs/results/semantic.md.
# Usage: scripts/experiments/semantic.sh      env: BUILD, THREADS=2, RUNS="..." (config names)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BIN=${BUILD:-$ROOT/build}/bin
THREADS=${THREADS:-2}
cd "$ROOT"
if [ ! -f data/sim/street_noise/gt/mesh.ply ]; then
    "$BIN/vdbmap-sim" street --label-noise 3 --seed 1 -o data/sim/street_noise --quiet
fi
if [ ! -f data/sim/street_rig_noise/dataset.yaml ]; then
    "$BIN/vdbmap-sim" street --rig surround --label-noise 3 --seed 1 -o data/sim/street_rig_noise \
        --quiet
fi
RUNS=${RUNS:-"semantic_naive_5cm semantic_mrf_5cm semantic_naive_10cm semantic_mrf_10cm
semantic_naive_15cm semantic_mrf_15cm semantic_rig_naive_5cm semantic_rig_mrf_5cm
semantic_rig_naive_10cm semantic_rig_mrf_10cm semantic_rig_naive_15cm semantic_rig_mrf_15cm"}
ARGS=()
for name in $RUNS; do
    case $name in
        semantic_rig_*) seq=data/sim/street_rig_noise ;;
        *) seq=data/sim/street_noise ;;
    esac
    "$BIN/vdbmap" run "config/$name.yaml" --threads "$THREADS" --quiet
    "$BIN/vdbmap" eval --gt "$seq/gt" --run "out/$name" --json "out/$name/eval.json" --quiet
    ARGS+=("$name=out/$name")
done
python3 scripts/experiments/semantic_table.py "${ARGS[@]}"
