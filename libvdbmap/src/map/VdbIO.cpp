// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/map/VdbIO.h"

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <fstream>

#include "io/FileUtil.h"
#include "vdbmap/Error.h"
#include "vdbmap/Version.h"
#include "vdbmap/io/AtomicFile.h"
#include "vdbmap/map/VoxelMap.h"

namespace vdbmap {
namespace {

/// openvdb::io::File::write writes through a std::ofstream whose state it never checks, so a
/// full disk would give a truncated map.vdb. This writes the same seekable archive (what
/// File::write does) into a stream we own and check.
class CheckedVdbWriter : public openvdb::io::Archive {
public:
    void writeTo(std::ostream& os, const openvdb::GridPtrVec& grids,
                 const openvdb::MetaMap& meta) const {
        Archive::write(os, grids, /*seekable=*/true, meta);
    }
};

}  // namespace

openvdb::GridPtrVec mapVdbGrids(const VoxelMap& map) {
    openvdb::GridPtrVec grids;
    // Plain float grids decoded from the packed TSDF; the names and classes are those of DATA.md.
    openvdb::FloatGrid::Ptr surface = map.surfaceGrid();
    surface->setSaveFloatAsHalf(false);
    grids.push_back(surface);
    grids.push_back(map.weightGrid());
    // The adaptive truncation, once an integrator has finalized the map (it sets the metadata).
    if (const auto eps_max = map.metadata().getMetadata<openvdb::DoubleMetadata>("truncation_max_m")) {
        grids.push_back(map.truncationGrid(static_cast<float>(eps_max->value())));
    }
    for (const auto& [name, grid] : map.extraGrids()) {
        // A new grid object sharing the (unchanged) tree: only its name is set.
        openvdb::GridBase::Ptr g = openvdb::ConstPtrCast<openvdb::GridBase>(grid->copyGrid());
        g->setName(name);
        grids.push_back(g);
    }
    return grids;
}

openvdb::MetaMap mapVdbMetadata(const VoxelMap& map) {
    openvdb::MetaMap meta(map.metadata());
    meta.insertMeta("creator", openvdb::StringMetadata(std::string("vdbmap ") + versionString()));
    if (!meta["voxel_size_m"]) meta.insertMeta("voxel_size_m", openvdb::DoubleMetadata(map.voxelSize()));
    return meta;
}

void writeVdbGrids(const std::filesystem::path& path, const openvdb::GridPtrVec& grids,
                   const openvdb::MetaMap& meta) {
    AtomicFile out(path);
    std::ofstream stream = detail::openOutput(out.tempPath(), path);
    try {
        CheckedVdbWriter().writeTo(stream, grids, meta);
    } catch (const openvdb::Exception& e) {
        throw IoError("writeMapVdb: cannot write '" + path.string() + "': " + e.what());
    }
    detail::closeOutput(stream, path);  // a full disk or a file-size limit is an IoError here
    out.commit();
}

void writeMapVdb(const std::filesystem::path& path, const VoxelMap& map) {
    writeVdbGrids(path, mapVdbGrids(map), mapVdbMetadata(map));
}

}  // namespace vdbmap
