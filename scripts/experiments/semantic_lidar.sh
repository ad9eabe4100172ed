#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Issue 14's targets on the simulated forward-camera street at 5 cm (docs/results/semantic.md):
# camera + LiDAR labels, LiDAR only, camera only with the geometric and the uniform fill. Every
# row is config/experiments/semantic_lidar.yaml varied with --set.
# Usage: scripts/experiments/semantic_lidar.sh
#   env: BUILD_DIR, OUT, FRAMES (of the simulated street; the simulator's default when empty)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin=${BUILD_DIR:-$root/build}/bin
out=${OUT:-$root/out}
seq=$out/sim/street_lidar
if [ ! -d "$seq/labels" ]; then
    "$bin/vdbmap-sim" street --label-noise 2 --lidar-label-flip 0.1 --lidar-label-boundary 2 \
        --seed 1 ${FRAMES:+--frames "$FRAMES"} -q -o "$seq"
fi
config=$root/config/experiments/semantic_lidar.yaml
run() {
    local name=$1; shift
    "$bin/vdbmap" run "$config" --set dataset.path="$seq" --threads 2 --quiet -o "$out/$name" "$@"
    "$bin/vdbmap" eval --gt "$seq/gt" --run "$out/$name" --json "$out/$name/eval.json" \
        > "$out/$name/eval.txt"
}
run semantic_camlidar_5cm
run semantic_lidaronly_5cm --set semantic.mrf.image_votes=false
run semantic_camonly_geometric_5cm --set semantic.mrf.lidar_labels=false
run semantic_camonly_uniform_5cm --set semantic.mrf.lidar_labels=false --set semantic.mrf.fill=uniform
run semantic_camlidar_uniform_5cm --set semantic.mrf.fill=uniform
