// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <openvdb/openvdb.h>
#include <openvdb/tree/ValueAccessor.h>

#include <cstdint>

#include "map/FastReciprocal.h"
#include "vdbmap/map/TsdfVoxel.h"

namespace vdbmap::detail {

/// Running weighted average of one observed packed voxel (paper Sec. 4.2):
/// D' = (W D + w d) / (W + w), W' = min(W + w, max_weight). The division is a refined
/// reciprocal estimate (FastReciprocal.h): its error, ~1e-7 relative, is far below the 16-bit
/// sdf quantum.
inline void observedAverage(std::uint32_t& value, float sdf_m, float w, float max_weight,
                            const TsdfCodec& codec) {
    const float W = codec.weight(value);
    const float D = codec.sdf(value);
    const float sum = W + w;
    value = codec.encode((W * D + w * sdf_m) * fastReciprocal(sum),
                         sum < max_weight ? sum : max_weight);
}

/// observedAverage, or for an unobserved voxel (its bit in the leaf's value mask off): it takes
/// d, w and is marked observed.
inline void runningAverage(std::uint32_t& value, std::uint64_t& mask_word, std::uint64_t bit,
                           float sdf_m, float w, float max_weight, const TsdfCodec& codec) {
    if (mask_word & bit) {
        observedAverage(value, sdf_m, w, max_weight, codec);
    } else {
        mask_word |= bit;
        value = codec.encode(sdf_m, w < max_weight ? w : max_weight);
    }
}

/// Raw access to the packed values and the value mask of the TSDF leaf that holds the last
/// voxel asked for. One per thread; the tree's topology must not change while it is in use
/// (the leaves are allocated before the voxel loop), so the accessor is the unregistered
/// kind. A voxel update costs a mask test and one 4-byte load and store instead of a tree
/// look-up and LeafBuffer's out-of-core checks. The state is plain values and __restrict
/// pointers (the codec is copied in) so that the compiler keeps it in registers across the
/// stores into the leaf.
class TsdfLeafCache {
public:
    using Accessor = openvdb::tree::ValueAccessor<TsdfTree, false>;

    explicit TsdfLeafCache(const TsdfCodec& codec) : codec_(codec) {}

    /// True if the leaf of `ijk` exists; then update() writes into it.
    bool fetch(const openvdb::Coord& ijk, Accessor& tree) {
        return enterLeaf(ijk & ~(TsdfLeaf::DIM - 1), tree);
    }

    /// fetch() for the leaf with this origin (a multiple of 8).
    bool enterLeaf(const openvdb::Coord& origin, Accessor& tree) {
        if (origin != origin_) {
            origin_ = origin;
            TsdfLeaf* leaf = tree.probeLeaf(openvdb::Coord(origin));
            if (leaf != nullptr) {
                values_ = leaf->buffer().data();
                mask_ = &leaf->getValueMask().template getWord<std::uint64_t>(0);
            } else {
                values_ = nullptr;
                mask_ = nullptr;
            }
        }
        return values_ != nullptr;
    }

    /// Running weighted average of one voxel of the fetched leaf (paper Sec. 4.2):
    /// D' = (W D + w d) / (W + w), W' = min(W + w, max_weight); an unobserved voxel takes d, w.
    void update(const openvdb::Coord& ijk, float sdf_m, float w, float max_weight) {
        updateAt(TsdfLeaf::coordToOffset(ijk), sdf_m, w, max_weight);
    }

    /// update() by the voxel's offset in the fetched leaf.
    void updateAt(unsigned off, float sdf_m, float w, float max_weight) {
        runningAverage(values_[off], mask_[off >> 6], std::uint64_t{1} << (off & 63), sdf_m, w,
                       max_weight, codec_);
    }

    /// Like update(), but only for voxels that are already observed. Returns whether it was.
    bool updateObserved(const openvdb::Coord& ijk, float sdf_m, float w, float max_weight) {
        const openvdb::Index off = TsdfLeaf::coordToOffset(ijk);
        if (!(mask_[off >> 6] & (std::uint64_t{1} << (off & 63)))) return false;
        update(ijk, sdf_m, w, max_weight);
        return true;
    }

private:
    const TsdfCodec codec_;
    openvdb::Coord origin_ = openvdb::Coord::max();
    std::uint32_t* __restrict values_ = nullptr;
    std::uint64_t* __restrict mask_ = nullptr;
};

}  // namespace vdbmap::detail
