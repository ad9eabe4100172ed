// SPDX-License-Identifier: Apache-2.0
// A view whose image a box hid (and whose scan saw the box) does not texture the wall behind it.
#include <catch2/catch.hpp>
#include <cmath>

#include "TexturePipeline.h"
#include "TextureTestScenes.h"
#include "vdbmap/render/ScanOcclusion.h"

using namespace vdbmap::texture;
using namespace vdbmap::texture::test;
using vdbmap::Vec3d;
using vdbmap::Vec3f;

namespace {

constexpr float kWallZ = 5.0f;
constexpr double kBoxZ = 2.5, kBoxX0 = -2.0, kBoxX1 = -0.5;  // box front face, world x range

/// The grey wall seen by a view; with `box`, the red box in front of it where it hides it.
cv::Mat render(const vdbmap::View& view, bool box) {
    const auto& in = view.intrinsics;
    cv::Mat image(in.height, in.width, CV_8UC3, cv::Scalar(120, 120, 120));
    const double centre_x = -view.T_C_W.translation().x();
    for (int v = 0; v < in.height; ++v) {
        for (int u = 0; u < in.width; ++u) {
            const double x_box = (u - in.cx) / in.fx * kBoxZ + centre_x;
            if (box && x_box >= kBoxX0 && x_box <= kBoxX1) {
                image.at<cv::Vec3b>(v, u) = cv::Vec3b(30, 30, 220);
            }
        }
    }
    return image;
}

/// The view's scan in its camera frame: the wall, and the box front if `box`, sampled densely
/// (1.5 px apart).
std::vector<Vec3f> scan(const vdbmap::View& view, bool box) {
    std::vector<Vec3f> points_C;
    const auto& in = view.intrinsics;
    const double centre_x = -view.T_C_W.translation().x();
    for (double v = 0; v < in.height; v += 1.5) {
        for (double u = 0; u < in.width; u += 1.5) {
            const double rx = (u - in.cx) / in.fx, ry = (v - in.cy) / in.fy;
            const double x_box = rx * kBoxZ + centre_x;
            const double z = box && x_box >= kBoxX0 && x_box <= kBoxX1 ? kBoxZ : kWallZ;
            points_C.emplace_back(static_cast<float>(rx * z), static_cast<float>(ry * z),
                                  static_cast<float>(z));
        }
    }
    return points_C;
}

}  // namespace

TEST_CASE("a view does not texture a face a box in its scan hides", "[texture][scan_occlusion]") {
    const MeshArrays mesh = planeGrid(16, 8, 2.0f, 1.0f, kWallZ);
    const std::vector<vdbmap::View> views = {makeView(0, -0.3), makeView(1, 0.3)};
    // Both views see every face as far as the mesh knows (the box is not in the map); view 0's
    // image and scan have the box, view 1's do not.
    vdbmap::Visibility vis =
        makeVisibility(mesh, views, [](std::size_t, std::uint32_t) { return true; });
    const std::vector<cv::Mat> images = {render(views[0], true), render(views[1], false)};
    // The mesh's own occlusion test cannot know the box; the scan of view 0 does.
    const std::size_t removed = vdbmap::removeScanOccluded(
        vis, mesh, views, [&](std::size_t v) { return scan(views[v], v == 0); }, {});
    CHECK(removed > 0);
    TextureOptions options;
    options.use_mrf = false;  // best view per face: the scan test alone decides
    options.photo_consistency = false;
    options.global_adjustment = false;
    options.exposure_gains = false;
    const TextureResult result = textureMesh(mesh, views, vis, bruteAdjacency(mesh),
                                             [&](std::size_t v) { return images[v]; }, options);
    std::size_t behind = 0;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        float x = 0;
        for (auto v : mesh.faces[f]) x += mesh.vertices_W[v].x() / 3.0f;
        // The box's shadow on the wall from view 0 (camera at x = -0.3): x in [-3.7, -0.7].
        if (x > -0.9f || x < -2.0f) continue;
        ++behind;
        CHECK(result.face_view[f] == 1);
    }
    CHECK(behind > 10);
    // Faces right of the shadow keep both views.
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        float x = 0;
        for (auto v : mesh.faces[f]) x += mesh.vertices_W[v].x() / 3.0f;
        if (x > -0.3f) CHECK(vis.count(f) == 2);
    }
}
