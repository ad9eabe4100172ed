// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/io/Camera.h"

namespace vdbmap {

/// A held-out ground-truth camera view (gt/views/): an image rendered from the ground-truth
/// textured mesh with shading but without vignetting or exposure change.
struct GtView {
    std::string image;  ///< file name, relative to the views folder
    CameraIntrinsics intrinsics;
    Isometry3d T_W_C = Isometry3d::Identity();  ///< camera -> world
};

/// Writes `views.json` in `folder` (atomically). Throws IoError.
void writeGtViews(const std::filesystem::path& folder, const std::vector<GtView>& views);
/// Reads `folder/views.json`. Throws IoError naming the file and the bad key.
std::vector<GtView> readGtViews(const std::filesystem::path& folder);

}  // namespace vdbmap
