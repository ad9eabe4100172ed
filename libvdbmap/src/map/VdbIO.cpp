// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/map/VdbIO.h"

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include "vdbmap/Error.h"
#include "vdbmap/Version.h"
#include "vdbmap/io/AtomicFile.h"
#include "vdbmap/map/VoxelMap.h"

namespace vdbmap {

void writeMapVdb(const std::filesystem::path& path, const VoxelMap& map) {
    openvdb::GridPtrVec grids;
    // Shallow copies share the trees; the names and classes are those of DATA.md.
    openvdb::FloatGrid::Ptr surface = map.tsdf()->copy();
    surface->setName("surface");
    surface->setGridClass(openvdb::GRID_LEVEL_SET);
    surface->setSaveFloatAsHalf(false);
    grids.push_back(surface);
    openvdb::FloatGrid::Ptr weight = map.weight()->copy();
    weight->setName("weight");
    grids.push_back(weight);
    for (const auto& [name, grid] : map.extraGrids()) {
        openvdb::GridBase::Ptr g = grid->copyGrid();
        g->setName(name);
        grids.push_back(g);
    }
    openvdb::MetaMap meta(map.metadata());
    meta.insertMeta("creator", openvdb::StringMetadata(std::string("vdbmap ") + versionString()));
    if (!meta["voxel_size_m"]) meta.insertMeta("voxel_size_m", openvdb::DoubleMetadata(map.voxelSize()));
    AtomicFile out(path);
    try {
        openvdb::io::File file(out.tempPath().string());
        file.write(grids, meta);
        file.close();
    } catch (const openvdb::Exception& e) {
        throw IoError("writeMapVdb: cannot write '" + path.string() + "': " + e.what());
    }
    out.commit();
}

}  // namespace vdbmap
