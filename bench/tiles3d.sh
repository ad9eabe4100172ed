#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Figures of docs/benchmarks/tiles3d.md: the demo (config/demo_street.yaml on
# `vdbmap-sim street --frames 20 --seed 1`) untiled with JPEG and with PNG atlases, and with
# 16 m tiles; for each: bytes of the 3D Tiles output against today's PLY + OBJ + MTL + PNG,
# bytes per face, the writer's share of the run time, faces and geometricError per level.
# Usage: bench/tiles3d.sh [BUILD_DIR] [WORK_DIR] [RUN...]   (RUN: jpeg png tiled16; default all)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${1:-$root/build}
work=${2:-$root/out/bench_tiles3d}
mkdir -p "$work"
seq=$work/seq
[ -f "$seq/poses.txt" ] || "$build/bin/vdbmap-sim" street --frames 20 --seed 1 -o "$seq" > /dev/null
cfg=$root/config/demo_street.yaml
tiled_cfg=$work/demo_tiled16.yaml
{ cat "$cfg"; echo "tiling: {tile_size_m: 16}"; } > "$tiled_cfg"
run() {  # name config extra-args...
    local name=$1 config=$2
    shift 2
    rm -rf "$work/$name"
    "$build/bin/vdbmap" run "$config" -o "$work/$name" --quiet --set dataset.path="$seq" "$@"
}
runs=("${@:3}")
[ ${#runs[@]} -gt 0 ] || runs=(jpeg png tiled16)
for r in "${runs[@]}"; do
    case $r in
        jpeg) run jpeg "$cfg" ;;
        png) run png "$cfg" --set export.3dtiles.image_format=png ;;
        tiled16) run tiled16 "$tiled_cfg" ;;
        *) echo "unknown run '$r' (jpeg, png, tiled16)" >&2; exit 2 ;;
    esac
done
python3 "$root/bench/tiles3d_table.py" "${runs[@]/#/$work/}"
