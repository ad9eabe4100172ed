// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/dynamic/JoinedObjects.h"

#include <array>

#include "vdbmap/dynamic/VoxelTable.h"

namespace vdbmap {

std::vector<std::uint8_t> moverOfJoined(const std::vector<Vec3f>& points_L, const std::vector<std::size_t>& members,
                                        const std::vector<std::uint8_t>& seed, const std::vector<std::uint8_t>& kept,
                                        float voxel_m) {
    std::vector<std::uint8_t> reached(members.size(), 0);
    const float inv = 1.0f / voxel_m;
    // 1. The voxels holding members not kept, and which of them hold a seed.
    VoxelTable table(members.size() + 16);
    std::vector<std::array<std::int64_t, 3>> coords;
    std::vector<std::uint32_t> voxel(members.size(), 0);
    std::vector<std::uint8_t> open;  // per voxel: reached by the flood
    std::vector<std::uint32_t> frontier;
    for (std::size_t m = 0; m < members.size(); ++m) {
        if (kept[m]) continue;
        const Vec3f& p = points_L[members[m]];
        const std::array<std::int64_t, 3> v = voxelCoords(p.x(), p.y(), p.z(), inv);
        const auto next = static_cast<std::uint32_t>(coords.size());
        const std::uint32_t id = table.insert(voxelKey(v[0], v[1], v[2]), next);
        if (id == next) {
            coords.push_back(v);
            open.push_back(0);
        }
        voxel[m] = id;
        if (seed[m] && !open[id]) {
            open[id] = 1;
            frontier.push_back(id);
        }
    }
    // 2. Flood from the seeds over the 26-neighbourhood of those voxels.
    while (!frontier.empty()) {
        const std::array<std::int64_t, 3> c = coords[frontier.back()];
        frontier.pop_back();
        forEachNeighbour(table, c, [&](std::uint32_t id) {
            if (open[id]) return;
            open[id] = 1;
            frontier.push_back(id);
        });
    }
    // 3. The members not kept in reached voxels.
    for (std::size_t m = 0; m < members.size(); ++m) reached[m] = !kept[m] && open[voxel[m]];
    return reached;
}

}  // namespace vdbmap
