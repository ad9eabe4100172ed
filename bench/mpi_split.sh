#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Issue 37's MPI split model (docs/benchmarks/scale.md): a simulated street, one process and
# `mpirun -np N vdbmap-mpi run --threads 1` for each N, then per rank from report.json its CPU
# time, frames and points integrated; the predicted speed-up is one process's CPU time over the
# largest rank's, the efficiency that over N, and "sum / one" the ranks' CPU over one process's.
#
#   bench/mpi_split.sh [BUILD [WORK [SIZE_M [RANKS...]]]]   (defaults: build out/bench_mpi 200 2 4 8)
#   PIPELINE=config/street_tiled.yaml (the default; any tiled pipeline)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=$(realpath "${1:-$root/build}")
WORK=$(realpath -m "${2:-$root/out/bench_mpi}")
SIZE=${3:-200}
shift $(( $# < 3 ? $# : 3 ))
RANKS=("$@")
[ ${#RANKS[@]} -gt 0 ] || RANKS=(2 4 8)
PIPELINE=${PIPELINE:-$root/config/street_tiled.yaml}
mkdir -p "$WORK"
seq=$WORK/street$SIZE
[ -f "$seq/gt/sim.json" ] || "$BUILD/bin/vdbmap-sim" street --size "$SIZE" --frames "$SIZE" --seed 4 -o "$seq" --quiet
S=(--set "dataset.path=$seq" --quiet --threads 1)
"$BUILD/bin/vdbmap" run "$PIPELINE" "${S[@]}" -o "$WORK/np1"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
for n in "${RANKS[@]}"; do
    mpirun --oversubscribe --bind-to none -np "$n" "$BUILD/bin/vdbmap-mpi" run "$PIPELINE" "${S[@]}" -o "$WORK/np$n"
done
python3 "$root/bench/mpi_split_table.py" "$WORK" 1 "${RANKS[@]}"
