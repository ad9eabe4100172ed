#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Installs missing packages (scripts/install-deps.sh), configures build/ (Release) and builds
# with every core. Quick when nothing changed. BUILD_DIR and CMAKE_ARGS override the defaults.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${BUILD_DIR:-$root/build}

"$root/scripts/install-deps.sh"

if [ ! -f "$build_dir/CMakeCache.txt" ]; then
    # shellcheck disable=SC2086
    cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DVDBMAP_BUILD_CGAL_PLUGIN=ON ${CMAKE_ARGS:-}
fi
cmake --build "$build_dir" -j"$(nproc)"
