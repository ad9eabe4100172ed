#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Imports OUT/map.vdb, OUT/mesh.ply and OUT/textured/mesh.obj into Blender 3.4 headless.
# Usage: scripts/blender_check.sh OUTDIR      (needs the Debian package `blender`)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
out=${1:?usage: scripts/blender_check.sh OUTDIR}
command -v blender >/dev/null || { echo "blender_check: install Blender first: apt-get install -y blender" >&2; exit 1; }
blender --background --factory-startup --python-exit-code 1 --python "$root/scripts/blender_check.py" -- "$out/map.vdb" "$out/mesh.ply" 2>&1 | grep -E "^blender_check"
status=${PIPESTATUS[0]}
if [ -f "$out/textured/mesh.obj" ]; then
    blender --background --factory-startup --python-exit-code 1 --python "$root/scripts/blender_check_textured.py" -- "$out/textured/mesh.obj" 2>&1 | grep -E "^blender_check"
    [ "${PIPESTATUS[0]}" -eq 0 ] || status=1
fi
exit "$status"
