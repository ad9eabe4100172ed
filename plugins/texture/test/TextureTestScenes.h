// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cmath>
#include <vector>

#include "TextureTypes.h"
#include "vdbmap/render/Visibility.h"

namespace vdbmap::texture::test {

/// A planar grid at z = depth_m in the world, facing -z (towards cameras at the origin looking
/// along +z), cols x rows quads of two triangles each, spanning [-half_w, half_w] x [-half_h,
/// half_h].
inline MeshArrays planeGrid(int cols, int rows, float half_w, float half_h, float depth_m) {
    MeshArrays mesh;
    for (int j = 0; j <= rows; ++j) {
        for (int i = 0; i <= cols; ++i) {
            mesh.vertices_W.emplace_back(-half_w + 2 * half_w * i / cols,
                                         -half_h + 2 * half_h * j / rows, depth_m);
        }
    }
    auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * (cols + 1) + i); };
    for (int j = 0; j < rows; ++j) {
        for (int i = 0; i < cols; ++i) {
            mesh.faces.push_back({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
            mesh.faces.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
        }
    }
    return mesh;
}

/// Face pairs sharing an edge (first < second, sorted), by brute force: the test oracle.
inline std::vector<std::array<std::uint32_t, 2>> bruteAdjacency(const MeshArrays& mesh) {
    std::vector<std::array<std::uint32_t, 2>> pairs;
    for (std::uint32_t a = 0; a < mesh.faces.size(); ++a) {
        for (std::uint32_t b = a + 1; b < mesh.faces.size(); ++b) {
            int shared = 0;
            for (auto va : mesh.faces[a]) {
                for (auto vb : mesh.faces[b]) shared += va == vb;
            }
            if (shared == 2) pairs.push_back({a, b});
        }
    }
    return pairs;
}

/// A pinhole view at camera centre `centre_W`, looking along +z (no rotation).
inline View makeView(std::size_t frame, double centre_x, int width = 200, int height = 100,
                     double focal = 100.0) {
    View view;
    view.frame = frame;
    view.camera = 0;
    view.intrinsics.width = width;
    view.intrinsics.height = height;
    view.intrinsics.fx = view.intrinsics.fy = focal;
    view.intrinsics.cx = (width - 1) / 2.0;
    view.intrinsics.cy = (height - 1) / 2.0;
    view.T_C_W = Isometry3d::Identity();
    view.T_C_W.translation() = Vec3d(-centre_x, 0, 0);
    return view;
}

/// Projection of a world point into a view (pinhole, no distortion).
inline Eigen::Vector2f projectPoint(const View& view, const Vec3f& p_W) {
    const Vec3d p_C = view.T_C_W * p_W.cast<double>();
    const auto& in = view.intrinsics;
    return Eigen::Vector2f(static_cast<float>(in.fx * p_C.x() / p_C.z() + in.cx),
                           static_cast<float>(in.fy * p_C.y() / p_C.z() + in.cy));
}

/// Hand-made visibility: face f is seen by the views `sees(f, v)` says, with exact projections.
template <typename SeesFn>
Visibility makeVisibility(const MeshArrays& mesh, const std::vector<View>& views, SeesFn&& sees) {
    Visibility vis;
    vis.offsets.push_back(0);
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        for (std::uint32_t v = 0; v < views.size(); ++v) {
            if (!sees(f, v)) continue;
            FaceObservation obs;
            obs.view = v;
            for (int k = 0; k < 3; ++k) {
                obs.pixels[k] = projectPoint(views[v], mesh.vertices_W[mesh.faces[f][k]]);
            }
            const Eigen::Vector2f e1 = obs.pixels[1] - obs.pixels[0];
            const Eigen::Vector2f e2 = obs.pixels[2] - obs.pixels[0];
            obs.area_px = 0.5f * std::abs(e1.x() * e2.y() - e1.y() * e2.x());
            obs.cos_angle = 1.0f;
            obs.depth_m = 5.0f;
            vis.obs.push_back(obs);
        }
        vis.offsets.push_back(vis.obs.size());
    }
    return vis;
}

}  // namespace vdbmap::texture::test
