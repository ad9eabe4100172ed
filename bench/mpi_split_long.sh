#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Issue 37 on a long drive (docs/benchmarks/scale.md, "1.6 km"): the runs one after the other,
# each under /usr/bin/time -v with the load average before and after (WORK/<run>.time,
# WORK/load.txt). config/street_tiled.yaml at 0.10 m.
#
#   bench/mpi_split_long.sh BUILD WORK SEQUENCE "np8 inflight np1"
#     npN:      OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe
#               --bind-to none -np N vdbmap-mpi run ... --threads 1 -o WORK/npN
#     np1:      vdbmap run ... --threads 1 -o WORK/np1 (one rank: the tiles one at a time on one thread)
#     inflight: vdbmap run ... --threads 2 -o WORK/inflight (tiles in flight: the peak memory)
#     notrim:   the same with VDBMAP_MALLOC_TRIM=0 (no malloc_trim after each tile)
#     pertile:  inflight with --set tiling.map_vdb=per_tile (a map.vdb per tile, the map behind
#               the sensor dropped: the peak does not grow with the drive)
#     pertile_np8: np8 with the same setting (no map gather on rank 0)
# Then: bench/mpi_split_table.py WORK 1 8 (with np1), bench/mpi_split_paper.py BUILD WORK/np8/report.json ...
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=$(realpath "$1")
WORK=$(realpath -m "$2")
SEQ=$(realpath "$3")
RUNS=${4:-"np8 inflight np1"}
mkdir -p "$WORK"
S=(--set "dataset.path=$SEQ" --set integrate.atsdf.voxel_size_m=0.10 --quiet)
for run in $RUNS; do
    rm -rf "${WORK:?}/$run"
    echo "$run start $(date -u +%FT%TZ) $(uptime)" >> "$WORK/load.txt"
    case $run in
        np1) /usr/bin/time -v -o "$WORK/$run.time" "$BUILD/bin/vdbmap" run "$root/config/street_tiled.yaml" \
                 "${S[@]}" --threads 1 -o "$WORK/$run" ;;
        inflight) /usr/bin/time -v -o "$WORK/$run.time" "$BUILD/bin/vdbmap" run "$root/config/street_tiled.yaml" \
                 "${S[@]}" --threads 2 -o "$WORK/$run" ;;
        pertile) /usr/bin/time -v -o "$WORK/$run.time" "$BUILD/bin/vdbmap" run "$root/config/street_tiled.yaml" \
                 "${S[@]}" --set tiling.map_vdb=per_tile --threads 2 -o "$WORK/$run" ;;
        pertile_np*) OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 /usr/bin/time -v -o "$WORK/$run.time" \
                 mpirun --oversubscribe --bind-to none -np "${run#pertile_np}" "$BUILD/bin/vdbmap-mpi" run \
                 "$root/config/street_tiled.yaml" "${S[@]}" --set tiling.map_vdb=per_tile --threads 1 -o "$WORK/$run" ;;
        notrim) VDBMAP_MALLOC_TRIM=0 /usr/bin/time -v -o "$WORK/$run.time" "$BUILD/bin/vdbmap" run \
                 "$root/config/street_tiled.yaml" "${S[@]}" --threads 2 -o "$WORK/$run" ;;
        np*) OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 /usr/bin/time -v -o "$WORK/$run.time" \
                 mpirun --oversubscribe --bind-to none -np "${run#np}" "$BUILD/bin/vdbmap-mpi" run \
                 "$root/config/street_tiled.yaml" "${S[@]}" --threads 1 -o "$WORK/$run" ;;
        *) echo "unknown run $run" >&2; exit 2 ;;
    esac
    echo "$run end $(date -u +%FT%TZ) $(uptime)" >> "$WORK/load.txt"
done
