// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <vector>

#include "vdbmap/sim/Traffic.h"

namespace vdbmap {

/// gt/movers.json of a sequence simulated with --traffic: the movers with their parts and one
/// pose T_W_O per frame (docs/simulator.md).
struct MoversFile {
    std::vector<double> times_s;  ///< per frame, seconds (times.txt)
    std::vector<Mover> movers;    ///< each with times_s.size() poses
};

/// Writes `file` as JSON, atomically. Poses are 12 numbers, the row-major 3x4 [R | t] of
/// T_W_O (as KITTI poses). Throws IoError.
void writeMoversJson(const std::filesystem::path& path, const MoversFile& file);

/// Reads a movers.json. Throws IoError naming the file and the key if it is missing,
/// malformed, or a mover's pose count differs from the frame count.
MoversFile readMoversJson(const std::filesystem::path& path);

}  // namespace vdbmap
