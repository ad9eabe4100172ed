// SPDX-License-Identifier: Apache-2.0
#include "pipeline/MapGather.h"

#include <openvdb/io/Stream.h>

#include <cstdint>
#include <cstring>
#include <sstream>
#include <vector>

#include "vdbmap/Error.h"
#include "vdbmap/map/VdbIO.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/pipeline/Tiling.h"

namespace vdbmap::detail {
namespace {

/// Removes the leaves of `grid` whose tile `owns` rejects; returns how many.
std::size_t keepOwnedLeaves(openvdb::FloatGrid& grid, const TileGrid& tiles,
                            const std::function<bool(int, int)>& owns) {
    using Leaf = openvdb::FloatTree::LeafNodeType;
    auto& tree = grid.tree();
    std::vector<openvdb::Coord> drop;
    for (auto it = tree.cbeginLeaf(); it; ++it) {
        const auto [ix, iy] = tiles.tileOf(it->origin());
        if (!owns(ix, iy)) drop.push_back(it->origin());
    }
    for (const openvdb::Coord& o : drop) {
        delete tree.stealNode<Leaf>(o, tree.background(), false);
    }
    return drop.size();
}

// A part: [uint32 count] then per grid [uint64 length][stream bytes].
void appendBlock(std::string& out, const std::string& block) {
    const std::uint64_t n = block.size();
    out.append(reinterpret_cast<const char*>(&n), sizeof(n));
    out.append(block);
}

std::vector<std::string> splitPart(const std::string& part) {
    std::uint32_t count = 0;
    if (part.size() < sizeof(count)) throw IoError("distributed map.vdb: a process sent an empty part");
    std::memcpy(&count, part.data(), sizeof(count));
    std::vector<std::string> blocks;
    std::size_t at = sizeof(count);
    for (std::uint32_t i = 0; i < count; ++i) {
        std::uint64_t n = 0;
        if (part.size() < at + sizeof(n)) throw IoError("distributed map.vdb: a part is truncated");
        std::memcpy(&n, part.data() + at, sizeof(n));
        at += sizeof(n);
        if (part.size() - at < n) throw IoError("distributed map.vdb: a part is truncated");
        blocks.push_back(part.substr(at, n));
        at += n;
    }
    return blocks;
}

openvdb::GridBase::Ptr readGrid(const std::string& block, openvdb::MetaMap::Ptr* meta) {
    try {
        std::istringstream is(block, std::ios::binary);
        // Read now: with delayed loading the leaves would keep reading from a copy of this
        // stream after their grid was merged into another and freed (ASan: heap-use-after-free).
        openvdb::io::Stream stream(is, /*delayLoad=*/false);
        const openvdb::GridPtrVecPtr grids = stream.getGrids();
        if (meta) *meta = stream.getMetadata();
        if (!grids || grids->size() != 1) throw IoError("distributed map.vdb: a part's grid is missing");
        return grids->front();
    } catch (const openvdb::Exception& e) {
        throw IoError(std::string("distributed map.vdb: a process sent an unreadable part: ") +
                      e.what());
    }
}

}  // namespace

std::string mapPart(const VoxelMap& map, const TileGrid& grid,
                    const std::function<bool(int, int)>& owns, std::size_t* dropped_leaves) {
    const int count = mapVdbGridCount(map);
    std::string part;
    const std::uint32_t n = static_cast<std::uint32_t>(count);
    part.append(reinterpret_cast<const char*>(&n), sizeof(n));
    for (int i = 0; i < count; ++i) {
        const openvdb::GridBase::Ptr g = mapVdbGrid(map, i);
        const auto f = openvdb::GridBase::grid<openvdb::FloatGrid>(g);
        if (!f) {
            throw Error("distributed map.vdb: grid '" + g->getName() + "' is a " + g->type() +
                        ", only float grids can be gathered");
        }
        const std::size_t dropped = keepOwnedLeaves(*f, grid, owns);
        if (i == 0 && dropped_leaves) *dropped_leaves = dropped;
        std::ostringstream os(std::ios::binary);
        openvdb::io::Stream(os).write(openvdb::GridCPtrVec{g},
                                      i == 0 ? mapVdbMetadata(map) : openvdb::MetaMap());
        appendBlock(part, os.str());
    }
    return part;
}

void MapAssembler::add(std::string&& part) {
    std::vector<std::string> blocks = splitPart(part);
    part.clear();
    if (!parts_.empty() && blocks.size() != parts_.front().size()) {
        throw IoError("distributed map.vdb: processes sent " + std::to_string(parts_.front().size()) +
                      " and " + std::to_string(blocks.size()) + " grids");
    }
    parts_.push_back(std::move(blocks));
}

void MapAssembler::write(const std::filesystem::path& path) {
    if (parts_.empty()) return;
    openvdb::MetaMap::Ptr meta;
    readGrid(parts_.front().front(), &meta);  // the file metadata travels with grid 0
    const int count = static_cast<int>(parts_.front().size());
    auto merged = [&](int i) {
        openvdb::GridBase::Ptr base;
        for (std::vector<std::string>& blocks : parts_) {
            openvdb::GridBase::Ptr g = readGrid(blocks[static_cast<std::size_t>(i)], nullptr);
            std::string().swap(blocks[static_cast<std::size_t>(i)]);  // no longer needed
            if (!base) {
                base = g;
                continue;
            }
            const auto to = openvdb::GridBase::grid<openvdb::FloatGrid>(base);
            const auto from = openvdb::GridBase::grid<openvdb::FloatGrid>(g);
            if (!to || !from) {
                throw IoError("distributed map.vdb: grid '" + g->getName() + "' is not a float grid");
            }
            to->tree().merge(from->tree());  // disjoint leaves: they move over
        }
        if (i == 0) surface_voxels_ = static_cast<std::size_t>(base->activeVoxelCount());
        return base;
    };
    writeVdbGridsOneByOne(path, count, merged, meta ? *meta : openvdb::MetaMap());
}

}  // namespace vdbmap::detail
