#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Issue 33's targets on the textured street with and without traffic (docs/results/traffic.md,
# "The targets"): held-out texture PSNR, geometry F@5 cm, ghost area, for the drive with
# `--traffic 4` against the same drive without traffic. config/experiments/texture.yaml (ATSDF,
# marching cubes, texture.mrf with every colour step), moving-object removal as shipped but
# without the simulator's moving labels (the free-space test and the object level alone), then
# with them, then off; then at 0.05 m and in 20 m tiles. One row per run.
# Usage: [SEED=N] [TRAFFIC=N] [ROWS="t0 t4 ..."] scripts/experiments/traffic_texture.sh [BUILD_DIR] [OUT_DIR] [extra --set ...]
#   SEED  the simulator's seed of both drives (default 1; 2 and 3 are drives the defaults were
#         not chosen on); TRAFFIC  the cars of the traffic drive's --traffic (default 4; the
#         rows keep the name t4); ROWS  the rows to run (default: all).
set -euo pipefail
BUILD=${1:-build}
OUT=${2:-out/traffic_texture}
shift $(( $# > 2 ? 2 : $# ))
SIM="$BUILD/bin/vdbmap-sim"
VDBMAP="$BUILD/bin/vdbmap"
CFG=config/experiments/texture.yaml
mkdir -p "$OUT"
SEED=${SEED:-1}
ROWS=${ROWS:-"t0 t4 t4_labels t4_masks t0_hidden t4_off t0_5cm t4_5cm t0_hidden_5cm t0_tiled t4_tiled"}
[ -d "$OUT/sim_t4" ] || "$SIM" street --traffic "${TRAFFIC:-4}" --seed "$SEED" -q -o "$OUT/sim_t4"
[ -d "$OUT/sim_t0" ] || "$SIM" street --seed "$SEED" -q -o "$OUT/sim_t0"
row() {  # name seq extra-args...
    local name=$1 seq=$2; shift 2
    case " $ROWS " in *" $name "*) ;; *) return 0 ;; esac
    "$VDBMAP" run "$CFG" --quiet --set dataset.path="$(realpath "$seq")" "$@" -o "$OUT/$name" > /dev/null
    # Ghosts against the traffic drive's movers (the no-traffic run gives the measure's floor).
    "$VDBMAP" eval --gt "$OUT/sim_t4/gt" --run "$OUT/$name" --json "$OUT/$name/eval_t4.json" --quiet > /dev/null
    "$VDBMAP" eval --gt "$seq/gt" --run "$OUT/$name" --json "$OUT/$name/eval.json" --quiet > /dev/null
    python3 - "$OUT/$name" "$name" <<'PY'
import json, sys
d, name = sys.argv[1], sys.argv[2]
e = json.load(open(d + "/eval.json")); t = json.load(open(d + "/eval_t4.json")).get("traffic", {})
g = e["geometry"]; tx = e.get("texture", {})
f5 = [m["fscore"] for m in g["fscore"] if abs(m["tau_m"] - 0.05) < 1e-9]
r = json.load(open(d + "/report.json"))
s = r["stages"]["integrate.atsdf"]
m = t.get("moving_points") or {}
print(name, "F@5cm", f5[0], "PSNR", tx.get("psnr_db"),
      "coverage", tx.get("coverage"), "ghost_m2", t.get("ghost_area_m2"), "ghost_fraction", t.get("ghost_fraction"),
      "recall", m.get("recall"), "precision", m.get("precision"),
      "integrate_s", s.get("seconds"), "removal_s", s.get("dynamic_removal", {}).get("seconds"))
PY
}
NOLAB="--set integrate.atsdf.dynamic_use_labels=false"
row t0 "$OUT/sim_t0" $NOLAB "$@"
row t4 "$OUT/sim_t4" $NOLAB "$@"
row t4_labels "$OUT/sim_t4" "$@"
# The simulator's masks of the movers in each image (gt/mover_masks): t4_masks textures with
# them (a perfect 2D detector); t0_hidden is the drive without traffic textured without the
# pixels the movers cover in the traffic drive's images: what the images still show.
MASKS="--set texture.mrf.image_masks=$(realpath "$OUT/sim_t4")/gt/mover_masks/image_2"
row t4_masks "$OUT/sim_t4" $NOLAB $MASKS "$@"
row t0_hidden "$OUT/sim_t0" $NOLAB $MASKS "$@"
row t4_off "$OUT/sim_t4" --set integrate.atsdf.dynamic_removal=false "$@"
# 0.05 m voxels, and 20 m tiles (merged into the untiled outputs, which vdbmap eval scores).
FIVE="--set integrate.atsdf.voxel_size_m=0.05"
TILED="--set tiling.tile_size_m=20 --set tiling.halo_m=4 --set tiling.merge=true"
row t0_5cm "$OUT/sim_t0" $NOLAB $FIVE "$@"
row t4_5cm "$OUT/sim_t4" $NOLAB $FIVE "$@"
row t0_hidden_5cm "$OUT/sim_t0" $NOLAB $FIVE $MASKS "$@"
row t0_tiled "$OUT/sim_t0" $NOLAB $TILED "$@"
row t4_tiled "$OUT/sim_t4" $NOLAB $TILED "$@"
