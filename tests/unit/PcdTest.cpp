// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>
#include <cstring>
#include <random>

#include "io/Lzf.h"
#include "unit/IoTestUtil.h"
#include "vdbmap/io/CalibIO.h"
#include "vdbmap/io/Image.h"
#include "vdbmap/io/PointCloudIO.h"

using namespace vdbmap;
using Catch::Matchers::Contains;

namespace {
const std::filesystem::path kFrame =
    std::filesystem::path(VDBMAP_TEST_DATA_DIR) / "lidar_camera_real" / "1";

std::string binaryString(const void* data, std::size_t size) {
    return std::string(static_cast<const char*>(data), size);
}
}  // namespace

TEST_CASE("LZF round trip on random, repetitive and empty data", "[io][pcd][lzf]") {
    std::mt19937 rng(7);
    std::vector<std::string> inputs = {"", "a", "abcabcabcabcabcabcabcabcabcabc",
                                       std::string(5000, 'x')};
    std::string random(20000, '\0');
    for (char& c : random) c = static_cast<char>(rng() % 7);  // small alphabet: many matches
    inputs.push_back(random);
    for (const std::string& in : inputs) {
        const std::string packed =
            detail::lzfCompress(reinterpret_cast<const std::uint8_t*>(in.data()), in.size());
        std::string out(in.size(), '\0');
        REQUIRE(detail::lzfDecompress(reinterpret_cast<const std::uint8_t*>(packed.data()),
                                      packed.size(), reinterpret_cast<std::uint8_t*>(out.data()),
                                      out.size()));
        CHECK(out == in);
    }
    // Repetitive input must actually compress.
    const std::string& x = inputs[3];
    CHECK(detail::lzfCompress(reinterpret_cast<const std::uint8_t*>(x.data()), x.size()).size() <
          x.size() / 10);
    // A back reference before the start of the output is rejected, not read out of bounds.
    const std::uint8_t bad[] = {0x20, 0x05};
    std::uint8_t out[8];
    CHECK_FALSE(detail::lzfDecompress(bad, sizeof(bad), out, sizeof(out)));
}

TEST_CASE("Real binary_compressed PCD decodes and projects onto its image", "[io][pcd]") {
    const PointCloud cloud = readPcd(kFrame / "calib.pcd");
    REQUIRE(cloud.size() == 101340);
    REQUIRE(cloud.intensity.size() == cloud.size());
    const CameraCalib calib = readCameraCalib(kFrame / "calib.txt");
    REQUIRE(calib.intrinsics.hasDistortion());
    CHECK(calib.intrinsics.fx == Approx(2152.8));
    const cv::Size size = readImageSize(kFrame / "calib.jpg");
    REQUIRE(size == cv::Size(1920, 1200));
    CameraIntrinsics intrinsics = calib.intrinsics;
    intrinsics.width = size.width;
    intrinsics.height = size.height;

    std::size_t finite = 0, inside = 0;
    double z_top = 0, z_bottom = 0;
    std::size_t n_top = 0, n_bottom = 0;
    for (const Vec3f& p_L : cloud.points) {
        if (!p_L.allFinite()) continue;
        ++finite;
        const Vec3d p_C = calib.T_C_L * p_L.cast<double>();
        Vec2d pixel;
        // Distortion polynomials explode far outside the field of view: keep points within
        // ~60 degrees of the optical axis.
        if (p_C.z() < 0.5 * p_C.head<2>().norm() || !intrinsics.project(p_C, pixel)) continue;
        if (!intrinsics.inside(pixel)) continue;
        ++inside;
        if (pixel.y() < 0.4 * size.height) {
            z_top += p_L.z();
            ++n_top;
        } else if (pixel.y() > 0.8 * size.height) {
            z_bottom += p_L.z();
            ++n_bottom;
        }
    }
    REQUIRE(finite > 90000);
    // The camera sees a forward wedge of the 360-degree scan: a good share lands inside.
    CHECK(inside > finite / 10);
    // Geometry check of T and K: pixels near the bottom of the image (road) come from points
    // lower in the LiDAR frame than pixels in the top part (trees, truck).
    REQUIRE(n_top > 100);
    REQUIRE(n_bottom > 100);
    CHECK(z_bottom / n_bottom < z_top / n_top - 0.5);
}

TEST_CASE("PCD written as ascii, binary and binary_compressed reads back identical", "[io][pcd]") {
    test::TempDir dir;
    PointCloud cloud = readPcd(kFrame / "calib.pcd");
    cloud.points.resize(20000);
    cloud.intensity.resize(20000);
    for (const auto& [encoding, name] :
         {std::pair{PcdEncoding::Ascii, "a.pcd"}, std::pair{PcdEncoding::Binary, "b.pcd"},
          std::pair{PcdEncoding::BinaryCompressed, "c.pcd"}}) {
        writePcd(dir / name, cloud, encoding);
        const PointCloud back = readPointCloud(dir / name);
        REQUIRE(back.size() == cloud.size());
        REQUIRE(back.intensity.size() == cloud.size());
        // Bitwise equality (NaN == NaN as bits).
        CHECK(std::memcmp(back.points.data(), cloud.points.data(), cloud.size() * sizeof(Vec3f)) ==
              0);
        CHECK(std::memcmp(back.intensity.data(), cloud.intensity.data(),
                          cloud.size() * sizeof(float)) == 0);
    }
    CHECK(std::filesystem::file_size(dir / "c.pcd") < std::filesystem::file_size(dir / "b.pcd"));
    CHECK(test::countEntries(dir.path()) == 3);
}

