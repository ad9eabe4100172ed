// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/map/CompactTsdf.h"

#include <openvdb/tools/Prune.h>
#include <openvdb/tree/ValueAccessor.h>

namespace vdbmap {

CompactTsdf::CompactTsdf() : topology_(false), acc_(topology_) {}

CompactTsdf::Slot CompactTsdf::encode(const Mask& observed, const std::uint32_t* dense) {
    Slot slot;
    std::uint16_t n = 0;
    for (openvdb::Index w = 0; w < Mask::WORD_COUNT; ++w) {
        slot.prefix[w] = n;
        n = static_cast<std::uint16_t>(n + __builtin_popcountll(observed.getWord<std::uint64_t>(w)));
    }
    slot.count = n;
    if (n == 0) return slot;
    slot.values.reset(new std::uint32_t[n]);
    std::uint32_t* out = slot.values.get();
    forEachSetBit(TsdfLeafView::words(observed), Mask::WORD_COUNT,
                  [&](std::size_t i) { *out++ = dense[i]; });
    return slot;
}

void CompactTsdf::insert(const openvdb::Coord& origin, const Mask& observed, Slot slot) {
    if (slot.count == 0) {
        erase(origin);
        return;
    }
    TopologyLeaf* leaf = acc_.probeLeaf(origin);
    if (leaf != nullptr && leaf->transientData() != kNoSlot) {  // replace the stored values
        Slot& old = slots_[leaf->transientData()];
        voxel_count_ -= old.count;
        old = std::move(slot);
    } else {
        if (leaf == nullptr) leaf = acc_.touchLeaf(origin);
        std::uint32_t index;
        if (!free_slots_.empty()) {
            index = free_slots_.back();
            free_slots_.pop_back();
            slots_[index] = std::move(slot);
        } else {
            index = static_cast<std::uint32_t>(slots_.size());
            slots_.push_back(std::move(slot));
        }
        leaf->setTransientData(index);
        ++leaf_count_;
    }
    voxel_count_ += slots_[leaf->transientData()].count;
    leaf->setValueMask(observed);
}

void CompactTsdf::erase(const openvdb::Coord& origin) {
    TopologyLeaf* leaf = acc_.probeLeaf(origin);
    if (leaf == nullptr || leaf->transientData() == kNoSlot) return;
    const std::uint32_t index = leaf->transientData();
    voxel_count_ -= slots_[index].count;
    slots_[index] = Slot{};
    free_slots_.push_back(index);
    --leaf_count_;
    // Keep the topology leaf (the working leaf comes back here later), without voxels.
    leaf->setValuesOff();
    leaf->setTransientData(kNoSlot);
}

void CompactTsdf::prune() { openvdb::tools::pruneInactive(topology_); }

TsdfLeafView CompactTsdf::view(const TopologyLeaf& leaf) const {
    if (leaf.transientData() == kNoSlot) {
        TsdfLeafView none;
        none.origin = leaf.origin();
        return none;
    }
    const Slot& slot = slots_[leaf.transientData()];
    TsdfLeafView v;
    v.origin = leaf.origin();
    v.mask = TsdfLeafView::words(leaf.getValueMask());
    v.values = slot.values.get();
    v.prefix = slot.prefix.data();
    return v;
}

TsdfLeafView CompactTsdf::view(const openvdb::Coord& origin) const {
    const TopologyLeaf* leaf = topology_.probeConstLeaf(origin);
    if (leaf == nullptr) {
        TsdfLeafView none;
        none.origin = origin;
        return none;
    }
    return view(*leaf);
}

void CompactTsdf::decode(const TsdfLeafView& leaf, Mask& observed, std::uint32_t* dense) {
    for (openvdb::Index w = 0; w < Mask::WORD_COUNT; ++w)
        observed.template getWord<std::uint64_t>(w) = leaf.mask[w];
    const std::uint32_t* in = leaf.values;
    leaf.forEachObserved([&](openvdb::Index i) { dense[i] = *in++; });
}

std::uint32_t* CompactTsdf::findObserved(
    const openvdb::Coord& ijk, openvdb::tree::ValueAccessor<const TopologyTree, false>& acc) {
    const TopologyLeaf* leaf = acc.probeConstLeaf(ijk);
    if (leaf == nullptr || leaf->transientData() == kNoSlot) return nullptr;
    const openvdb::Index offset = TopologyLeaf::coordToOffset(ijk);
    const TsdfLeafView v = view(*leaf);
    if (!v.observed(offset)) return nullptr;
    return slots_[leaf->transientData()].values.get() + v.rank(offset);
}

std::size_t CompactTsdf::memoryBytes() const {
    return static_cast<std::size_t>(topology_.memUsage()) + slots_.capacity() * sizeof(Slot) +
           free_slots_.capacity() * sizeof(std::uint32_t) + voxel_count_ * sizeof(std::uint32_t);
}

std::vector<TsdfLeafView> CompactTsdf::views() const {
    std::vector<TsdfLeafView> out;
    out.reserve(leaf_count_);
    for (auto it = topology_.cbeginLeaf(); it; ++it)
        if (it->transientData() != kNoSlot) out.push_back(view(*it));
    return out;
}

void CompactTsdf::clear() {
    acc_.clear();
    topology_.clear();
    slots_.clear();
    free_slots_.clear();
    leaf_count_ = 0;
    voxel_count_ = 0;
}

}  // namespace vdbmap
