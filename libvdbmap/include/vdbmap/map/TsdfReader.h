// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "vdbmap/map/VdbTrees.h"
#include <openvdb/tree/ValueAccessor.h>

#include <cstdint>

#include "vdbmap/map/CompactTsdf.h"
#include "vdbmap/map/VoxelMap.h"

namespace vdbmap {

/// Random read access to the packed TSDF of a VoxelMap, whichever store holds a leaf (the dense
/// working tree or the CompactTsdf). One per thread; it caches the last leaf, so neighbouring
/// look-ups (marching cubes corners) cost a mask test and a load. The map must not change
/// while a reader is in use.
class TsdfReader {
public:
    explicit TsdfReader(const VoxelMap& map)
        : compact_(map.compactTsdf()),
          working_(map.workingTsdf()->tree()),
          topology_(map.compactTsdf().topology()),
          has_working_(map.workingTsdf()->tree().leafCount() > 0),
          background_(map.codec().background()) {
        leaf_.origin = openvdb::Coord::max();
    }

    /// The packed value of voxel `ijk`; false (and the background value) if it is unobserved.
    bool probe(const openvdb::Coord& ijk, std::uint32_t& packed) {
        const openvdb::Coord origin(ijk.x() & ~7, ijk.y() & ~7, ijk.z() & ~7);
        if (origin != leaf_.origin) enter(origin);
        const openvdb::Index offset = TsdfLeaf::coordToOffset(ijk);
        if (leaf_.mask == nullptr || !leaf_.observed(offset)) {
            packed = background_;
            return false;
        }
        packed = leaf_.value(offset);
        return true;
    }

private:
    void enter(const openvdb::Coord& origin) {
        if (has_working_) {
            if (const TsdfLeaf* dense = working_.probeConstLeaf(origin)) {
                leaf_ = TsdfLeafView::of(*dense);
                return;
            }
        }
        if (const CompactTsdf::TopologyLeaf* compact = topology_.probeConstLeaf(origin)) {
            leaf_ = compact_.view(*compact);
            return;
        }
        leaf_ = TsdfLeafView{};
        leaf_.origin = origin;
    }

    const CompactTsdf& compact_;
    openvdb::tree::ValueAccessor<const TsdfTree, false> working_;
    openvdb::tree::ValueAccessor<const CompactTsdf::TopologyTree, false> topology_;
    const bool has_working_;
    const std::uint32_t background_;
    TsdfLeafView leaf_;
};

}  // namespace vdbmap