TEST_CASE("PCD fields in any order, types and counts", "[io][pcd]") {
    test::TempDir dir;
    // ascii, with a COUNT 2 field before x, double z, unsigned short intensity.
    test::writeText(dir / "ascii.pcd",
                    "# comment\nVERSION .7\nFIELDS rgb normal y x z intensity\n"
                    "SIZE 4 4 4 4 8 2\nTYPE U F F F F U\nCOUNT 1 2 1 1 1 1\nWIDTH 2\nHEIGHT 1\n"
                    "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n"
                    "7 0.5 0.5 2 1 3 100\n8 0 0 -5 -4 nan 7\n");
    PointCloud a = readPcd(dir / "ascii.pcd");
    REQUIRE(a.size() == 2);
    CHECK(a.points[0] == Vec3f(1, 2, 3));
    CHECK(a.points[1].x() == -4);
    CHECK(a.points[1].y() == -5);
    CHECK(std::isnan(a.points[1].z()));
    CHECK(a.intensity == std::vector<float>{100, 7});

    // binary, point-major: int32 x, float64 y, int8 z, 2 pad bytes field, no intensity.
    std::string bytes =
        "VERSION 0.7\nFIELDS x y pad z\nSIZE 4 8 1 1\nTYPE I F U I\nCOUNT 1 1 2 1\nWIDTH 1\n"
        "HEIGHT 2\nPOINTS 2\nDATA binary\n";
    for (int i = 0; i < 2; ++i) {
        const std::int32_t x = -7 + i;
        const double y = 0.25 * i;
        const std::uint8_t pad[2] = {9, 9};
        const std::int8_t z = static_cast<std::int8_t>(-3 * i);
        bytes +=
            binaryString(&x, 4) + binaryString(&y, 8) + binaryString(pad, 2) + binaryString(&z, 1);
    }
    test::writeText(dir / "binary.pcd", bytes);
    const PointCloud b = readPcd(dir / "binary.pcd");
    REQUIRE(b.size() == 2);
    CHECK(b.intensity.empty());
    CHECK(b.points[0] == Vec3f(-7, 0, 0));
    CHECK(b.points[1] == Vec3f(-6, 0.25f, -3));

    // Truncated binary data names the file.
    test::writeText(dir / "short.pcd", bytes.substr(0, bytes.size() - 3));
    CHECK_THAT(test::ioErrorMessage([&] { readPcd(dir / "short.pcd"); }),
               Contains("short.pcd") && Contains("truncated"));
}

TEST_CASE("Corrupt PCD header throws IoError naming the file and the line", "[io][pcd]") {
    test::TempDir dir;
    const std::string good_tail = "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n";
    test::writeText(dir / "size.pcd",
                    "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 four\nTYPE F F F\n" + good_tail);
    CHECK_THAT(test::ioErrorMessage([&] { readPcd(dir / "size.pcd"); }),
               Contains("size.pcd:3") && Contains("SIZE 4 4 four"));
    test::writeText(dir / "keyword.pcd",
                    "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
                    "WIDHT 1\n" +
                        good_tail);
    CHECK_THAT(test::ioErrorMessage([&] { readPcd(dir / "keyword.pcd"); }),
               Contains("keyword.pcd:5") && Contains("WIDHT"));
    test::writeText(
        dir / "count.pcd",
        "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 1\nPOINTS 3\nDATA ascii\n");
    CHECK_THAT(test::ioErrorMessage([&] { readPcd(dir / "count.pcd"); }),
               Contains("count.pcd:7") && Contains("POINTS"));
    test::writeText(dir / "nodata.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\n");
    CHECK_THAT(test::ioErrorMessage([&] { readPcd(dir / "nodata.pcd"); }),
               Contains("nodata.pcd") && Contains("DATA"));
    test::writeText(dir / "noxyz.pcd",
                    "FIELDS x y intensity\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n1 2 3\n");
    CHECK_THAT(test::ioErrorMessage([&] { readPcd(dir / "noxyz.pcd"); }), Contains("noxyz.pcd"));
    // An absurd POINTS is rejected before any allocation.
    test::writeText(dir / "huge.pcd",
                    "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 4000000000000\n"
                    "POINTS 4000000000000\nDATA binary\n123456789012");
    CHECK_THAT(test::ioErrorMessage([&] { readPcd(dir / "huge.pcd"); }),
               Contains("huge.pcd") && Contains("POINTS 4000000000000"));
    // Corrupt compressed payload: sizes fine, LZF stream garbage.
    std::string compressed =
        "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA binary_compressed\n";
    const std::uint32_t sizes[2] = {2, 12};
    compressed += binaryString(sizes, 8) + std::string("\x20\x05", 2);
    test::writeText(dir / "lzf.pcd", compressed);
    CHECK_THAT(test::ioErrorMessage([&] { readPcd(dir / "lzf.pcd"); }),
               Contains("lzf.pcd") && Contains("corrupt"));
}
