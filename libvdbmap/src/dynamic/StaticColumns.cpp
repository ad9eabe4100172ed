// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/dynamic/StaticColumns.h"

#include <algorithm>
#include <array>

#include "vdbmap/dynamic/VoxelTable.h"

namespace vdbmap {

std::vector<std::uint8_t> staticColumns(const std::vector<Vec3f>& points_L, const std::vector<std::size_t>& members,
                                        const std::vector<std::uint8_t>& kept, float voxel_m,
                                        float max_footprint_m, float min_height_m) {
    std::vector<std::uint8_t> column(members.size(), 0);
    const float inv = 1.0f / voxel_m;
    // 1. The voxels holding kept members.
    VoxelTable table(members.size() + 16);
    std::vector<std::array<std::int64_t, 3>> coords;
    std::vector<std::int64_t> voxel(members.size(), -1);
    for (std::size_t m = 0; m < members.size(); ++m) {
        if (!kept[m]) continue;
        const Vec3f& p = points_L[members[m]];
        const std::array<std::int64_t, 3> v = voxelCoords(p.x(), p.y(), p.z(), inv);
        const auto next = static_cast<std::uint32_t>(coords.size());
        const std::uint32_t id = table.insert(voxelKey(v[0], v[1], v[2]), next);
        if (id == next) coords.push_back(v);
        voxel[m] = id;
    }
    // 2. Their connected parts (26-neighbourhood).
    std::vector<std::int32_t> part(coords.size(), -1);
    std::int32_t parts = 0;
    for (std::size_t start = 0; start < coords.size(); ++start) {
        if (part[start] >= 0) continue;
        std::vector<std::uint32_t> frontier{static_cast<std::uint32_t>(start)};
        part[start] = parts;
        while (!frontier.empty()) {
            const std::array<std::int64_t, 3> c = coords[frontier.back()];
            frontier.pop_back();
            forEachNeighbour(table, c, [&](std::uint32_t id) {
                if (part[id] >= 0) return;
                part[id] = parts;
                frontier.push_back(id);
            });
        }
        ++parts;
    }
    // 3. Each part's bounding box in L from its members; the thin, tall ones are columns.
    std::vector<Vec3f> lo(static_cast<std::size_t>(parts), Vec3f::Constant(1e30f));
    std::vector<Vec3f> hi(static_cast<std::size_t>(parts), Vec3f::Constant(-1e30f));
    for (std::size_t m = 0; m < members.size(); ++m) {
        if (voxel[m] < 0) continue;
        const auto k = static_cast<std::size_t>(part[static_cast<std::size_t>(voxel[m])]);
        lo[k] = lo[k].cwiseMin(points_L[members[m]]);
        hi[k] = hi[k].cwiseMax(points_L[members[m]]);
    }
    for (std::size_t m = 0; m < members.size(); ++m) {
        if (voxel[m] < 0) continue;
        const auto k = static_cast<std::size_t>(part[static_cast<std::size_t>(voxel[m])]);
        const Vec3f size = hi[k] - lo[k];
        column[m] = size.x() <= max_footprint_m && size.y() <= max_footprint_m && size.z() >= min_height_m;
    }
    return column;
}

}  // namespace vdbmap
