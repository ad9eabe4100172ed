// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <openvdb/openvdb.h>
#include <openvdb/tree/ValueAccessor.h>

namespace vdbmap::detail {

/// Raw access to the tsdf and weight values of the leaf that holds the last voxel asked for.
/// The two trees have the same topology. One per thread; the trees' topology must not change
/// while it is in use (the leaves are allocated before the voxel loop), so the accessors are
/// the unregistered kind. A voxel update then costs a mask test and two array accesses instead
/// of two tree look-ups and LeafBuffer's out-of-core checks.
class TsdfLeafCache {
public:
    using Tree = openvdb::FloatTree;
    using Leaf = Tree::LeafNodeType;

    TsdfLeafCache(Tree& tsdf, Tree& weight) : tsdf_(tsdf), weight_(weight) {}

    /// True if the leaf of `ijk` exists; then `sdf()`, `weight()` and the masks refer to it.
    bool fetch(const openvdb::Coord& ijk) {
        const openvdb::Coord origin = ijk & ~(Leaf::DIM - 1);
        if (origin != origin_) {
            origin_ = origin;
            Leaf* t = tsdf_.probeLeaf(origin);
            Leaf* w = weight_.probeLeaf(origin);
            if (t != nullptr && w != nullptr) {
                sdf_ = t->buffer().data();
                weight_values_ = w->buffer().data();
                sdf_mask_ = &t->getValueMask();
                weight_mask_ = &w->getValueMask();
            } else {
                sdf_ = nullptr;
            }
        }
        return sdf_ != nullptr;
    }

    /// Running weighted average of one voxel of the fetched leaf (paper Sec. 4.2):
    /// D' = (W D + w d) / (W + w), W' = min(W + w, max_weight); an unobserved voxel takes d, w.
    void update(const openvdb::Coord& ijk, float sdf_m, float w, float max_weight) {
        const openvdb::Index off = Leaf::coordToOffset(ijk);
        if (sdf_mask_->isOn(off)) {
            const float W = weight_values_[off];
            sdf_[off] = (W * sdf_[off] + w * sdf_m) / (W + w);
            weight_values_[off] = W + w < max_weight ? W + w : max_weight;
        } else {
            sdf_mask_->setOn(off);
            weight_mask_->setOn(off);
            sdf_[off] = sdf_m;
            weight_values_[off] = w < max_weight ? w : max_weight;
        }
    }

    /// Like update(), but only for voxels that are already observed. Returns whether it was.
    bool updateObserved(const openvdb::Coord& ijk, float sdf_m, float w, float max_weight) {
        const openvdb::Index off = Leaf::coordToOffset(ijk);
        if (!sdf_mask_->isOn(off)) return false;
        update(ijk, sdf_m, w, max_weight);
        return true;
    }

private:
    openvdb::tree::ValueAccessor<Tree, false> tsdf_;
    openvdb::tree::ValueAccessor<Tree, false> weight_;
    openvdb::Coord origin_ = openvdb::Coord::max();
    float* sdf_ = nullptr;
    float* weight_values_ = nullptr;
    openvdb::util::NodeMask<3>* sdf_mask_ = nullptr;
    openvdb::util::NodeMask<3>* weight_mask_ = nullptr;
};

}  // namespace vdbmap::detail
