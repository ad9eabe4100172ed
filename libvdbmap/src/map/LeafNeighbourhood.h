// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <openvdb/openvdb.h>
#include <openvdb/tree/ValueAccessor.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "map/TsdfLeafCache.h"
#include "vdbmap/core/Bits.h"
#include "vdbmap/map/TsdfVoxel.h"

namespace vdbmap::detail {

/// The TSDF leaves around an 8^3 block that its points' updates can reach: a cube of
/// (2 R + 1)^3 leaves centred on the block's own leaf, one bit each.
struct LeafNeighbourhood {
    int radius = 1;         ///< R, in leaves
    int side = 3;           ///< 2 R + 1
    std::size_t words = 1;  ///< 64-bit words per block

    /// `reach_vox`: how far (voxels) an update can land from its point's block.
    explicit LeafNeighbourhood(int reach_vox)
        : radius(std::max(1, (reach_vox + 7) / 8)),
          side(2 * radius + 1),
          words((static_cast<std::size_t>(side) * side * side + 63) / 64) {
        // slab_[a][(lo, hi)]: the bits of the leaves whose offset along axis a is in [lo, hi].
        for (int a = 0; a < 3; ++a) {
            slab_[a].assign(static_cast<std::size_t>(side * side) * words, 0);
            for (int lo = -radius; lo <= radius; ++lo)
                for (int hi = lo; hi <= radius; ++hi) {
                    std::uint64_t* m = slab_[a].data() + slabOffset(lo, hi);
                    for (int u = -radius; u <= radius; ++u)
                        for (int v = -radius; v <= radius; ++v)
                            for (int c = lo; c <= hi; ++c) {
                                const std::size_t b =
                                    a == 0 ? bit(c, u, v) : (a == 1 ? bit(u, c, v) : bit(u, v, c));
                                m[b / 64] |= std::uint64_t{1} << (b % 64);
                            }
                }
        }
    }

    std::size_t size() const { return static_cast<std::size_t>(side) * side * side; }
    /// Bit of the leaf at block-relative leaf offset (dx, dy, dz), each in [-R, R].
    std::size_t bit(int dx, int dy, int dz) const {
        return static_cast<std::size_t>(((dx + radius) * side + (dy + radius)) * side + (dz + radius));
    }
    /// Origin (voxels) of the leaf of bit `b` around block `bc`.
    openvdb::Coord origin(const openvdb::Coord& bc, std::size_t b) const {
        const int i = static_cast<int>(b);
        const int dz = i % side - radius, dy = (i / side) % side - radius,
                  dx = i / (side * side) - radius;
        return openvdb::Coord((bc.x() + dx) * 8, (bc.y() + dy) * 8, (bc.z() + dz) * 8);
    }
    /// Sets in `bits` the leaves of the box [x0, x1] x [y0, y1] x [z0, z1] (block-relative leaf
    /// offsets, each clipped to [-R, R] by the caller; an empty range sets none): the AND of
    /// three slabs, a word at a time.
    void markBox(std::uint64_t* bits, int x0, int x1, int y0, int y1, int z0, int z1) const {
        if (x0 > x1 || y0 > y1 || z0 > z1) return;
        const std::uint64_t* mx = slab_[0].data() + slabOffset(x0, x1);
        const std::uint64_t* my = slab_[1].data() + slabOffset(y0, y1);
        const std::uint64_t* mz = slab_[2].data() + slabOffset(z0, z1);
        for (std::size_t w = 0; w < words; ++w) bits[w] |= mx[w] & my[w] & mz[w];
    }

private:
    std::size_t slabOffset(int lo, int hi) const {
        return static_cast<std::size_t>((lo + radius) * side + (hi + radius)) * words;
    }
    std::vector<std::uint64_t> slab_[3];
};

using vdbmap::forEachSetBit;

/// The sink of integrateRay (map/RayUpdate.h) for the points of one block: the raw values and
/// masks of the leaves of the block's neighbourhood, resolved once per block (`load`) from the
/// bits of the leaves its segments cross, so that a leaf crossing in the voxel walk is a table
/// look-up instead of a tree probe. Each update is the running average of paper Sec. 4.2.
class BlockLeafTable {
public:
    BlockLeafTable(const LeafNeighbourhood& hood, const TsdfCodec& codec, float max_weight)
        : hood_(hood), codec_(codec), max_weight_(max_weight), entries_(hood.size()) {}

    /// Resolves the leaves named by `bits` around block `bc` (they exist: phase 3a allocated
    /// them); the others are absent. Stamps each with `stamp` (the leaf's transientData: the
    /// last scan that could update it). Prefetches the block's own leaf.
    void load(const openvdb::Coord& bc, const std::uint64_t* bits, TsdfLeafCache::Accessor& acc,
              std::uint32_t stamp) {
        std::fill(entries_.begin(), entries_.end(), Entry{});
        bc_ = bc;
        forEachSetBit(bits, hood_.words, [&](std::size_t b) {
            TsdfLeaf* leaf = acc.probeLeaf(hood_.origin(bc, b));
            if (leaf != nullptr) {
                leaf->setTransientData(stamp);
                entries_[b] = {leaf->buffer().data(),
                               &leaf->getValueMask().template getWord<std::uint64_t>(0)};
            }
        });
        const Entry& own = entries_[hood_.bit(0, 0, 0)];
        if (own.values != nullptr) {
            constexpr std::size_t kLine = 64 / sizeof(std::uint32_t);
            for (std::size_t i = 0; i < TsdfLeaf::SIZE; i += kLine)
                __builtin_prefetch(own.values + i, 1);
        }
    }

    bool enterLeaf(const openvdb::Coord& origin) {
        const int dx = (origin.x() >> 3) - bc_.x(), dy = (origin.y() >> 3) - bc_.y(),
                  dz = (origin.z() >> 3) - bc_.z();
        const int r = hood_.radius;
        if (dx < -r || dx > r || dy < -r || dy > r || dz < -r || dz > r) {
            current_ = Entry{};
        } else {
            current_ = entries_[hood_.bit(dx, dy, dz)];
        }
        return current_.values != nullptr;
    }

    void update(int, int, int, unsigned offset, float sdf_m, float w) {
        runningAverage(current_.values[offset], current_.mask[offset >> 6],
                       std::uint64_t{1} << (offset & 63), sdf_m, w, max_weight_, codec_);
    }

private:
    struct Entry {
        std::uint32_t* values = nullptr;
        std::uint64_t* mask = nullptr;
    };
    const LeafNeighbourhood& hood_;
    const TsdfCodec codec_;
    const float max_weight_;
    std::vector<Entry> entries_;
    openvdb::Coord bc_;
    Entry current_;
};

}  // namespace vdbmap::detail
