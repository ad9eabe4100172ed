// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <opencv2/core.hpp>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/mesh/MeshArrays.h"
#include "vdbmap/mesh/TriMesh.h"

namespace vdbmap::texture {

/// A triangle mesh as plain arrays (world frame W, metres): what the texturing algorithms use,
/// so that they run and test without OpenMesh or a pipeline. `vdbmap::meshArrays(mesh)`
/// makes one from a TriMesh.
using MeshArrays = vdbmap::MeshArrays;
using vdbmap::meshArrays;

/// Returns the 8-bit BGR colour image of view `view` (the index into the views vector). Must be
/// thread-safe: the texturing passes call it from TBB tasks, one image per task.
using ImageLoader = std::function<cv::Mat(std::size_t view)>;

/// Per (face, view) observation statistics gathered in one streaming pass over the images.
struct ObservationStats {
    float quality = 0;               ///< E_Q: sum of gradient magnitude over the face
    Vec3f mean_bgr = Vec3f::Zero();  ///< mean colour over the face's pixels, 0..255
    std::uint32_t pixels = 0;        ///< pixels whose centre lies inside the face
};

}  // namespace vdbmap::texture
