#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The sanitizer configuration: library, plugins, apps and tests (no benchmarks) built with
# -fsanitize=address,undefined (clang 14, -O1, line tables) in build-asan/, then the whole
# ctest suite, which includes the replay of every fuzz corpus (fuzz_replay_*). Any ASan error,
# UBSan report or leak fails the test that shows it. Suppressions: tests/sanitizers/*.supp
# (commented). clang rather than GCC: with both sanitizers on, GCC 12 takes 1.7 to 1.8 times
# as long per file (VoxelMap.cpp 160 s against 93 s, a test file 27 s against 15 s).
# SANITIZE_CXX / SANITIZE_CC override. `.ci/run` runs it after the release suite.
# The optional GPL plugin plugins/cgal is left out here (CGAL's templates would double the
# build time; its tests run in the release suite of scripts/test.sh).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${SANITIZE_BUILD_DIR:-$root/build-asan}
start=$(date +%s)

cxx=${SANITIZE_CXX:-clang++-14}
cc=${SANITIZE_CC:-clang-14}
"$root/scripts/install-deps.sh" clang-14
if [ ! -f "$build_dir/CMakeCache.txt" ]; then
    # shellcheck disable=SC2086
    cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_C_COMPILER="$cc" \
        -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1" \
        -DVDBMAP_SANITIZE=address,undefined -DVDBMAP_BUILD_BENCH=OFF \
        -DVDBMAP_BUILD_CGAL_PLUGIN=OFF ${CMAKE_ARGS:-}
fi
cmake --build "$build_dir" -j"$(nproc)"
built=$(date +%s)

supp="$root/tests/sanitizers"
# halt_on_error: a UBSan report is a failure, not a line in a log nobody reads.
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:suppressions=$supp/ubsan.supp"
export ASAN_OPTIONS="detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=0"
export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
# One ctest run, the slowest tests first (COST, cmake/TestCost.cmake). The mpirun tests turn
# leak detection off in mpirun and its ranks only (tests/mpi/MpiRunTest.cpp says why).
ctest --test-dir "$build_dir" --output-on-failure -j"$(nproc)" "$@"
done_at=$(date +%s)
echo "sanitize.sh: build $((built - start)) s, tests $((done_at - built)) s"
