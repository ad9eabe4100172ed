// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>
#include <openvdb/io/File.h>

#include <filesystem>
#include <fstream>

#include "support/MapTestUtil.h"
#include "support/PlainAtsdfConfig.h"
#include "support/SimLidar.h"
#include "vdbmap/Error.h"
#include "vdbmap/map/AtsdfIntegrator.h"
#include "vdbmap/map/VdbIO.h"
#include "vdbmap/map/VoxelMap.h"

using namespace vdbmap;
using namespace vdbmap::test;
namespace fs = std::filesystem;

namespace {

/// One scan of `scene` from the origin, integrated and finalized (the truncation grid exists).
void scanOnce(VoxelMap& map, const SimScene& scene, int azimuth_steps) {
    SimLidarConfig lidar;
    lidar.azimuth_steps = azimuth_steps;
    AtsdfIntegrator integrator(map, plainAtsdfConfig());
    integrateScans(integrator, scene, lidar, {poseAt(Vec3d::Zero())});
    integrator.finalize();
}

}  // namespace

TEST_CASE("map.vdb round trip: grids, classes, values and metadata", "[tsdf][vdb]") {
    SimScene scene;
    scene.add(SimPlane{Vec3d(0, 0, -1.7), Vec3d::UnitZ()});
    scene.add(SimSphere{Vec3d(5, 0, 0), 1.0});
    VoxelMap map(0.1, 0.3f);
    scanOnce(map, scene, 512);

    const fs::path dir = fs::path(VDBMAP_BINARY_DIR) / "test_out" / "VdbIOTest";
    fs::remove_all(dir);
    const fs::path path = dir / "map.vdb";
    writeMapVdb(path, map);
    REQUIRE(fs::exists(path));
    for (const auto& e : fs::directory_iterator(dir)) CHECK(e.path().filename() == "map.vdb");

    openvdb::io::File file(path.string());
    file.open();
    const auto meta = file.getMetadata();
    REQUIRE(meta);
    CHECK(meta->metaValue<std::string>("creator").rfind("vdbmap ", 0) == 0);
    CHECK(meta->metaValue<double>("voxel_size_m") == Approx(0.1));
    CHECK(meta->metaValue<std::string>("truncation_mode") == "adaptive");
    CHECK(meta->metaValue<double>("truncation_min_m") == Approx(0.1));
    CHECK(meta->metaValue<double>("truncation_max_m") == Approx(0.3));
    CHECK(meta->metaValue<double>("flatness_k") == Approx(1.0));

    auto surface = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("surface"));
    auto weight = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("weight"));
    auto trunc = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("truncation"));
    file.close();
    REQUIRE(surface);
    REQUIRE(weight);
    REQUIRE(trunc);
    CHECK(surface->getGridClass() == openvdb::GRID_LEVEL_SET);
    CHECK(surface->voxelSize()[0] == Approx(0.1));
    CHECK(surface->activeVoxelCount() == map.activeVoxelCount());
    CHECK(maxGridDifference(*surface, *map.surfaceGrid()) == 0.0);
    CHECK(maxGridDifference(*weight, *map.weightGrid()) == 0.0);
    CHECK(trunc->activeVoxelCount() == map.activeVoxelCount());
    // The file's floats are the packed voxels, decoded.
    std::size_t checked = 0;
    auto sacc = surface->getConstAccessor();
    auto wacc = weight->getConstAccessor();
    map.forEachVoxel([&](const openvdb::Coord& c, std::uint32_t packed) {
        if (++checked > 1000) return;
        CHECK(sacc.getValue(c) == map.codec().sdf(packed));
        CHECK(wacc.getValue(c) == map.codec().weight(packed));
    });
    float lo = 1e9f, hi = -1e9f;
    for (auto it = trunc->cbeginValueOn(); it; ++it) {
        lo = std::min(lo, *it);
        hi = std::max(hi, *it);
    }
    CHECK(lo >= 0.1f - 1e-6f);
    CHECK(hi <= 0.3f + 1e-6f);
    CHECK(lo < hi);  // adaptive: not one value everywhere
}

TEST_CASE("writeMapVdb, one grid at a time, writes what Archive::write writes", "[tsdf][vdb]") {
    // writeMapVdb decodes and writes one grid at a time (the decoded grids of a long drive are
    // its largest allocation); the file must be OpenVDB's own file of all grids at once
    // (io::File::write), byte for byte but for the archive's random UUID.
    SimScene scene;
    scene.add(SimPlane{Vec3d(0, 0, -1.7), Vec3d::UnitZ()});
    VoxelMap map(0.1, 0.3f);
    scanOnce(map, scene, 256);
    auto label = openvdb::FloatGrid::create(0.0f);
    label->tree().setValue(openvdb::Coord(1, 2, 3), 7.0f);
    map.setExtraGrid("label", label);

    const fs::path dir = fs::path(VDBMAP_BINARY_DIR) / "test_out" / "VdbIOTestOneByOne";
    fs::remove_all(dir);
    fs::create_directories(dir);
    writeMapVdb(dir / "lazy.vdb", map);
    openvdb::GridPtrVec grids;
    for (int i = 0; i < mapVdbGridCount(map); ++i) grids.push_back(mapVdbGrid(map, i));
    openvdb::io::File((dir / "all.vdb").string()).write(grids, mapVdbMetadata(map));
    auto bytes = [](const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    const std::string lazy = bytes(dir / "lazy.vdb"), all = bytes(dir / "all.vdb");
    REQUIRE(lazy.size() == all.size());
    // Header: magic (8 B), file version (4), library version (8), offsets flag (1), UUID (36).
    constexpr std::size_t kUuidBegin = 21, kUuidEnd = 57;
    CHECK(lazy.substr(0, kUuidBegin) == all.substr(0, kUuidBegin));
    CHECK(lazy.substr(kUuidEnd) == all.substr(kUuidEnd));

    openvdb::io::File file((dir / "lazy.vdb").string());
    file.open();
    const auto read = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("label"));
    file.close();
    REQUIRE(read);
    CHECK(read->tree().getValue(openvdb::Coord(1, 2, 3)) == 7.0f);
}

TEST_CASE("writeMapVdb into an impossible path throws IoError and leaves nothing",
          "[tsdf][vdb]") {
    VoxelMap map(0.1);
    const fs::path dir = fs::path(VDBMAP_BINARY_DIR) / "test_out" / "VdbIOTestBad";
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "not_a_dir") << "x";
    CHECK_THROWS_AS(writeMapVdb(dir / "not_a_dir" / "map.vdb", map), Error);
    std::size_t files = 0;
    for (const auto& e : fs::recursive_directory_iterator(dir)) files += e.is_regular_file() ? 1 : 0;
    CHECK(files == 1);
}
