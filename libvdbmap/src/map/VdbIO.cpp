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
