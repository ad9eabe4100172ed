#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Builds the libFuzzer targets of tests/fuzz with clang (the library instrumented with
# -fsanitize=fuzzer-no-link,address,undefined) in build-fuzz/, then, if a target is named,
# fuzzes it from its corpus:  scripts/fuzz.sh [NAME [SECONDS [extra libFuzzer flags]]]
# FUZZ_NO_BUILD=1 skips the build step (e.g. while another target of build-fuzz builds).
# NAME is Bin, Pcd, Lzf, Ply, Obj, Calib, Poses, LabelSet or PipelineYaml. New inputs go to
# build-fuzz/corpus/<name>/ (the seeds in tests/fuzz/corpus/<name>/ are only read); a
# crash/leak/timeout input is written to build-fuzz/findings/. The fuzzer runs under nice -n 19.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${FUZZ_BUILD_DIR:-$root/build-fuzz}
cxx=${FUZZ_CXX:-clang++-14}
cc=${FUZZ_CC:-clang-14}
if ! command -v "$cxx" > /dev/null; then
    echo "fuzz.sh: $cxx not found (Debian: apt-get install clang-14)" >&2
    exit 1
fi
if [ ! -f "$build_dir/CMakeCache.txt" ]; then
    # shellcheck disable=SC2086
    cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_C_COMPILER="$cc" \
        -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only" \
        -DVDBMAP_FUZZ=ON -DVDBMAP_BUILD_TESTS=OFF -DVDBMAP_BUILD_APPS=OFF \
        -DVDBMAP_BUILD_PLUGINS=OFF -DVDBMAP_BUILD_BENCH=OFF ${CMAKE_ARGS:-}
fi
[ -n "${FUZZ_NO_BUILD:-}" ] || cmake --build "$build_dir" -j"${FUZZ_JOBS:-2}"
[ $# -ge 1 ] || exit 0

name=$1
seconds=${2:-600}
shift $(( $# >= 2 ? 2 : 1 ))
corpus_name=$(sed -n "s/^set(VDBMAP_FUZZ_CORPUS_${name} \(.*\))$/\1/p" "$root/tests/fuzz/CMakeLists.txt")
[ -n "$corpus_name" ] || { echo "fuzz.sh: unknown target $name" >&2; exit 2; }
work="$build_dir/corpus/$corpus_name"
mkdir -p "$work" "$build_dir/findings"
cd "$build_dir/findings"
exec nice -n 19 "$build_dir/bin/${name}Fuzz" "$work" "$root/tests/fuzz/corpus/$corpus_name" \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=4096 -print_final_stats=1 \
    -artifact_prefix="$build_dir/findings/${corpus_name}-" "$@"
