// SPDX-License-Identifier: Apache-2.0
// `vdbmap info` on a map.vdb with known content: grid names, class, counts and bounds.
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "vdbmap/map/VdbIO.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/pipeline/StageRegistry.h"

namespace fs = std::filesystem;

TEST_CASE("vdbmap info prints grids, counts, bounds and metadata", "[cli][info]") {
    vdbmap::registerBuiltinStages();  // openvdb::initialize() inside the library
    const fs::path dir = fs::temp_directory_path() / ("vdbmap_info_test_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path vdb = dir / "map.vdb";

    // A 3 x 2 x 1 block of active voxels at index (10..12, -4..-3, 7), voxel size 0.5 m.
    vdbmap::VoxelMap map(0.5);
    for (int i = 10; i <= 12; ++i) {
        for (int j = -4; j <= -3; ++j) {
            map.setVoxel(openvdb::Coord(i, j, 7), 0.1f, 1.0f);
        }
    }
    map.metadata().insertMeta("test_key", openvdb::StringMetadata("test_value"));
    vdbmap::writeMapVdb(vdb, map);

    const fs::path log = dir / "info.txt";
    const std::string cmd = "'" + (fs::path(VDBMAP_BINARY_DIR) / "bin" / "vdbmap").string() +
                            "' info '" + vdb.string() + "' > '" + log.string() + "' 2>&1";
    const int status = std::system(cmd.c_str());
    std::ifstream in(log);
    const std::string out((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    INFO(out);
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
    CHECK(out.find("  surface\n") != std::string::npos);
    CHECK(out.find("  weight\n") != std::string::npos);
    CHECK(out.find("class: level set") != std::string::npos);
    CHECK(out.find("value type: float") != std::string::npos);
    CHECK(out.find("voxel size: (0.5, 0.5, 0.5)") != std::string::npos);
    CHECK(out.find("active voxels: 6") != std::string::npos);
    CHECK(out.find("bounding box (index): (10, -4, 7) .. (12, -3, 7)") != std::string::npos);
    // World box = voxel faces: (10 - 0.5) * 0.5 = 4.75 ... (12 + 0.5) * 0.5 = 6.25.
    CHECK(out.find("bounding box (world, m): (4.75, -2.25, 3.25) .. (6.25, -1.25, 3.75)") !=
          std::string::npos);
    CHECK(out.find("test_key (string) = test_value") != std::string::npos);
    CHECK(out.find("creator (string) = vdbmap ") != std::string::npos);
    fs::remove_all(dir);
}
