#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Issue 13's scale measurements (docs/benchmarks/scale.md): simulated straight streets of
# 100 / 400 / 1600 m (vdbmap-sim street --size N --frames N --seed 4), the full pipeline
# (config/street_tiled.yaml: integration, mesh, texture, semantic) tiled and, where it fits,
# untiled, at 0.10 and 0.05 m voxels; vdbmap-mpi with 1 and 2 ranks; tiled vs untiled quality
# (scripts/merge_tiles.py + vdbmap eval); then the issue's target table (bench/scale_table.py).
#
# Resumable: every step writes WORK/<step>.done when it succeeded and is skipped next time;
# each step's command is in WORK/<step>.cmd and its /usr/bin/time -v output in WORK/<step>.time.
# Delete a .done file to redo a step.
#
#   bench/scale.sh [options]
#     --build DIR       build folder (default: build)
#     --work DIR        where sequences, runs and logs go (default: out/bench_scale)
#     --sizes "..."     drive lengths in metres (default: "100 400 1600")
#     --voxels "..."    voxel sizes (default: "0.10 0.05")
#     --untiled "..."   voxel:largest drive run untiled (default: "0.10:400 0.05:100")
#     --mpi SIZE        drive for the 1- and 2-rank vdbmap-mpi runs at 0.10 m (default: 400;
#                       0 = none)
#     --repeats N       timed runs of each tiled / MPI step (default 1; the table shows
#                       medians; repeats after the first keep only report.json and the times)
#     --table           only print the table of what exists
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=$root/build
WORK=$root/out/bench_scale
SIZES="100 400 1600"
VOXELS="0.10 0.05"
UNTILED="0.10:400 0.05:100"
MPI_SIZE=400
REPEATS=1
TABLE_ONLY=0
while [ $# -gt 0 ]; do
    case "$1" in
        --build) BUILD=$(realpath "$2"); shift 2 ;;
        --work) WORK=$(realpath -m "$2"); shift 2 ;;
        --sizes) SIZES=$2; shift 2 ;;
        --voxels) VOXELS=$2; shift 2 ;;
        --untiled) UNTILED=$2; shift 2 ;;
        --mpi) MPI_SIZE=$2; shift 2 ;;
        --repeats) REPEATS=$2; shift 2 ;;
        --table) TABLE_ONLY=1; shift ;;
        *) echo "scale.sh: unknown option '$1' (see the header of $0)" >&2; exit 2 ;;
    esac
done
VDBMAP=$BUILD/bin/vdbmap
SIM=$BUILD/bin/vdbmap-sim
MPI_EXE=$BUILD/bin/vdbmap-mpi
CONFIG=$root/config/street_tiled.yaml
mkdir -p "$WORK"

table() { python3 "$root/bench/scale_table.py" "$WORK"; }
if [ "$TABLE_ONLY" = 1 ]; then table; exit 0; fi
for exe in "$VDBMAP" "$SIM"; do
    [ -x "$exe" ] || { echo "scale.sh: $exe missing: build first (scripts/build.sh)" >&2; exit 1; }
done

# step NAME CMD...: runs CMD under /usr/bin/time -v unless WORK/NAME.done exists.
step() {
    local name=$1
    shift
    if [ -f "$WORK/$name.done" ]; then
        echo "scale.sh: $name: done before, skipped"
        return 0
    fi
    printf '%q ' "$@" > "$WORK/$name.cmd"
    echo >> "$WORK/$name.cmd"
    echo "scale.sh: $name: $(cat "$WORK/$name.cmd")"
    if /usr/bin/time -v -o "$WORK/$name.time" "$@" > "$WORK/$name.log" 2>&1; then
        touch "$WORK/$name.done"
    else
        echo "scale.sh: $name failed (exit $?), see $WORK/$name.log" >&2
        return 1
    fi
}

untiled_max() {  # largest drive run untiled at voxel $1
    local pair
    for pair in $UNTILED; do
        if [ "${pair%%:*}" = "$1" ]; then echo "${pair#*:}"; return; fi
    done
    echo 0
}

# Repeats after the first keep report.json only (the tile outputs are the first run's).
trim_repeat() { find "$1" -mindepth 1 -maxdepth 1 ! -name report.json -exec rm -rf {} +; }

mpi_env=()
[ "$(id -u)" = 0 ] && mpi_env=(env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1)

for size in $SIZES; do
    seq=$WORK/street$size
    step "sim_$size" "$SIM" street --size "$size" --frames "$size" --seed 4 -o "$seq" --quiet
    for voxel in $VOXELS; do
        common=(--set "dataset.path=$seq" --set "integrate.atsdf.voxel_size_m=$voxel" --quiet)
        for ((r = 1; r <= REPEATS; ++r)); do
            name=tiled_${size}_${voxel}
            [ "$r" -gt 1 ] && name=${name}_r$r
            step "$name" "$VDBMAP" run "$CONFIG" "${common[@]}" -o "$WORK/$name"
            [ "$r" -gt 1 ] && trim_repeat "$WORK/$name"
        done
        name=tiled_${size}_${voxel}
        if [ ! -f "$WORK/$name.eval.done" ]; then
            python3 "$root/scripts/merge_tiles.py" "$WORK/$name" > /dev/null
            step "$name.eval" "$VDBMAP" eval --gt "$seq/gt" --run "$WORK/$name/merged" \
                --json "$WORK/$name.eval.json" --quiet
        fi
        if [ "$size" -le "$(untiled_max "$voxel")" ]; then
            name=untiled_${size}_${voxel}
            step "$name" "$VDBMAP" run "$CONFIG" "${common[@]}" --set tiling.tile_size_m=0 \
                -o "$WORK/$name"
            step "$name.eval" "$VDBMAP" eval --gt "$seq/gt" --run "$WORK/$name" \
                --json "$WORK/$name.eval.json" --quiet
        fi
    done
done

if [ "$MPI_SIZE" != 0 ]; then
    [ -x "$MPI_EXE" ] || { echo "scale.sh: $MPI_EXE missing (build with MPI)" >&2; exit 1; }
    seq=$WORK/street$MPI_SIZE
    step "sim_$MPI_SIZE" "$SIM" street --size "$MPI_SIZE" --frames "$MPI_SIZE" --seed 4 -o "$seq" --quiet
    for ranks in 1 2; do
        for ((r = 1; r <= REPEATS; ++r)); do
            name=mpi${ranks}_${MPI_SIZE}_0.10
            [ "$r" -gt 1 ] && name=${name}_r$r
            # --bind-to none: one rank may use both cores (TBB), as a plain `vdbmap run`.
            step "$name" "${mpi_env[@]}" mpirun --bind-to none -np "$ranks" "$MPI_EXE" run \
                "$CONFIG" --set "dataset.path=$seq" --set integrate.atsdf.voxel_size_m=0.10 \
                --quiet -o "$WORK/$name"
            [ "$r" -gt 1 ] && trim_repeat "$WORK/$name"
        done
    done
fi
table
