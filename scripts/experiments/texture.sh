#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Texture ablation (paper Sec. 5, docs/results/texture.md): the simulated street with vignetting,
# exposure changes and occluders, textured with one colour step after the other. Every row is
# config/experiments/texture.yaml (all steps on) varied with --set; each is scored by
# `vdbmap eval` on the held-out views. Prints one Markdown row per run.
# Usage: scripts/experiments/texture.sh
#   env: BUILD, OUT, THREADS=2, ROWS="1 2 3 4 5 6 7", FRAMES (of the simulated street; the
#        simulator's default when empty)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BIN=${BUILD:-$ROOT/build}/bin
OUT=${OUT:-$ROOT/out}
THREADS=${THREADS:-2}
ROWS=${ROWS:-"1 2 3 4 5 6 7"}
SEQ=$OUT/sim/street_occ
if [ ! -f "$SEQ/gt/mesh.ply" ]; then
    "$BIN/vdbmap-sim" street --occluders --seed 1 ${FRAMES:+--frames "$FRAMES"} -o "$SEQ" --quiet
fi
S=texture.mrf
echo "| # | steps | PSNR (dB) | MAE (0-255) | texture.mrf (s) |"
echo "|---|---|---|---|---|"
for row in $ROWS; do
    case $row in
        1) steps="best view only"
           extra=(--set $S.mrf=false --set $S.vignetting=false --set $S.photo_consistency=false
                  --set $S.global_adjustment=false) ;;
        2) steps="+ MRF"
           extra=(--set $S.vignetting=false --set $S.photo_consistency=false
                  --set $S.global_adjustment=false) ;;
        3) steps="+ vignetting correction (given a b c)"
           extra=(--set $S.photo_consistency=false --set $S.global_adjustment=false) ;;
        4) steps="+ photo-consistency"
           extra=(--set $S.global_adjustment=false) ;;
        5) steps="+ global colour adjustment (all on)"
           extra=() ;;
        6) steps="as 5, vignetting estimated"
           extra=(--set $S.estimate_vignetting=true --set "$S.vignetting_params=[]") ;;
        7) steps="as 5, unseen faces grey"
           extra=(--set $S.fill=grey) ;;
        *) echo "texture.sh: ROWS are 1 to 7, got '$row'" >&2; exit 2 ;;
    esac
    dir=$OUT/texture_ablation_$row
    "$BIN/vdbmap" run "$ROOT/config/experiments/texture.yaml" -o "$dir" --set dataset.path="$SEQ" \
        "${extra[@]}" --threads "$THREADS" --quiet
    "$BIN/vdbmap" eval --gt "$SEQ/gt" --run "$dir" --json "$dir/eval.json" --quiet
    python3 - "$row" "$steps" "$dir" <<'PY'
import json, sys
row, steps, d = sys.argv[1:]
t = json.load(open(d + "/eval.json"))["texture"]
r = json.load(open(d + "/report.json"))
wall = r["stages"]["texture.mrf"]["wall_time_s"]
print("| %s | %s | %.3f | %.3f | %.1f |" % (row, steps, t["psnr_db"], t["mae"], wall))
PY
done
