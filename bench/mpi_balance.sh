#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Issue 37, ranks that outnumber the tiles (docs/benchmarks/scale.md, "Tiles cut for balance"):
# a simulated street, one process, then N ranks with whole tiles and N ranks with
# `tiling.split_for_processes: N` (the plan cuts the costliest tiles into pieces), and one
# process with the same setting (the cut run's own baseline and its outputs, which the ranks'
# must equal byte for byte). Every process runs --threads 1; the table gives per rank CPU time
# (report.json) and the predicted speed-up (one process's CPU over the largest rank's).
#
#   bench/mpi_balance.sh [BUILD [WORK [SIZE_M [RANKS]]]]   (defaults: build out/bench_balance 200 8)
#   PIPELINE=config/street_tiled.yaml (the default; any tiled pipeline); SEED=4 (the street's)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=$(realpath "${1:-$root/build}")
WORK=$(realpath -m "${2:-$root/out/bench_balance}")
SIZE=${3:-200}
N=${4:-8}
PIPELINE=${PIPELINE:-$root/config/street_tiled.yaml}
mkdir -p "$WORK"
SEED=${SEED:-4}
seq=$WORK/street$SIZE
[ -f "$seq/gt/sim.json" ] || "$BUILD/bin/vdbmap-sim" street --size "$SIZE" --frames "$SIZE" --seed "$SEED" -o "$seq" --quiet
S=(--set "dataset.path=$seq" --quiet --threads 1)
CUT=(--set "tiling.split_for_processes=$N")
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
"$BUILD/bin/vdbmap" run "$PIPELINE" "${S[@]}" -o "$WORK/np1"
"$BUILD/bin/vdbmap" run "$PIPELINE" "${S[@]}" "${CUT[@]}" -o "$WORK/np1_cut"
mpirun --oversubscribe --bind-to none -np "$N" "$BUILD/bin/vdbmap-mpi" run "$PIPELINE" "${S[@]}" -o "$WORK/np${N}"
mpirun --oversubscribe --bind-to none -np "$N" "$BUILD/bin/vdbmap-mpi" run "$PIPELINE" "${S[@]}" "${CUT[@]}" -o "$WORK/np${N}_cut"
python3 "$root/bench/mpi_balance_table.py" "$WORK" np1 np1_cut "np${N}" "np${N}_cut"
# The cut ranks' outputs are the cut single process's, byte for byte.
diff -r "$WORK/np1_cut/tiles" "$WORK/np${N}_cut/tiles" && cmp "$WORK/np1_cut/tiles.json" "$WORK/np${N}_cut/tiles.json" \
    && echo "np${N}_cut: tiles/ and tiles.json are those of np1_cut, byte for byte"
