#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# ctest tiles3d_gltf_validator (LABEL tiles3d; needs node and the npm registry once): installs
# gltf-validator with `npm ci` from the committed package-lock.json into BUILD/tiles3d_validator,
# makes a small simulated street, runs export.3dtiles tiled (meshopt, JPEG), tiled (compression
# none, JPEG: the validator does not decode EXT_meshopt_compression, so this is where it checks
# the parents' vertex data) and untiled (none, PNG), and validates every GLB: 0 errors; the
# warnings are listed.
set -euo pipefail
build=$1
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
work=$build/test_scratch/tiles3d_validator
tools=$build/tiles3d_validator
mkdir -p "$tools" "$work"
if [ ! -f "$tools/node_modules/gltf-validator/package.json" ] ||
   ! cmp -s "$here/package-lock.json" "$tools/package-lock.json"; then
    cp "$here/package.json" "$here/package-lock.json" "$tools/"
    (cd "$tools" && npm ci --no-audit --no-fund --silent)
fi
seq=$work/seq
[ -f "$seq/poses.txt" ] || "$build/bin/vdbmap-sim" street --frames 6 --seed 1 -o "$seq" > /dev/null
for mode in tiled tiledplain untiled; do
    cfg=$work/$mode.yaml
    {
        echo "dataset: {format: kitti, path: $seq, max_range_m: 12}"
        echo "plugins: [texture, semantic, tiles3d]"
        echo "stages:"
        echo "  - {stage: integrate.atsdf, voxel_size_m: 0.2}"
        echo "  - {stage: mesh.marching_cubes}"
        echo "  - {stage: texture.mrf, max_view_angle_deg: 85}"
        echo "  - {stage: semantic.mrf, max_view_angle_deg: 88, lidar_labels: true, label_map: semantickitti}"
        if [ "$mode" != untiled ]; then
            if [ "$mode" = tiled ]; then
                echo "  - {stage: export.3dtiles}"
            else
                echo "  - {stage: export.3dtiles, compression: none}"
            fi
            echo "tiling: {tile_size_m: 8, halo_m: 1, occluder_margin_m: 3, max_view_distance_m: 20}"
        else
            echo "  - {stage: export.3dtiles, compression: none, image_format: png}"
        fi
    } > "$cfg"
    rm -rf "$work/$mode"
    "$build/bin/vdbmap" run "$cfg" -o "$work/$mode" --quiet
done
node "$here/validate.mjs" "$tools/node_modules" "$work/tiled" "$work/tiledplain" "$work/untiled"
