// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include "unit/IoTestUtil.h"
#include "vdbmap/io/PointCloudIO.h"

using namespace vdbmap;
using Catch::Matchers::Contains;

TEST_CASE("Real binary PLY point cloud (CloudCompare) reads with intensity", "[io][ply]") {
    const auto path = std::filesystem::path(VDBMAP_TEST_DATA_DIR) / "scan_pair_real" / "source.ply";
    const PointCloud cloud = readPointCloud(path);
    // Header: element vertex 69792, x y z scalar_intensity as float; 4 floats per vertex.
    REQUIRE(cloud.size() == 69792);
    REQUIRE(cloud.intensity.size() == cloud.size());
    const std::string bytes = test::readBytes(path);
    CHECK(bytes.size() - bytes.find("end_header\n") - 11 == cloud.size() * 16);
    std::size_t finite = 0;
    double max_range = 0;
    for (const Vec3f& p : cloud.points) {
        if (!p.allFinite()) continue;
        ++finite;
        max_range = std::max(max_range, static_cast<double>(p.norm()));
    }
    CHECK(finite == cloud.size());
    CHECK(max_range > 10.0);
    CHECK(max_range < 300.0);

    test::TempDir dir;
    writePlyPoints(dir / "copy.ply", cloud);
    const PointCloud back = readPlyPoints(dir / "copy.ply");
    REQUIRE(back.size() == cloud.size());
    CHECK(back.points == cloud.points);
    CHECK(back.intensity == cloud.intensity);
}

TEST_CASE("ASCII and big-endian PLY points; errors name the file", "[io][ply]") {
    test::TempDir dir;
    test::writeText(dir / "a.ply",
                    "ply\nformat ascii 1.0\nelement vertex 2\nproperty double z\nproperty uchar "
                    "red\nproperty float x\nproperty float y\nproperty float intensity\n"
                    "element face 0\nproperty list uchar int vertex_indices\nend_header\n"
                    "3 255 1 2 0.5\n-1 0 4 5 0.25\n");
    const PointCloud a = readPlyPoints(dir / "a.ply");
    REQUIRE(a.size() == 2);
    CHECK(a.points[0] == Vec3f(1, 2, 3));
    CHECK(a.points[1] == Vec3f(4, 5, -1));
    CHECK(a.intensity == std::vector<float>{0.5f, 0.25f});

    // Big endian: one vertex (1.0f, 2.0f, -3.0f).
    std::string be =
        "ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty float x\n"
        "property float y\nproperty float z\nend_header\n";
    be += std::string("\x3f\x80\x00\x00\x40\x00\x00\x00\xc0\x40\x00\x00", 12);
    test::writeText(dir / "be.ply", be);
    const PointCloud b = readPlyPoints(dir / "be.ply");
    REQUIRE(b.size() == 1);
    CHECK(b.points[0] == Vec3f(1, 2, -3));
    CHECK(b.intensity.empty());

    test::writeText(dir / "trunc.ply", be.substr(0, be.size() - 2));
    CHECK_THAT(test::ioErrorMessage([&] { readPlyPoints(dir / "trunc.ply"); }),
               Contains("trunc.ply") && Contains("truncated"));
    test::writeText(dir / "noz.ply",
                    "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                    "property float y\nend_header\n1 2\n");
    CHECK_THAT(test::ioErrorMessage([&] { readPlyPoints(dir / "noz.ply"); }), Contains("noz.ply"));
    test::writeText(dir / "nohead.ply", "plx\n");
    CHECK_THAT(test::ioErrorMessage([&] { readPlyPoints(dir / "nohead.ply"); }),
               Contains("nohead.ply:1"));
}
