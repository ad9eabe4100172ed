#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Usage: install_plugin_template.sh BUILD_DIR SOURCE_DIR [CMAKE]
# Installs BUILD_DIR into a scratch prefix, builds examples/plugin_template out of tree against
# that prefix (find_package(vdbmap CONFIG REQUIRED)), runs its config with the installed
# `vdbmap`, and checks the output. Exits non-zero on any failure.
set -euo pipefail
build_dir=$(cd "$1" && pwd)
source_dir=$(cd "$2" && pwd)
cmake_bin=${3:-cmake}
work=$(mktemp -d "${TMPDIR:-/tmp}/vdbmap_install_test.XXXXXX")
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"

"$cmake_bin" --install "$build_dir" --prefix "$prefix" > "$work/install.log"
test -x "$prefix/bin/vdbmap" || { echo "installed vdbmap missing"; exit 1; }
test -f "$prefix/lib/cmake/vdbmap/vdbmapConfig.cmake" || { echo "package config missing"; exit 1; }

"$cmake_bin" -S "$source_dir/examples/plugin_template" -B "$work/template-build" \
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" > "$work/configure.log"
"$cmake_bin" --build "$work/template-build" -j2 > "$work/build.log"
plugin=$(find "$work/template-build" -name 'vdbmap_plugin_template.so' | head -n1)
test -n "$plugin" || { echo "plugin not built"; cat "$work/build.log"; exit 1; }

# The installed app finds the plugin by name through VDBMAP_PLUGIN_PATH.
export VDBMAP_PLUGIN_PATH=$(dirname "$plugin")
"$prefix/bin/vdbmap" describe template.greet | grep -q "greeting"
"$prefix/bin/vdbmap" run "$source_dir/examples/plugin_template/config.yaml" \
    -o "$work/run" --set template.greet.repeat=3 --quiet
test "$(grep -c 'Hello from the template plugin' "$work/run/greetings.txt")" -eq 3
grep -q '"template.greet"' "$work/run/report.json"

# The template's mesh stage through the tile API: a tiled run on a tiny simulated street.
"$build_dir/bin/vdbmap-sim" street -o "$work/seq" --frames 2 --size 20 --gt-views 0 --quiet \
    --threads 1
"$prefix/bin/vdbmap" run "$source_dir/examples/plugin_template/tiles.yaml" \
    --set dataset.path="$work/seq" -o "$work/tiles" --quiet
test -s "$work/tiles/tiles.json"
summaries=$(find "$work/tiles/tiles" -name summary.json | wc -l)
test "$summaries" -ge 2 || { echo "expected a summary.json per tile, got $summaries"; exit 1; }
python3 - "$work/tiles" <<'CHECK'
import json, os, sys
out = sys.argv[1]
index = json.load(open(os.path.join(out, "tiles.json")))
faces = 0
read = 0
for t in index["tiles"]:
    s = json.load(open(os.path.join(out, "tiles", t["name"], "summary.json")))
    assert s["tile"] == t["name"], s
    assert s["core_faces"] == t["counts"]["faces"], (s, t)
    assert s["views"] == t["counts"]["views"], (s, t)
    faces += s["core_faces"]
    read += s["images_read"]
assert faces == index["counts"]["faces"] > 0, index["counts"]
assert read > 0, "no tile read an image"
CHECK

# The relocated install also finds its own plugins (<exe>/../lib/vdbmap/plugins).
unset VDBMAP_PLUGIN_PATH
mkdir -p "$prefix/lib/vdbmap/plugins"
cp "$plugin" "$prefix/lib/vdbmap/plugins/"
mv "$prefix" "$work/moved"
"$work/moved/bin/vdbmap" run "$source_dir/examples/plugin_template/config.yaml" \
    -o "$work/run2" --quiet
test -f "$work/run2/greetings.txt"
echo "install + out-of-tree plugin_template: OK"
