#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Truncation modes on the simulated forward-drive street (issue 16): for each voxel size and eps
# range, the adaptive mode (default), the paper's Eq. 4 (truncation_mode: paper), fixed eps at
# eps_min, the middle and eps_max, and the VDBFusion-style baseline (bench/ProjectiveBaseline.h)
# at eps_max, each scored by `vdbmap eval` (F@5/10 cm, accuracy, completeness, road and sidewalk
# recall@10 cm). Prints one line per run (docs/results/geometry.md).
# Usage: scripts/experiments/truncation.sh
#   env: BUILD, OUT, FRAMES=50, RUNS="0.10:0.4:0.8 0.10:0.1:0.3 0.05:0.2:0.4", SCENE=street,
#        TAU=0.05,0.1, CONFIG=config/experiments/truncation.yaml, EVAL_ARGS (e.g. "--cutoff 0.3"),
#        MODES="adaptive paper fixed vdbfusion" (the rows to run),
#        SET (extra --set options of every vdbmap run, e.g.
#        "integrate.atsdf.grazing_band_both_sides=true"; the adaptive row is named after them)
# SUV: SCENE=suv FRAMES=40 RUNS=0.025:0.1:0.3 TAU=0.02,0.05 CONFIG=config/experiments/suv.yaml
#      EVAL_ARGS="--cutoff 0.3 --sample-spacing 0.01" scripts/experiments/truncation.sh
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BIN=${BUILD:-$ROOT/build}/bin
OUT=${OUT:-$ROOT/out}
FRAMES=${FRAMES:-50}
SCENE=${SCENE:-street}
RUNS=${RUNS:-"0.10:0.4:0.8 0.10:0.1:0.3 0.05:0.2:0.4"}
TAU=${TAU:-0.05,0.1}
CONFIG=${CONFIG:-$ROOT/config/experiments/truncation.yaml}
EVAL_ARGS=${EVAL_ARGS:-}
MODES=${MODES:-"adaptive paper fixed vdbfusion"}
SET=${SET:-}
extra=()
for kv in $SET; do extra+=(--set "$kv"); done
wants() { [[ " $MODES " == *" $1 "* ]]; }
suffix=${SET:+_$(echo "$SET" | tr ' =/' '___')}  # of the run folders made with SET
SEQ=$OUT/sim/${SCENE}${FRAMES}
if [ ! -f "$SEQ/gt/mesh.ply" ]; then
    nice -n 10 "$BIN/vdbmap-sim" "$SCENE" -o "$SEQ" --frames "$FRAMES" --seed 1 --no-images --quiet
fi
row() {  # name dir
    python3 - "$1" "$2" "$TAU" <<'PY'
import json, sys
name, d, tau = sys.argv[1], sys.argv[2], [float(t) for t in sys.argv[3].split(',')]
e = json.load(open(d + '/eval.json'))['geometry']
f = {round(x['tau_m'], 4): x for x in e['fscore']}
def recall(cls, t):
    for c in e['per_class']:
        if c['name'] == cls:
            return [r['recall'] for r in c['recall'] if abs(r['tau_m'] - t) < 1e-9][0]
    return float('nan')
try:
    st = json.load(open(d + '/report.json'))['stages']['integrate.atsdf']
    upd = '%.1f' % st['updates_per_point']
except (OSError, KeyError):
    upd = '-'
t1 = max(tau)
cells = [name] + ['%.4f' % f[round(t, 4)]['fscore'] for t in tau] + \
        ['%.3f' % f[round(t1, 4)]['recall'], '%.1f' % (1000 * e['accuracy']['mean_m']),
         '%.1f' % (1000 * e['completeness']['mean_m']), '%.3f' % recall('road', t1),
         '%.3f' % recall('sidewalk', t1), upd]
print('| ' + ' | '.join(cells) + ' |', flush=True)
PY
}
evaluate() {  # name dir
    nice -n 10 "$BIN/vdbmap" eval --gt "$SEQ/gt" --run "$2" --tau "$TAU" --json "$2/eval.json" $EVAL_ARGS --quiet
    row "$1" "$2"
}
echo "| run | F@${TAU//,/ | F@} | recall@max τ | acc. mean [mm] | compl. mean [mm] | road recall | sidewalk recall | updates/point |"
echo "|---|$(echo "$TAU" | sed 's/[^,]*/---|/g; s/,//g')---|---|---|---|---|---|"
for spec in $RUNS; do
    IFS=: read -r voxel lo hi <<<"$spec"
    mid=$(python3 -c "print(round(($lo + $hi) / 2, 4))")
    tag="${SCENE}_v${voxel}_${lo}-${hi}"
    for mode in adaptive paper; do
        wants $mode || continue
        dir=$OUT/exp/${tag}_$mode$suffix
        nice -n 10 "$BIN/vdbmap" run "$CONFIG" -o "$dir" --set dataset.path="$SEQ" \
            --set integrate.atsdf.voxel_size_m="$voxel" --set integrate.atsdf.truncation_mode=$mode \
            --set integrate.atsdf.truncation_min_m="$lo" --set integrate.atsdf.truncation_max_m="$hi" \
            "${extra[@]}" --quiet
        evaluate "$mode [$lo, $hi] @ $voxel${SET:+ ($SET)}" "$dir"
    done
    for eps in $lo $mid $hi; do
        wants fixed || break
        dir=$OUT/exp/${tag}_fixed$eps$suffix
        nice -n 10 "$BIN/vdbmap" run "$CONFIG" -o "$dir" --set dataset.path="$SEQ" \
            --set integrate.atsdf.voxel_size_m="$voxel" --set integrate.atsdf.truncation_mode=fixed \
            --set integrate.atsdf.truncation_min_m="$eps" --set integrate.atsdf.truncation_max_m="$eps" \
            "${extra[@]}" --quiet
        evaluate "fixed $eps @ $voxel${SET:+ ($SET)}" "$dir"
    done
    wants vdbfusion || continue
    dir=$OUT/exp/${tag}_vdbfusion
    mkdir -p "$dir"
    nice -n 10 "$BIN/bench_integration" --pipeline "$ROOT/bench/run_integration.yaml" \
        --set dataset.path="$SEQ" --set integrate.atsdf.voxel_size_m="$voxel" \
        --set integrate.atsdf.truncation_max_m="$hi" --set integrate.atsdf.truncation_min_m="$lo" \
        --repeat 1 --threads 1 --out "$dir/bench" --baseline-mesh "$dir/mesh.ply" >/dev/null 2>&1
    evaluate "VDBFusion-style $hi @ $voxel" "$dir"
done
