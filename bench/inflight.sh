#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Issue 37's one-process measurements (docs/benchmarks/scale.md, "Tiles in flight"): the tiled
# 400 m street at 0.10 m (config/street_tiled.yaml: integration, mesh, texture, semantic) with
# one tile at a time (tiling.max_tiles_in_flight=1, the sequential run of before) and with the
# default (tiles in flight, as many as threads within the memory budget), both --threads 2;
# then vdbmap-mpi with 2 ranks of --threads 1 on the same drive. Prints cores busy (report.json
# timings.cpu_s / timings.total_s), wall, CPU, peak memory, budget, most tiles in flight.
#
#   bench/inflight.sh BUILD WORK SEQ [REPEATS] [STEPS]
#     SEQ: a simulated drive (vdbmap-sim street --size 400 --frames 400 --seed 4 -o SEQ)
#     STEPS: any of "one inflight mpi" (default: all three)
# Each run: WORK/<step>_<k>/ (outputs), WORK/<step>_<k>.time (/usr/bin/time -v), .log.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=$(realpath "$1")
WORK=$(realpath -m "$2")
SEQ=$(realpath "$3")
REPEATS=${4:-1}
STEPS=${5:-"one inflight mpi"}
mkdir -p "$WORK"
S=(--set "dataset.path=$SEQ" --set integrate.atsdf.voxel_size_m=0.10 --quiet)
for k in $(seq 1 "$REPEATS"); do
    for step in $STEPS; do
        out=$WORK/${step}_$k
        rm -rf "$out"
        case $step in
            one) cmd=("$BUILD/bin/vdbmap" run "$root/config/street_tiled.yaml" "${S[@]}"
                      --set tiling.max_tiles_in_flight=1 --threads 2 -o "$out") ;;
            inflight) cmd=("$BUILD/bin/vdbmap" run "$root/config/street_tiled.yaml" "${S[@]}"
                           --threads 2 -o "$out") ;;
            mpi) cmd=(env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
                      mpirun --oversubscribe --bind-to none -np 2 "$BUILD/bin/vdbmap-mpi" run
                      "$root/config/street_tiled.yaml" "${S[@]}" --threads 1 -o "$out") ;;
            *) echo "inflight.sh: unknown step $step" >&2; exit 2 ;;
        esac
        echo "inflight.sh: $step #$k: uptime $(uptime | sed 's/.*load/load/')" | tee -a "$WORK/load.txt"
        printf '%q ' "${cmd[@]}" > "$WORK/${step}_$k.cmd"
        /usr/bin/time -v -o "$WORK/${step}_$k.time" nice -n 5 "${cmd[@]}" > "$WORK/${step}_$k.log" 2>&1
        echo "inflight.sh: $step #$k done: uptime $(uptime | sed 's/.*load/load/')" | tee -a "$WORK/load.txt"
    done
done
python3 "$root/bench/inflight_table.py" "$WORK"
