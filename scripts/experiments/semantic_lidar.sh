#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Issue 14's targets on the simulated forward-camera street at 5 cm (docs/results/semantic.md):
# camera + LiDAR labels, LiDAR only, camera only with the geometric and the uniform fill.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
cd "$root"
bin=${BUILD_DIR:-$root/build}/bin
seq=data/sim/street_lidar
if [ ! -d "$seq/labels" ]; then
    "$bin/vdbmap-sim" street --label-noise 2 --lidar-label-flip 0.1 --lidar-label-boundary 2 \
        --seed 1 -q -o "$seq"
fi
config=config/street_camera_lidar_semantic.yaml
run() {
    local name=$1; shift
    "$bin/vdbmap" run "$config" --threads 2 --quiet -o "out/$name" "$@"
    "$bin/vdbmap" eval --gt "$seq/gt" --run "out/$name" --json "out/$name/eval.json" \
        > "out/$name/eval.txt"
}
run semantic_camlidar_5cm
run semantic_lidaronly_5cm --set semantic.mrf.image_votes=false
run semantic_camonly_geometric_5cm --set semantic.mrf.lidar_labels=false
run semantic_camonly_uniform_5cm --set semantic.mrf.lidar_labels=false --set semantic.mrf.fill=uniform
run semantic_camlidar_uniform_5cm --set semantic.mrf.fill=uniform
