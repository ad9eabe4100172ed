#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Same set-up as build.sh, then the whole test suite (unit, integration, CLI, install +
# out-of-tree plugin build) with ctest.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${BUILD_DIR:-$root/build}
start=$(date +%s)

"$root/scripts/build.sh"
built=$(date +%s)

ctest --test-dir "$build_dir" --output-on-failure -j"$(nproc)" "$@"
done_at=$(date +%s)
echo "test.sh: build $((built - start)) s, tests $((done_at - built)) s"
