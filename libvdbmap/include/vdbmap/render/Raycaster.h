// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/mesh/TriMesh.h"

namespace vdbmap {

/// Ray casting against a static triangle mesh with an Embree BVH (Apache-2.0). Shared by the
/// visibility test of the texture and semantic plugins, the simulator and the evaluation.
/// Const methods are thread-safe and may be called from TBB tasks.
class Raycaster {
public:
    struct Hit {
        float distance = 0;      ///< along the (unit) direction, metres
        std::uint32_t face = 0;  ///< triangle index (= face idx for fromMesh)
        float u = 0, v = 0;      ///< barycentric coordinates of the hit (Embree convention)
        Vec3f normal_unit = Vec3f::Zero();  ///< geometric normal, (v1-v0)x(v2-v0) normalised
    };

    /// Builds the BVH. Throws InvalidInput on an index out of range.
    Raycaster(const std::vector<Vec3f>& vertices,
              const std::vector<std::array<std::uint32_t, 3>>& triangles);
    static Raycaster fromMesh(const TriMesh& mesh);
    ~Raycaster();
    Raycaster(Raycaster&&) noexcept;
    Raycaster& operator=(Raycaster&&) noexcept;

    /// First hit with distance in [t_min, t_max], or nullopt. `direction_unit` must be unit.
    std::optional<Hit> intersect(const Vec3f& origin, const Vec3f& direction_unit,
                                 float t_min = 0.0f,
                                 float t_max = std::numeric_limits<float>::infinity()) const;
    /// True if anything is hit with distance in [t_min, t_max] (cheaper than intersect).
    bool occluded(const Vec3f& origin, const Vec3f& direction_unit, float t_min,
                  float t_max) const;
    /// Batched version of intersect, parallel over rays (TBB). hits[i] is empty on a miss.
    /// `origins` has one entry per direction, or a single entry shared by all rays. Throws
    /// InvalidInput on other sizes.
    void intersect(const std::vector<Vec3f>& origins, const std::vector<Vec3f>& directions_unit,
                   float t_max, std::vector<std::optional<Hit>>& hits) const;

    /// Closest point on the mesh to a query point (Embree rtcPointQuery, exact point-to-triangle
    /// distance).
    struct ClosestPoint {
        float distance = 0;      ///< metres
        std::uint32_t face = 0;  ///< triangle index
        Vec3f point = Vec3f::Zero();  ///< the closest point on that triangle
    };
    /// Closest point within `max_distance` of `query`, or nullopt if nothing is that close (or
    /// the mesh is empty). Thread-safe.
    std::optional<ClosestPoint> closestPoint(
        const Vec3f& query, float max_distance = std::numeric_limits<float>::infinity()) const;

    std::size_t numTriangles() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace vdbmap
