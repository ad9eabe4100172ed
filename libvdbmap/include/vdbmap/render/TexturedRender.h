// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/io/Camera.h"
#include "vdbmap/io/MeshIO.h"

namespace vdbmap {

class Raycaster;

/// One textured mesh to render: its OBJ data, one BGR8 texture per material, a Raycaster built
/// on mesh.positions / triangle vertex indices, and optional per-face class ids.
struct RenderLayer {
    const ObjMesh* mesh = nullptr;
    const std::vector<cv::Mat>* textures = nullptr;
    const Raycaster* raycaster = nullptr;
    const std::vector<std::uint8_t>* face_labels = nullptr;  ///< null = label 255
};

/// Shading of a render: none (pure texture, for baked textures) or Lambert with one
/// directional light plus ambient.
struct RenderOptions {
    bool lambert = false;
    Vec3f light_dir_W = Vec3f(0.3f, 0.2f, 1.0f).normalized();  ///< towards the light
    float ambient = 0.35f;                                      ///< 0..1
    float max_depth_m = 500.0f;
};

/// The result of a render; pixels without surface have face -1, depth 0, colour black and
/// label 255.
struct RenderedView {
    cv::Mat color;   ///< CV_8UC3, BGR
    cv::Mat labels;  ///< CV_8UC1, class id of the hit face
    cv::Mat depth;   ///< CV_32FC1, ray distance in metres
    cv::Mat layer;   ///< CV_8UC1, index of the layer hit (255 = none)
    cv::Mat face;    ///< CV_32SC1, face index within its layer (-1 = none)
};

/// Samples a BGR8 texture at OBJ UV (v up, repeating), bilinearly; returns B, G, R in 0..255.
Vec3f sampleTexture(const cv::Mat& texture_bgr, float u, float v);

/// Ray casts every pixel of a pinhole camera (no distortion; pixel (0,0) is the centre of the
/// top-left pixel) against the layers and keeps the nearest hit. `T_C_W` maps world to camera.
/// Parallel over rows (TBB). Throws InvalidInput if a layer lacks mesh/textures/raycaster or
/// the intrinsics are empty.
RenderedView renderView(const std::vector<RenderLayer>& layers,
                        const CameraIntrinsics& intrinsics, const Isometry3d& T_C_W,
                        const RenderOptions& options = {});

}  // namespace vdbmap
