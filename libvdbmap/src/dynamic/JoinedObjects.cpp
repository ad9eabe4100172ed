// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/dynamic/JoinedObjects.h"

#include <array>
#include <cmath>
#include <unordered_map>

namespace vdbmap {

namespace {

std::uint64_t keyOf(const Vec3f& p, float inv_voxel) {
    // 21 bits per axis around the origin: +-2^20 voxels, +-200 km at 0.2 m.
    const auto field = [](float v) { return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v)) + (1 << 20)) & 0x1fffff; };
    return (field(p.x() * inv_voxel) << 42) | (field(p.y() * inv_voxel) << 21) | field(p.z() * inv_voxel);
}

}  // namespace

std::vector<std::uint8_t> moverOfJoined(const std::vector<Vec3f>& points_L, const std::vector<std::size_t>& members,
                                        const std::vector<std::uint8_t>& seed, const std::vector<std::uint8_t>& kept,
                                        float voxel_m) {
    std::vector<std::uint8_t> reached(members.size(), 0);
    const float inv = 1.0f / voxel_m;
    // 1. The voxels holding members not kept, and which of them hold a seed.
    std::unordered_map<std::uint64_t, std::uint32_t> voxel_of_key;
    std::vector<std::array<std::int64_t, 3>> coords;
    std::vector<std::uint32_t> voxel(members.size(), 0);
    std::vector<std::uint8_t> open;  // per voxel: reached by the flood
    std::vector<std::uint32_t> frontier;
    for (std::size_t m = 0; m < members.size(); ++m) {
        if (kept[m]) continue;
        const Vec3f& p = points_L[members[m]];
        const std::uint64_t key = keyOf(p, inv);
        const auto [it, fresh] = voxel_of_key.emplace(key, static_cast<std::uint32_t>(coords.size()));
        if (fresh) {
            coords.push_back({static_cast<std::int64_t>(std::floor(p.x() * inv)), static_cast<std::int64_t>(std::floor(p.y() * inv)),
                              static_cast<std::int64_t>(std::floor(p.z() * inv))});
            open.push_back(0);
        }
        voxel[m] = it->second;
        if (seed[m] && !open[it->second]) {
            open[it->second] = 1;
            frontier.push_back(it->second);
        }
    }
    // 2. Flood from the seeds over the 26-neighbourhood of those voxels.
    while (!frontier.empty()) {
        const std::array<std::int64_t, 3> c = coords[frontier.back()];
        frontier.pop_back();
        for (int dz = -1; dz <= 1; ++dz) {
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dx = -1; dx <= 1; ++dx) {
                    const Vec3f centre(static_cast<float>(c[0] + dx) + 0.5f, static_cast<float>(c[1] + dy) + 0.5f,
                                       static_cast<float>(c[2] + dz) + 0.5f);
                    const auto it = voxel_of_key.find(keyOf(centre, 1.0f));
                    if (it == voxel_of_key.end() || open[it->second]) continue;
                    open[it->second] = 1;
                    frontier.push_back(it->second);
                }
            }
        }
    }
    // 3. The members not kept in reached voxels.
    for (std::size_t m = 0; m < members.size(); ++m) reached[m] = !kept[m] && open[voxel[m]];
    return reached;
}

}  // namespace vdbmap
