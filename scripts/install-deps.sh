#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Installs the Debian 12 packages vdbmap builds against (the one list of them). Idempotent:
# when every package is present it only checks (dpkg -s) and exits 0. As root it runs
# `apt-get update` (only if something is missing) and `apt-get install`; otherwise it prints
# the exact command to run and exits 1. Extra packages a script needs on top of the list (the
# sanitizer build's clang-14) are given as arguments.
set -euo pipefail

PACKAGES=(
    cmake g++ make pkg-config lld
    libopenvdb-dev libboost-iostreams-dev libboost-dev libtbb-dev libimath-dev
    libeigen3-dev libopencv-dev libopenmesh-dev libcgal-dev
    libyaml-cpp-dev catch2 libembree-dev
    libspdlog-dev libfmt-dev libcli11-dev nlohmann-json3-dev
    liblzf-dev
    openmpi-bin libopenmpi-dev
    pybind11-dev python3-dev python3-numpy python3-pytest python3-open3d xvfb xauth
    libcpp-httplib-dev chromium
    libmeshoptimizer-dev
    nodejs
    "$@"
)
# node's npm (gltf-validator, the viewer's browser tests): Debian's `npm` only when no npm is on
# PATH (a NodeSource nodejs brings its own npm, and Debian's npm would conflict with it).
if ! command -v npm > /dev/null 2>&1; then
    PACKAGES+=(npm)
fi

missing=()
for pkg in "${PACKAGES[@]}"; do
    if ! dpkg -s "$pkg" > /dev/null 2>&1; then
        missing+=("$pkg")
    fi
done

if [ ${#missing[@]} -eq 0 ]; then
    echo "install-deps: all ${#PACKAGES[@]} packages present"
    exit 0
fi

apt_line="apt-get install -y --no-install-recommends ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
    echo "install-deps: missing packages: ${missing[*]}" >&2
    echo "install-deps: run as root:" >&2
    echo "  sudo apt-get update && sudo $apt_line" >&2
    exit 1
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update
# shellcheck disable=SC2086
apt-get install -y --no-install-recommends "${missing[@]}"
