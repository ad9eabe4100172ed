#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Frame rate of the viewer's overview (`vdbmap view OUT`) in headless Debian chromium with
# software WebGL (SwiftShader), median of REPEATS runs of SECONDS each
# (docs/benchmarks/viewer.md). Needs node, npm (first run: npm ci of tests/browser) and chromium.
# Usage: bench/viewer_fps.sh OUT [REPEATS] [SECONDS]     (OUT: a run's folder with 3dtiles/)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${BUILD_DIR:-$root/build}
out=${1:?usage: bench/viewer_fps.sh OUT [REPEATS] [SECONDS]}
repeats=${2:-5}
seconds=${3:-3}
browser_dir="$build_dir/bench/browser"
"$root/tests/browser/setup.sh" "$browser_dir" > /dev/null
echo "machine: $(nproc) cores, $(uptime | sed 's/.*load average/load average/')"
chromium --version 2>/dev/null | head -1 || true
node "$browser_dir/fps.mjs" --vdbmap "$build_dir/bin/vdbmap" --out "$out" \
    --repeats "$repeats" --seconds "$seconds"
