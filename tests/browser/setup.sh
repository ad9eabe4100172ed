#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Prepares the browser tests in a build folder: copies tests/browser/*.mjs, package.json and
# package-lock.json to DEST and runs `npm ci` there (puppeteer-core, cesium) unless DEST's
# node_modules already matches the lock file. Needs the npm registry on the first run and
# Debian's chromium (scripts/install-deps.sh installs both npm's node and chromium).
# Usage: tests/browser/setup.sh DEST
set -euo pipefail
src=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
dest=${1:?usage: setup.sh DEST}
mkdir -p "$dest"
cp "$src"/*.mjs "$src/package.json" "$src/package-lock.json" "$dest/"
command -v node > /dev/null || { echo "browser tests: node is not installed" >&2; exit 1; }
command -v npm > /dev/null || { echo "browser tests: npm is not installed" >&2; exit 1; }
[ -x "${CHROMIUM:-/usr/bin/chromium}" ] || { echo "browser tests: ${CHROMIUM:-/usr/bin/chromium} is missing (apt-get install chromium)" >&2; exit 1; }
stamp="$dest/node_modules/.vdbmap-lock.sha256"
want=$(sha256sum "$src/package-lock.json" | cut -d' ' -f1)
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ]; then
    echo "browser tests: node_modules in $dest is up to date"
    exit 0
fi
(cd "$dest" && npm ci --no-audit --no-fund --loglevel=error)
echo "$want" > "$stamp"
echo "browser tests: npm ci done in $dest"
