// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace vdbmap {

/// Voxel keys and a hash table of them for the voxels of one scan (ScanObjects, JoinedObjects):
/// voxelKey packs integer voxel coordinates, 21 bits per axis around the origin (+-2^20
/// voxels: +-200 km at 0.2 m); a key plus voxelKey(dx, dy, dz) - voxelKey(0, 0, 0) is the
/// key of the neighbour at (dx, dy, dz) (the fields never wrap).

/// Open-addressing hash of voxel keys to voxel indices (a key and its value in one slot: one
/// cache miss a probe).
class VoxelTable {
public:
    explicit VoxelTable(std::size_t expected) {
        std::size_t n = 64;  // at least one block of slots (hash)
        while (n < 2 * expected) n <<= 1;
        slots_.assign(n, Slot{kEmptyKey, 0});
        mask_ = n - 1;
    }
    /// The index of `key`, inserting `next` if absent (returns it).
    std::uint32_t insert(std::uint64_t key, std::uint32_t next) {
        std::size_t h = hash(key);
        while (slots_[h].key != kEmptyKey) {
            if (slots_[h].key == key) return slots_[h].value;
            h = (h + 1) & mask_;
        }
        slots_[h] = Slot{key, next};
        return next;
    }
    /// The index of `key` or -1.
    std::int64_t find(std::uint64_t key) const {
        std::size_t h = hash(key);
        while (slots_[h].key != kEmptyKey) {
            if (slots_[h].key == key) return slots_[h].value;
            h = (h + 1) & mask_;
        }
        return -1;
    }

private:
    static constexpr std::uint64_t kEmptyKey = ~std::uint64_t(0);
    struct Slot {
        std::uint64_t key;
        std::uint32_t value;
    };
    /// Blocks of 4 x 4 x 4 voxels hash to one run of 64 slots (16 B each), and the voxel's
    /// place in its block picks the slot: a scan's points, which come in spatial order, probe
    /// a few cache lines at a time instead of one random line per voxel.
    std::size_t hash(std::uint64_t k) const {
        const std::uint64_t m = (std::uint64_t(1) << 21) - 1;
        const std::uint64_t x = k >> 42, y = (k >> 21) & m, z = k & m;
        std::uint64_t b = ((x >> 2) << 42) | ((y >> 2) << 21) | (z >> 2);
        b ^= b >> 33;
        b *= 0xff51afd7ed558ccdULL;
        b ^= b >> 33;
        return static_cast<std::size_t>((b << 6) | ((x & 3) << 4) | ((y & 3) << 2) | (z & 3)) & mask_;
    }
    std::vector<Slot> slots_;
    std::size_t mask_ = 0;
};

constexpr int kVoxelKeyBits = 21;
constexpr std::int64_t kVoxelKeyOffset = std::int64_t(1) << (kVoxelKeyBits - 1);

inline std::uint64_t voxelKey(std::int64_t x, std::int64_t y, std::int64_t z) {
    const std::uint64_t m = (std::uint64_t(1) << kVoxelKeyBits) - 1;
    return ((static_cast<std::uint64_t>(x + kVoxelKeyOffset) & m) << (2 * kVoxelKeyBits)) |
           ((static_cast<std::uint64_t>(y + kVoxelKeyOffset) & m) << kVoxelKeyBits) |
           (static_cast<std::uint64_t>(z + kVoxelKeyOffset) & m);
}

/// The integer coordinates of the voxel of edge 1 / inv_voxel_m holding (x, y, z).
inline std::array<std::int64_t, 3> voxelCoords(float x, float y, float z, float inv_voxel_m) {
    return {static_cast<std::int64_t>(std::floor(x * inv_voxel_m)), static_cast<std::int64_t>(std::floor(y * inv_voxel_m)),
            static_cast<std::int64_t>(std::floor(z * inv_voxel_m))};
}

/// Calls visit(index) for each voxel of `table` in the 26-neighbourhood of the voxel at `c`
/// (c itself included): the step of a flood over a scan's voxels (JoinedObjects, StaticColumns).
template <typename Visit>
void forEachNeighbour(const VoxelTable& table, const std::array<std::int64_t, 3>& c, Visit&& visit) {
    for (int dz = -1; dz <= 1; ++dz) {
        for (int dy = -1; dy <= 1; ++dy) {
            for (int dx = -1; dx <= 1; ++dx) {
                const std::int64_t id = table.find(voxelKey(c[0] + dx, c[1] + dy, c[2] + dz));
                if (id >= 0) visit(static_cast<std::uint32_t>(id));
            }
        }
    }
}

}  // namespace vdbmap
