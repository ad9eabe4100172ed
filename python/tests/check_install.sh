#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Usage: check_install.sh BUILD_DIR PYTHON SITE_DIR
# `cmake --install` into a scratch prefix, then the installed package imports, from a folder
# outside the build, and maps a plane. Exits non-zero on any failure.
set -euo pipefail
build_dir=$1
python=$2
site_dir=$3
work=$(mktemp -d "${TMPDIR:-/tmp}/vdbmap_python_install.XXXXXX")
trap 'rm -rf "$work"' EXIT
cmake --install "$build_dir" --prefix "$work/prefix" > "$work/install.log"
test -f "$work/prefix/$site_dir/vdbmap/__init__.py" || { echo "package not installed in $site_dir"; exit 1; }
cd "$work"
PYTHONPATH="$work/prefix/$site_dir" "$python" - "$work/prefix" <<'CHECK'
import sys
import numpy as np
import vdbmap
assert vdbmap.__file__.startswith(sys.argv[1]), vdbmap.__file__
d = np.array([[np.cos(a), np.sin(a), -0.3] for a in np.linspace(0, 6.28, 2000)])
pts = (d * (1.8 / 0.3)).astype(np.float32)  # a ring on the plane z = -1.8 below the sensor
m = vdbmap.Map(voxel_size_m=0.2)
m.integrate(pts, np.eye(4))
assert m.stats["points_integrated"] == 2000, m.stats
print("installed vdbmap", vdbmap.__version__, "OK")
CHECK
