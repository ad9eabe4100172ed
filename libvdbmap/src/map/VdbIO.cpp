// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/map/VdbIO.h"

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <functional>

#include "io/FileUtil.h"
#include "vdbmap/Error.h"
#include "vdbmap/Version.h"
#include "vdbmap/io/AtomicFile.h"
#include "vdbmap/map/VoxelMap.h"

namespace vdbmap {
namespace {

/// openvdb::io::File::write writes through a std::ofstream whose state it never checks, so a
/// full disk would give a truncated map.vdb. This writes the same seekable archive (what
/// File::write does) into a stream we own and check, one grid at a time.
class CheckedVdbWriter : public openvdb::io::Archive {
public:
    /// Archive::write's seekable archive with `count` grids made one at a time by `make(i)`
    /// and released once written, so that only one decoded grid is in memory (Archive::write's
    /// steps for grids of unique, non-empty names that share no tree).
    void writeOneByOne(std::ostream& os, int count,
                       const std::function<openvdb::GridBase::Ptr(int)>& make,
                       const openvdb::MetaMap& meta) const {
        openvdb::io::setDataCompression(os, compression());
        openvdb::io::setWriteGridStatsMetadata(os, isGridStatsMetadataEnabled());
        writeHeader(os, /*seekable=*/true);
        meta.writeMeta(os);
        const std::int32_t grids = count;
        os.write(reinterpret_cast<const char*>(&grids), sizeof(grids));
        for (int i = 0; i < count; ++i) {
            const openvdb::GridBase::Ptr grid = make(i);
            openvdb::io::GridDescriptor descriptor(grid->getName(), grid->type(),
                                                   grid->saveFloatAsHalf());
            writeGrid(descriptor, grid, os, /*seekable=*/true);
            openvdb::io::setDataCompression(os, compression());
        }
    }
};

}  // namespace

openvdb::GridBase::Ptr mapVdbGrid(const VoxelMap& map, int i,
                                  const std::function<bool(const openvdb::Coord&)>& keep) {
    const auto eps_max = map.metadata().getMetadata<openvdb::DoubleMetadata>("truncation_max_m");
    if (i == 0) {
        // Plain float grids decoded from the packed TSDF; names and classes are docs/DATA.md's.
        openvdb::FloatGrid::Ptr surface = map.surfaceGrid(keep);
        surface->setSaveFloatAsHalf(false);
        return surface;
    }
    if (i == 1) return map.weightGrid(keep);
    if (eps_max && i == 2) return map.truncationGrid(static_cast<float>(eps_max->value()), keep);
    int k = i - (eps_max ? 3 : 2);
    for (const auto& [name, grid] : map.extraGrids()) {
        if (k-- > 0) continue;
        // A new grid object sharing the (unchanged) tree: only its name is set.
        openvdb::GridBase::Ptr g = openvdb::ConstPtrCast<openvdb::GridBase>(grid->copyGrid());
        g->setName(name);
        return g;
    }
    return nullptr;
}

int mapVdbGridCount(const VoxelMap& map) {
    const bool eps = map.metadata().getMetadata<openvdb::DoubleMetadata>("truncation_max_m") != nullptr;
    return 2 + (eps ? 1 : 0) + static_cast<int>(map.extraGrids().size());
}

openvdb::MetaMap mapVdbMetadata(const VoxelMap& map) {
    openvdb::MetaMap meta(map.metadata());
    meta.insertMeta("creator", openvdb::StringMetadata(std::string("vdbmap ") + versionString()));
    if (!meta["voxel_size_m"]) meta.insertMeta("voxel_size_m", openvdb::DoubleMetadata(map.voxelSize()));
    return meta;
}

namespace {
/// Test hook (docs/tiling.md, "Resume"): with VDBMAP_TEST_KILL_IN_MAP_VDB=1 the process raises
/// SIGKILL while it makes the second grid, the first already in the temporary file: a run
/// killed during the map.vdb write, deterministically, for the resume tests.
void testKillInMapVdb(int grid) {
    static const bool kill = std::getenv("VDBMAP_TEST_KILL_IN_MAP_VDB") != nullptr;
    if (kill && grid == 1) ::raise(SIGKILL);
}
}  // namespace

void writeVdbGridsOneByOne(const std::filesystem::path& path, int count,
                           const std::function<openvdb::GridBase::Ptr(int)>& make,
                           const openvdb::MetaMap& meta) {
    AtomicFile out(path);
    std::ofstream stream = detail::openOutput(out.tempPath(), path);
    try {
        CheckedVdbWriter().writeOneByOne(stream, count, [&](int i) {
            testKillInMapVdb(i);
            return make(i);
        }, meta);
    } catch (const openvdb::Exception& e) {
        throw IoError("writeMapVdb: cannot write '" + path.string() + "': " + e.what());
    }
    detail::closeOutput(stream, path);  // a full disk or a file-size limit is an IoError here
    out.commit();
}

void writeMapVdb(const std::filesystem::path& path, const VoxelMap& map) {
    // One decoded grid at a time: at the end of a long drive they are the largest allocation.
    writeVdbGridsOneByOne(
        path, mapVdbGridCount(map), [&](int i) { return mapVdbGrid(map, i); },
        mapVdbMetadata(map));
}

std::size_t writeMapVdbPart(const std::filesystem::path& path, const VoxelMap& map,
                            const std::function<bool(const openvdb::Coord&)>& keep,
                            const openvdb::MetaMap& meta) {
    openvdb::MetaMap file_meta = mapVdbMetadata(map);
    file_meta.removeMeta("scans_integrated");  // the whole run's, not the part's
    for (auto it = meta.beginMeta(); it != meta.endMeta(); ++it) {
        file_meta.insertMeta(it->first, *it->second);
    }
    // The TSDF's grids only: the extra grids (mapVdbGrid's last ones) are the whole map's.
    const int count = mapVdbGridCount(map) - static_cast<int>(map.extraGrids().size());
    std::size_t voxels = 0;
    writeVdbGridsOneByOne(
        path, count,
        [&](int i) {
            openvdb::GridBase::Ptr grid = mapVdbGrid(map, i, keep);
            if (i == 0) voxels = static_cast<std::size_t>(grid->activeVoxelCount());
            return grid;
        },
        file_meta);
    return voxels;
}

}  // namespace vdbmap
