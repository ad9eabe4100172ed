// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>
#include <sys/stat.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <thread>

#include "unit/IoTestUtil.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/io/PointCloudIO.h"

using namespace vdbmap;
using Catch::Matchers::Contains;

namespace {
const std::filesystem::path kScans =
    std::filesystem::path(VDBMAP_TEST_DATA_DIR) / "kitti_scans_real";
}

TEST_CASE("Real KITTI scans read with file size / 16 points", "[io][bin]") {
    for (const char* name : {"000000.bin", "000001.bin"}) {
        const auto path = kScans / name;
        const PointCloud cloud = readBin(path);
        const std::size_t expected = std::filesystem::file_size(path) / 16;
        CHECK(cloud.size() == expected);
        REQUIRE(cloud.intensity.size() == expected);
        // A real Velodyne HDL-64 scan, sensor ~1.73 m above the road: ranges up to ~120 m,
        // reflectance in [0, 1], and a large share of the points on the ground plane.
        double max_range = 0;
        std::size_t ground = 0;
        for (std::size_t i = 0; i < cloud.size(); ++i) {
            max_range = std::max(max_range, static_cast<double>(cloud.points[i].norm()));
            ground += cloud.points[i].z() > -2.2f && cloud.points[i].z() < -1.4f ? 1 : 0;
            REQUIRE(cloud.intensity[i] >= 0.0f);
            REQUIRE(cloud.intensity[i] <= 1.0f);
        }
        CHECK(max_range > 30.0);
        CHECK(max_range < 200.0);
        CHECK(ground > cloud.size() / 3);
    }
    CHECK(readBin(kScans / "000000.bin").size() == 124668);
}

TEST_CASE("Truncated .bin throws IoError naming the file and size", "[io][bin]") {
    test::TempDir dir;
    const std::string bytes = test::readBytes(kScans / "000000.bin");
    test::writeText(dir / "000007.bin", bytes.substr(0, 16 * 10 + 7));
    const std::string message = test::ioErrorMessage([&] { readBin(dir / "000007.bin"); });
    CHECK_THAT(message, Contains("000007.bin") && Contains("167"));
    CHECK_THAT(test::ioErrorMessage([&] { readBin(dir / "missing.bin"); }),
               Contains("missing.bin"));
}

TEST_CASE("writeBin / readBin round trip and readPointCloud dispatch", "[io][bin]") {
    test::TempDir dir;
    PointCloud cloud;
    for (int i = 0; i < 50; ++i) {
        cloud.points.emplace_back(0.1f * i, -2.5f + i, 3.25f * std::sin(static_cast<float>(i)));
        cloud.intensity.push_back(0.01f * i);
    }
    writeBin(dir / "a.bin", cloud);
    const PointCloud back = readPointCloud(dir / "a.bin");
    REQUIRE(back.size() == cloud.size());
    for (std::size_t i = 0; i < cloud.size(); ++i) {
        CHECK(back.points[i] == cloud.points[i]);
        CHECK(back.intensity[i] == cloud.intensity[i]);
    }
    CHECK_THAT(test::ioErrorMessage([&] { readPointCloud(dir / "a.xyz"); }), Contains("a.xyz"));
    CHECK(test::countEntries(dir.path()) == 1);  // no temporary left behind
}

TEST_CASE("filterScan drops non-finite and out-of-range points and counts them", "[io][bin]") {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    PointCloud cloud;
    cloud.points = {{5, 0, 0}, {nan, 0, 0}, {0.5f, 0, 0}, {0, 0, inf}, {0, 300, 0}, {0, 0, -2}};
    cloud.intensity = {1, 2, 3, 4, 5, 6};
    ScanReadStats stats;
    filterScan(cloud, 1.0, 200.0, &stats);
    CHECK(stats.points_read == 6);
    CHECK(stats.dropped_non_finite == 2);
    CHECK(stats.dropped_range == 2);
    REQUIRE(cloud.size() == 2);
    CHECK(cloud.points[0] == Vec3f(5, 0, 0));
    CHECK(cloud.points[1] == Vec3f(0, 0, -2));
    CHECK(cloud.intensity == std::vector<float>{1, 6});
}

