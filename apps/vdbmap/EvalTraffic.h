// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

namespace vdbmap {
class Raycaster;
}

/// Settings of the traffic section of `vdbmap eval`.
struct TrafficEvalOptions {
    double ghost_distance_m = 0.1;   ///< farther than this from the static ground truth
    double swept_inflate_m = 0.1;    ///< each mover box grown by this on every side
    double footprint_cell_m = 0.05;  ///< raster of the swept ground area
    double sample_spacing_m = 0.02;  ///< sub-triangle size of the ghost area
    std::filesystem::path ghost_ply;  ///< if set: the run's faces with ghost area, as PLY
};

/// The traffic section of `vdbmap eval` when `gt_dir`/movers.json exists (vdbmap-sim
/// --traffic), else null: the ghost area of `run_dir`/mesh.ply (if present) against the
/// static ground truth `static_gt` inside the movers' swept volume, the swept ground area and
/// their ratio, and, with `run_dir`/dynamic_points.ply, the moving-point recall, precision and
/// static retention against the sequence's labels. Appends its lines to `table`. Throws
/// IoError for unreadable files.
nlohmann::json evalTraffic(const std::filesystem::path& gt_dir,
                           const std::filesystem::path& run_dir, const vdbmap::Raycaster& static_gt,
                           const TrafficEvalOptions& options, std::ostringstream& table);
