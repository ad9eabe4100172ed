// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "vdbmap/core/Types.h"

namespace vdbmap::tiles3d {

/// Page index of a face without texture.
inline constexpr std::uint32_t kNoPage = 0xffffffffu;

/// The content of one 3D Tiles tile: triangles with per-corner positions and texture
/// coordinates (an unindexed mesh: every face has its own three corners, so that each face can
/// carry its own feature id), a class and a confidence per face, and the atlas pages.
struct TileMesh {
    /// Positions are relative to this point of W (metres): float32 keeps 0.1 mm within a
    /// kilometre of it (the relative-to-centre offset of the GLB's node).
    Eigen::Vector3d origin_W = Eigen::Vector3d::Zero();
    std::vector<std::array<Eigen::Vector3f, 3>> corners;  ///< per face, relative to origin_W
    /// Per face and corner, glTF convention: (0, 0) is the top-left of the page. Empty when no
    /// face is textured.
    std::vector<std::array<Eigen::Vector2f, 3>> uvs;
    std::vector<std::uint32_t> page;   ///< per face: index into pages, or kNoPage
    std::vector<std::uint8_t> label;   ///< per face: class id, 255 = unknown
    std::vector<float> confidence;     ///< per face, [0, 1]
    std::vector<cv::Mat> pages;        ///< CV_8UC3 BGR atlas pages

    std::size_t faces() const { return corners.size(); }
    /// Corner k of face f in W.
    Eigen::Vector3d cornerW(std::size_t f, int k) const {
        return origin_W + corners[f][static_cast<std::size_t>(k)].cast<double>();
    }
    /// Throws InvalidInput if the per-face arrays disagree in size or a page index is out of
    /// range.
    void check() const;
};

/// An axis-aligned box in W, metres (empty until a point is added).
struct Bounds {
    Eigen::Vector3d min_W = Eigen::Vector3d::Constant(1e300);
    Eigen::Vector3d max_W = Eigen::Vector3d::Constant(-1e300);
    bool empty() const { return min_W.x() > max_W.x(); }
    void add(const Eigen::Vector3d& p) {
        min_W = min_W.cwiseMin(p);
        max_W = max_W.cwiseMax(p);
    }
    void add(const Bounds& b) {
        if (!b.empty()) { add(b.min_W); add(b.max_W); }
    }
    bool contains(const Bounds& b, double tolerance_m) const {
        return (b.min_W.array() >= min_W.array() - tolerance_m).all() &&
               (b.max_W.array() <= max_W.array() + tolerance_m).all();
    }
};

/// Axis-aligned bounds of the faces' corners in W.
Bounds boundsW(const TileMesh& mesh);

/// Area of each class id over the faces (m^2), indexed by id.
std::array<double, 256> classAreas(const TileMesh& mesh);

}  // namespace vdbmap::tiles3d