TEST_CASE("Scans read the same from a regular file, an empty file and a pipe", "[io][bin]") {
    // Reading must not depend on seeking or on knowing the size beforehand: a FIFO (a scan
    // streamed by another process) has neither.
    test::TempDir dir;
    const std::string bytes = test::readBytes(kScans / "000000.bin");
    const PointCloud whole = readBin(kScans / "000000.bin");
    REQUIRE(whole.size() == bytes.size() / 16);
    test::writeText(dir / "empty.bin", "");
    CHECK(readBin(dir / "empty.bin").size() == 0);
    const std::filesystem::path fifo = dir / "pipe.bin";
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    std::thread writer([&] { test::writeText(fifo, bytes); });
    PointCloud piped;
    std::string error;
    try {
        piped = readBin(fifo);
    } catch (const std::exception& e) {
        error = e.what();
        test::readBytes(fifo);  // let the writer finish: a failure, not a hang
    }
    writer.join();
    REQUIRE(error.empty());
    REQUIRE(piped.size() == whole.size());
    for (std::size_t i = 0; i < whole.size(); i += 997) CHECK(piped.points[i] == whole.points[i]);
    CHECK(piped.points.back() == whole.points.back());
    CHECK(piped.intensity.back() == whole.intensity.back());
}

TEST_CASE("readBin into a reused cloud: the scan read, whatever the cloud held", "[io][bin]") {
    // A reader of many scans reads each one into the storage of the one before. Every point
    // must come from this file (the read goes in pieces of 4096 points: 124668 is not a
    // multiple), a smaller scan must not keep the bigger one's tail, and a failed read must not
    // leave a half-read scan behind.
    test::TempDir dir;
    const std::string bytes = test::readBytes(kScans / "000000.bin");
    PointCloud small;
    for (int i = 0; i < 5000; ++i) {
        small.points.emplace_back(0.5f * i, 1.0f - i, 0.25f * i);
        small.intensity.push_back(0.0001f * i);
    }
    writeBin(dir / "small.bin", small);
    PointCloud reused;
    readBin(kScans / "000001.bin", reused);  // the bigger scan first
    REQUIRE(reused.size() > small.size());
    readBin(dir / "small.bin", reused);
    CHECK(reused.points == small.points);
    CHECK(reused.intensity == small.intensity);
    readBin(kScans / "000000.bin", reused);
    REQUIRE(reused.size() == bytes.size() / 16);
    for (std::size_t i = 0; i < reused.size(); ++i) {
        float v[4];
        std::memcpy(v, bytes.data() + 16 * i, 16);
        REQUIRE(reused.points[i] == Vec3f(v[0], v[1], v[2]));
        REQUIRE(reused.intensity[i] == v[3]);
    }
    test::writeText(dir / "cut.bin", bytes.substr(0, 16 * 5000 + 3));
    CHECK_THAT(test::ioErrorMessage([&] { readBin(dir / "cut.bin", reused); }),
               Contains("cut.bin") && Contains("80003"));
    CHECK(reused.empty());
    CHECK(reused.intensity.empty());
}

TEST_CASE("filterScan keeps exactly the points a double-precision range check keeps", "[io][bin]") {
    // filterScan decides most points in float and only those near a bound in double: its result
    // must be the plain double check's, also for points within float rounding of a bound, at
    // the bound itself, tiny, huge and non-finite.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    const double min_m = 2.5, max_m = 80.0;
    PointCloud cloud;
    for (int i = 0; i < 20000; ++i) {
        Vec3f d(unit(rng), unit(rng), unit(rng));
        if (d.norm() < 1e-3f) continue;
        d.normalize();
        const double target = (i % 4 == 0) ? min_m : (i % 4 == 1) ? max_m : 1.0 + 100.0 * (unit(rng) + 1.0f);
        // Around the bound: a few float steps either side of it.
        const float r = std::nextafter(static_cast<float>(target), (i % 2) ? 1e9f : 0.0f) *
                        (1.0f + static_cast<float>(i % 7 - 3) * 1e-7f);
        cloud.points.push_back(d * r);
        cloud.intensity.push_back(static_cast<float>(i));
    }
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (const Vec3f& p : {Vec3f(0, 0, 0), Vec3f(1e-25f, 0, 0), Vec3f(3e38f, 3e38f, 0),
                           Vec3f(nan, 1, 1), Vec3f(static_cast<float>(min_m), 0, 0),
                           Vec3f(0, static_cast<float>(max_m), 0)}) {
        cloud.points.push_back(p);
        cloud.intensity.push_back(-1.0f);
    }
    std::vector<Vec3f> expected;
    std::vector<float> expected_intensity;
    for (std::size_t i = 0; i < cloud.size(); ++i) {
        const Vec3f& p = cloud.points[i];
        const double r2 = p.cast<double>().squaredNorm();
        if (p.allFinite() && r2 >= min_m * min_m && r2 <= max_m * max_m) {
            expected.push_back(p);
            expected_intensity.push_back(cloud.intensity[i]);
        }
    }
    REQUIRE(expected.size() > 1000);
    REQUIRE(expected.size() < cloud.size() - 1000);  // both bounds cut
    ScanReadStats stats;
    filterScan(cloud, min_m, max_m, &stats);
    CHECK(cloud.points == expected);
    CHECK(cloud.intensity == expected_intensity);
    CHECK(stats.dropped_non_finite == 1);
}
