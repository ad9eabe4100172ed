#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Moving-object removal on simulated streets with traffic (issue 33, docs/results/traffic.md):
# recall / precision of the removed points (the free-space test alone: the simulator's labels
# would give 1.0), and the cost against integration (median of 3 runs, removal on and off).
# Usage: scripts/experiments/traffic_dynamic.sh [BUILD_DIR] [OUT_DIR]
set -euo pipefail
BUILD=${1:-build}
OUT=${2:-out/traffic_dynamic}
SIM="$BUILD/bin/vdbmap-sim"
VDBMAP="$BUILD/bin/vdbmap"
CFG=config/experiments/traffic_dynamic.yaml
EVAL=scripts/experiments/dynamic_points_eval.py
mkdir -p "$OUT"
[ -d "$OUT/sim_t4" ] || "$SIM" street --traffic 4 --no-images --seed 1 -q -o "$OUT/sim_t4"
[ -d "$OUT/sim_t4_40" ] || "$SIM" street --traffic 4 --no-images --seed 1 --frames 40 -q -o "$OUT/sim_t4_40"
[ -d "$OUT/sim_t0" ] || "$SIM" street --no-images --seed 1 -q -o "$OUT/sim_t0"
row() {  # name seq extra-args...
    local name=$1 seq=$2; shift 2
    "$VDBMAP" run "$CFG" --quiet --set dataset.path="$(realpath "$seq")" \
        --set integrate.atsdf.dynamic_use_labels=false "$@" -o "$OUT/$name" > /dev/null
    echo "$name $(python3 "$EVAL" "$seq" "$OUT/$name")"
}
row t4_10cm "$OUT/sim_t4"
row t4_10cm_tiled "$OUT/sim_t4" --set tiling.tile_size_m=25.6
row t4_5cm "$OUT/sim_t4" --set integrate.atsdf.voxel_size_m=0.05
row t4_40f_10cm "$OUT/sim_t4_40"
row t0_10cm "$OUT/sim_t0"
cmp "$OUT/t4_10cm/dynamic_points.ply" "$OUT/t4_10cm_tiled/dynamic_points.ply" && echo "tiled == untiled: identical dynamic_points.ply"
# The per-point test alone, as before the object level (objects off, share radius 0.1 m).
POINTS="--set integrate.atsdf.dynamic_objects=false --set integrate.atsdf.dynamic_share_radius_m=0.1"
row t4_10cm_points "$OUT/sim_t4" $POINTS
row t4_40f_10cm_points "$OUT/sim_t4_40" $POINTS
row t0_10cm_points "$OUT/sim_t0" $POINTS
# Ghost area (vdbmap eval against the traffic sequence's static truth).
for name in t4_10cm t4_5cm t4_10cm_points; do
    "$VDBMAP" eval --gt "$OUT/sim_t4/gt" --run "$OUT/$name" --json "$OUT/$name/eval.json" --quiet > /dev/null
    python3 -c "import json; t=json.load(open('$OUT/$name/eval.json'))['traffic']; print('$name ghost_area_m2', t['ghost_area_m2'], 'ghost_fraction', t['ghost_fraction'])"
done
# Cost: integrate.atsdf seconds with the removal on and off, 3 runs each, 0.10 and 0.05 m.
for vox in 0.1 0.05; do
    for mode in true false; do
        for r in 1 2 3; do
            "$VDBMAP" run "$CFG" --quiet --set dataset.path="$(realpath "$OUT/sim_t4")" \
                --set integrate.atsdf.voxel_size_m=$vox --set integrate.atsdf.dynamic_removal=$mode \
                -o "$OUT/cost" > /dev/null
            python3 -c "import json,sys; s=json.load(open('$OUT/cost/report.json'))['stages']['integrate.atsdf']; d=s['dynamic_removal']; print('cost voxel $vox removal $mode run $r integrate_s', s['seconds'], 'removal_s', d.get('seconds', 0), 'images_s', d.get('range_images_s', 0), 'votes_s', d.get('votes_s', 0))"
        done
    done
done
