#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Bytes fetched to the first complete overview of a tileset (docs/benchmarks/tiles3d.md):
# `vdbmap view OUT` in headless Debian chromium (software WebGL), the viewer's overview camera,
# a fresh cache; tests/browser/overview_bytes.mjs. Needs node, npm (first run: npm ci of
# tests/browser) and chromium.
# Usage: bench/tiles3d_overview.sh OUT [WIDTH HEIGHT [ERROR_TARGET]]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${BUILD_DIR:-$root/build}
out=${1:?usage: bench/tiles3d_overview.sh OUT [WIDTH HEIGHT [ERROR_TARGET]]}
browser_dir="$build_dir/bench/browser"
"$root/tests/browser/setup.sh" "$browser_dir" > /dev/null
node "$browser_dir/overview_bytes.mjs" --vdbmap "$build_dir/bin/vdbmap" --out "$out" \
    --width "${2:-1280}" --height "${3:-800}" --error-target "${4:-16}"
