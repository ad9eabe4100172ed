// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "SemanticVotes.h"
#include "vdbmap/core/Types.h"

namespace vdbmap::semantic {

/// Faces binned in a uniform grid of cubic cells for "all faces within r of a point" queries:
/// a face goes into every cell that its bounding box, grown by `radius_m`, touches, so that a
/// query looks into the one cell that holds the point.
class FaceGrid {
public:
    /// `vertices` and `triangles` must outlive the grid. Cells are 2 `radius_m` wide.
    FaceGrid(const std::vector<Vec3f>& vertices,
             const std::vector<std::array<std::uint32_t, 3>>& triangles, float radius_m);
    /// Every face whose closest point lies closer than the grid's radius to `p`, with that
    /// distance, ascending by face index (`faces` and `distances_m` are cleared first).
    void facesWithin(const Vec3f& p, std::vector<std::uint32_t>& faces,
                     std::vector<float>& distances_m) const;
    std::size_t numFaces() const { return triangles_.size(); }

private:
    const std::vector<Vec3f>& vertices_;
    const std::vector<std::array<std::uint32_t, 3>>& triangles_;
    float radius_m_;
    std::unordered_map<std::uint64_t, std::uint32_t> cell_index_;  // cell key -> cell
    std::vector<std::uint64_t> cell_offsets_;                      // size cells + 1
    std::vector<std::uint32_t> cell_faces_;
    std::vector<Eigen::Vector4f> spheres_;  // per face: centroid, bounding radius + radius_m
};

/// Exact distance from `p` to the triangle (a, b, c) (Ericson, Real-Time Collision Detection,
/// 5.1.5).
float pointTriangleDistance(const Vec3f& p, const Vec3f& a, const Vec3f& b, const Vec3f& c);

/// LiDAR votes of labelled points for the faces near them, accumulated scan by scan:
/// a point p of class c adds w(d) = 1 - (d / r)^2 to S_L(F_i, c) of every face F_i whose
/// distance d to p is below r = radius_m. Points are buffered (up to `batch_points`, across
/// scans) and merged per (cell of r/2, class) into their mean with their count as weight
/// before they vote, so that the dense rings near the sensor and the overlap of consecutive
/// scans do not cost more than they tell. Deterministic (does not depend on the thread
/// count). `vertices` and `triangles` must outlive the accumulator.
class LidarVoteAccumulator {
public:
    LidarVoteAccumulator(const std::vector<Vec3f>& vertices,
                         const std::vector<std::array<std::uint32_t, 3>>& triangles,
                         std::size_t num_classes, float radius_m,
                         std::size_t batch_points = std::size_t(1) << 21);
    /// Points in the world frame with their class index (into the label set; kNoClass =
    /// void, does not vote). Throws InvalidInput on a size mismatch or a class out of range.
    void add(const std::vector<Vec3f>& points_W, const std::vector<std::uint32_t>& classes);
    /// The accumulated votes (weights = sum of w(d)); `votes` counts the points that reached
    /// a face, `void_votes` the void points.
    FaceVotes finish();
    /// Points that reached no face (known after finish()).
    std::size_t pointsWithoutFace() const { return points_without_face_; }

    static constexpr std::uint32_t kNoClass = 0xFFFFFFFFu;

private:
    void flush();  // merge and splat the buffered points

    FaceGrid grid_;
    std::size_t batch_points_;
    std::vector<Vec3f> pending_points_;
    std::vector<std::uint32_t> pending_classes_;
    std::size_t num_classes_;
    float radius_m_;
    std::vector<float> mass_;  // face-major, num_classes per face
    std::size_t points_voted_ = 0;
    std::size_t points_void_ = 0;
    std::size_t points_without_face_ = 0;
};

}  // namespace vdbmap::semantic
