// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "vdbmap/map/VdbTrees.h"
#include <openvdb/tree/ValueAccessor.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "vdbmap/core/Bits.h"
#include "vdbmap/map/TsdfVoxel.h"

namespace vdbmap {

/// A read-only view of one 8^3 TSDF leaf, dense or compact: its observed-voxel mask (8 words
/// of 64 bits, OpenVDB's voxel offset order) and either its 512 packed values (`dense`, a leaf
/// of the working tree) or only the observed ones in mask order (`values` + `prefix`, a leaf of
/// the CompactTsdf). `mask == nullptr`: no such leaf.
struct TsdfLeafView {
    openvdb::Coord origin;
    const std::uint64_t* mask = nullptr;
    const std::uint32_t* dense = nullptr;
    const std::uint32_t* values = nullptr;
    const std::uint16_t* prefix = nullptr;

    /// The view of a dense leaf.
    static TsdfLeafView of(const TsdfLeaf& leaf) {
        TsdfLeafView v;
        v.origin = leaf.origin();
        v.mask = words(leaf.getValueMask());
        v.dense = leaf.buffer().data();
        return v;
    }
    /// The 64-bit words of an OpenVDB node mask (its only data member).
    static const std::uint64_t* words(const TsdfLeaf::NodeMaskType& m) {
        static_assert(sizeof(TsdfLeaf::NodeMaskType) == TsdfLeaf::SIZE / 8, "NodeMask layout");
        return reinterpret_cast<const std::uint64_t*>(&m);
    }

    bool observed(openvdb::Index offset) const {
        return (mask[offset >> 6] >> (offset & 63)) & 1u;
    }
    /// Position of an observed voxel among the leaf's observed voxels (compact leaves).
    unsigned rank(openvdb::Index offset) const {
        const std::uint64_t below = mask[offset >> 6] & ((std::uint64_t{1} << (offset & 63)) - 1);
        return prefix[offset >> 6] + static_cast<unsigned>(__builtin_popcountll(below));
    }
    /// visit(offset) for each observed voxel, in offset order.
    template <typename Visit>
    void forEachObserved(Visit&& visit) const {
        forEachSetBit(mask, TsdfLeaf::NodeMaskType::WORD_COUNT,
                      [&](std::size_t i) { visit(static_cast<openvdb::Index>(i)); });
    }
    /// The packed value of an observed voxel (offset in the leaf).
    std::uint32_t value(openvdb::Index offset) const {
        return dense != nullptr ? dense[offset] : values[rank(offset)];
    }
};

/// The at-rest store of the TSDF: the packed values (TsdfVoxel.h) of the OBSERVED voxels only.
/// Its topology is an OpenVDB mask tree with the TSDF's 8^3 leaves, whose leaf mask is the set of
/// observed voxels; the leaf's transientData names a slot holding those voxels' values in mask
/// order, and a voxel's value is values[prefix[word] + popcount(mask word below its bit)] (the
/// "value-on index" layout of NanoVDB's index grids).
/// Why: a dense leaf of 4-byte values costs 2 KiB whatever its fill, and a thin truncation band
/// fills a leaf to ~16 % (81 of 512 voxels on the benchmark street): 26 B per observed voxel
/// before any tree overhead. Here the same voxel costs 4 B plus its share of the leaf's mask
/// and slot. The integrator works on dense leaves (the working tree of VoxelMap) and moves the
/// leaves it has not touched for a while here, losslessly.
class CompactTsdf {
public:
    /// Internal nodes of 16^3 and 8^3 children (the standard MaskTree has 32^3 and 16^3): with
    /// 0.10 m voxels ~4 KiB per 6.4 m cube (and ~33 KiB per 102 m cube above) instead of ~33 KiB
    /// per 12.8 m cube (and ~260 KiB per 410 m cube); on a sparse band the standard nodes cost
    /// more than the values. The 8^3 leaves are the TSDF's.
    using TopologyTree = openvdb::tree::Tree4<openvdb::ValueMask, 4, 3, 3>::Type;
    using TopologyLeaf = TopologyTree::LeafNodeType;
    using Mask = TsdfLeaf::NodeMaskType;
    /// transientData of a topology leaf without a slot: erased while its leaf is in the working
    /// tree (the topology leaf is kept for the leaf's return; prune() removes the rest).
    static constexpr std::uint32_t kNoSlot = 0xFFFFFFFFu;

    /// The observed values of one leaf.
    struct Slot {
        std::unique_ptr<std::uint32_t[]> values;
        std::array<std::uint16_t, Mask::WORD_COUNT> prefix{};  ///< observed voxels before word w
        std::uint16_t count = 0;
    };

    CompactTsdf();
    CompactTsdf(const CompactTsdf&) = delete;
    CompactTsdf& operator=(const CompactTsdf&) = delete;

    /// The observed values of a dense leaf (thread-safe, no state).
    static Slot encode(const Mask& observed, const std::uint32_t* dense);
    /// Stores an encoded leaf (not thread-safe); replaces what the leaf held. An empty slot
    /// (no observed voxel) erases the leaf instead.
    void insert(const openvdb::Coord& origin, const Mask& observed, Slot slot);
    /// Removes the leaf's values (not thread-safe); no-op if absent.
    void erase(const openvdb::Coord& origin);
    /// Drops the topology leaves of erased leaves.
    void prune();

    /// The leaf with this origin (multiple of 8), or a view with mask == nullptr.
    TsdfLeafView view(const openvdb::Coord& origin) const;
    /// view() of a topology leaf of this store.
    TsdfLeafView view(const TopologyLeaf& leaf) const;
    /// Writes the leaf's observed values into `dense` and its mask into `observed`; the other
    /// dense values are left as they are. Thread-safe.
    static void decode(const TsdfLeafView& leaf, Mask& observed, std::uint32_t* dense);
    /// Mutable value of an observed voxel, or nullptr (unobserved or absent). The topology must
    /// not change while the pointer is used.
    std::uint32_t* findObserved(const openvdb::Coord& ijk,
                                openvdb::tree::ValueAccessor<const TopologyTree, false>& acc);

    const TopologyTree& topology() const { return topology_; }
    /// Leaves stored and observed voxels stored.
    std::size_t leafCount() const { return leaf_count_; }
    std::size_t voxelCount() const { return voxel_count_; }
    /// Bytes: the topology tree, the slot table and the values.
    std::size_t memoryBytes() const;
    /// All views, in topology order (for parallel loops).
    std::vector<TsdfLeafView> views() const;
    void clear();

private:
    TopologyTree topology_;
    /// For the serial insert / erase (leaves come in spatially coherent order).
    openvdb::tree::ValueAccessor<TopologyTree> acc_;
    std::vector<Slot> slots_;
    std::vector<std::uint32_t> free_slots_;
    std::size_t leaf_count_ = 0;
    std::size_t voxel_count_ = 0;
};

}  // namespace vdbmap
