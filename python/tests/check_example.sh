#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Usage: check_example.sh BIN_DIR PYTHON SOURCE_DIR
# Runs examples/python/map_kitti.py on a small simulated KITTI odometry download (under Xvfb)
# and checks that its PNG shows a mesh: not blank, with shaded (grey) pixels.
set -euo pipefail
bin_dir=$1
python=$2
source_dir=$3
work=$(mktemp -d "${TMPDIR:-/tmp}/vdbmap_python_example.XXXXXX")
trap 'rm -rf "$work"' EXIT
"$bin_dir/vdbmap-sim" street --layout kitti-odometry --frames 4 --size 30 --gt-views 0 --no-images \
    --quiet -o "$work/sim"
xvfb-run -a "$python" "$source_dir/examples/python/map_kitti.py" \
    "$work/sim/dataset/sequences/00" --frames 4 --png "$work/mesh.png" | tee "$work/log.txt"
grep -q "4 scans" "$work/log.txt"
"$python" - "$work/mesh.png" <<'CHECK'
import sys
import numpy as np
import open3d as o3d
img = np.asarray(o3d.io.read_image(sys.argv[1]))
assert img.shape[0] == 720 and img.shape[1] == 1280, img.shape
grey = img[..., :3].mean(axis=2)
shaded = np.mean((grey > 20) & (grey < 235))
print(f"shaded share {shaded:.3f}")
assert shaded > 0.03, "the PNG shows no mesh"
CHECK
