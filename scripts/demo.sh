#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The full pipeline on a built-in scene: build, simulate a small street (skipped when present),
# run config/demo_street.yaml (ATSDF map, mesh, textured mesh, semantic mesh), evaluate against
# the simulator's ground truth, and summarise what was written where.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${BUILD_DIR:-$root/build}
cd "$root"

"$root/scripts/build.sh"

seq_dir=out/sim/demo
run_dir=out/demo/run
if [ -f "$seq_dir/poses.txt" ] && [ -d "$seq_dir/velodyne" ] && [ -d "$seq_dir/labels" ]; then
    echo "demo: reusing the simulated sequence in $seq_dir"
else
    rm -rf "$seq_dir"
    "$build_dir/bin/vdbmap-sim" street --frames 20 --seed 1 -o "$seq_dir"
fi

"$build_dir/bin/vdbmap" run config/demo_street.yaml -o "$run_dir"
eval_status=0
"$build_dir/bin/vdbmap" eval --gt "$seq_dir/gt" --run "$run_dir" || eval_status=$?

echo
echo "== vdbmap demo: outputs =="
find "$run_dir" -maxdepth 2 -type f \( -name '*.vdb' -o -name '*.ply' -o -name '*.obj' \
    -o -name '*.mtl' -o -name '*.png' -o -name '*.json' -o -name '*.glb' \) -printf '%p\t%s bytes\n' | sort
python3 - "$run_dir/report.json" <<'PY' || true
import json, sys
r = json.load(open(sys.argv[1]))
c = r.get("counts", {})
print("frames %s, active voxels %s, mesh %s vertices / %s faces, peak memory %.0f MiB" % (
    c.get("frames"), c.get("active_voxels"), c.get("vertices"), c.get("faces"),
    r.get("peak_memory_bytes", 0) / 2**20))
for t in r.get("timings", {}).get("stages", []):
    print("  %-22s %8.2f s" % (t["stage"], t["wall_time_s"]))
PY
echo "sequence:  $seq_dir   (simulated, ground truth in $seq_dir/gt)"
echo "map:       $run_dir/map.vdb   (vdbmap info $run_dir/map.vdb)"
echo "mesh:      $run_dir/mesh.ply"
echo "textured:  $run_dir/textured/mesh.obj"
echo "semantic:  $run_dir/semantic/mesh.ply and mesh.obj"
echo "report:    $run_dir/report.json"
if [ -f "$run_dir/3dtiles/tileset.json" ]; then
    echo "3D Tiles:  $run_dir/3dtiles/tileset.json   (docs/tiles3d.md, docs/viewer.md)"
    echo "view it:   $build_dir/bin/vdbmap view $run_dir"
fi
if [ "$eval_status" -ne 0 ]; then
    echo "demo: vdbmap eval exited with $eval_status" >&2
    exit "$eval_status"
fi
