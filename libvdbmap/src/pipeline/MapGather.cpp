// SPDX-License-Identifier: Apache-2.0
#include "pipeline/MapGather.h"

#include <openvdb/io/Stream.h>

#include <sstream>
#include <vector>

#include "vdbmap/Error.h"
#include "vdbmap/map/VdbIO.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/pipeline/Tiling.h"

namespace vdbmap::detail {
namespace {

std::int32_t floorDiv(std::int32_t a, std::int32_t b) {
    return a >= 0 ? a / b : -((-a + b - 1) / b);
}

/// Removes the leaves of `grid` whose tile `owns` rejects; returns how many.
std::size_t keepOwnedLeaves(openvdb::FloatGrid& grid, const TileGrid& tiles,
                            const std::function<bool(int, int)>& owns) {
    using Leaf = openvdb::FloatTree::LeafNodeType;
    auto& tree = grid.tree();
    std::vector<openvdb::Coord> drop;
    for (auto it = tree.cbeginLeaf(); it; ++it) {
        const openvdb::Coord o = it->origin();
        const int ix = floorDiv(o[tiles.groundAxis(0)], tiles.tileVoxels());
        const int iy = floorDiv(o[tiles.groundAxis(1)], tiles.tileVoxels());
        if (!owns(ix, iy)) drop.push_back(o);
    }
    for (const openvdb::Coord& o : drop) {
        delete tree.stealNode<Leaf>(o, tree.background(), false);
    }
    return drop.size();
}

}  // namespace

std::string mapPart(const VoxelMap& map, const TileGrid& grid,
                    const std::function<bool(int, int)>& owns, std::size_t* dropped_leaves) {
    openvdb::GridPtrVec grids = mapVdbGrids(map);
    std::size_t dropped = 0;
    for (const openvdb::GridBase::Ptr& g : grids) {
        const auto f = openvdb::GridBase::grid<openvdb::FloatGrid>(g);
        if (!f) {
            throw Error("distributed map.vdb: grid '" + g->getName() + "' is a " + g->type() +
                        ", only float grids can be gathered");
        }
        const std::size_t n = keepOwnedLeaves(*f, grid, owns);
        if (f->getName() == "surface") dropped = n;
    }
    if (dropped_leaves) *dropped_leaves = dropped;
    std::ostringstream os(std::ios::binary);
    openvdb::io::Stream(os).write(grids, mapVdbMetadata(map));
    return os.str();
}

void MapAssembler::add(std::string&& part) {
    openvdb::GridPtrVecPtr grids;
    openvdb::MetaMap::Ptr meta;
    try {
        std::istringstream is(std::move(part), std::ios::binary);
        openvdb::io::Stream stream(is);
        grids = stream.getGrids();
        meta = stream.getMetadata();
    } catch (const openvdb::Exception& e) {
        throw IoError(std::string("distributed map.vdb: a process sent an unreadable part: ") +
                      e.what());
    }
    if (!meta_) meta_ = meta;
    for (const openvdb::GridBase::Ptr& g : *grids) {
        openvdb::GridBase::Ptr base;
        for (const auto& mine : grids_)
            if (mine->getName() == g->getName()) base = mine;
        if (!base) {
            grids_.push_back(g);
            continue;
        }
        const auto to = openvdb::GridBase::grid<openvdb::FloatGrid>(base);
        const auto from = openvdb::GridBase::grid<openvdb::FloatGrid>(g);
        if (!to || !from) throw IoError("distributed map.vdb: grid '" + g->getName() + "' is not a float grid");
        // The parts hold disjoint leaves: merging moves them over.
        to->tree().merge(from->tree());
    }
}

void MapAssembler::write(const std::filesystem::path& path) const {
    writeVdbGrids(path, grids_, meta_ ? *meta_ : openvdb::MetaMap());
}

std::size_t MapAssembler::activeVoxels() const {
    for (const auto& g : grids_)
        if (g->getName() == "surface") return static_cast<std::size_t>(g->activeVoxelCount());
    return 0;
}

}  // namespace vdbmap::detail
