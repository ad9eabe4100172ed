// SPDX-License-Identifier: Apache-2.0
// Inputs that are well-formed text but wrong data, and numbers that must be refused before a
// cast (NaN, huge values: UB in C++ otherwise). Each was found by reading the readers for the
// fuzz targets of tests/fuzz, or by the fuzzers; the same inputs are in the corpora.
#include <catch2/catch.hpp>

#include "unit/IoTestUtil.h"
#include "vdbmap/io/CalibIO.h"
#include "vdbmap/io/LabelSet.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/io/PointCloudIO.h"
#include "vdbmap/io/PoseIO.h"
#include "vdbmap/pipeline/Pipeline.h"

using namespace vdbmap;
using Catch::Matchers::Contains;

TEST_CASE("poses: a scaled or mirrored rotation and an overflowing quaternion are refused",
          "[io][poses][hardening]") {
    test::TempDir dir;
    test::writeText(dir / "scaled.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n2 0 0 0 0 2 0 0 0 0 2 0\n");
    CHECK_THAT(test::ioErrorMessage([&] { readKittiPoses(dir / "scaled.txt"); }),
               Contains("scaled.txt:2") && Contains("not a rotation"));
    test::writeText(dir / "mirror.txt", "-1 0 0 0 0 1 0 0 0 0 1 0\n");
    CHECK_THAT(test::ioErrorMessage([&] { readKittiPoses(dir / "mirror.txt"); }),
               Contains("not a rotation") && Contains("det = -1"));
    test::writeText(dir / "tum.txt", "0 0 0 0 1e200 1e200 0 1\n");
    CHECK_THAT(test::ioErrorMessage([&] { readTumPoses(dir / "tum.txt"); }),
               Contains("tum.txt:1") && Contains("quaternion"));
}

TEST_CASE("calib: a Tr or T that is not rigid is refused", "[io][calib][hardening]") {
    test::TempDir dir;
    const std::string P = "700 0 600 0 0 700 170 0 0 0 1 0";
    test::writeText(dir / "calib.txt", "P0: " + P + "\nTr: 1 0 0 0 0 1 0 0 0 0.5 1 0\n");
    CHECK_THROWS_WITH(readKittiCalib(dir / "calib.txt"), Contains("not a rotation"));
    test::writeText(dir / "cam.txt", "K: 500 0 320 0 500 240 0 0 1\nT: 3 0 0 0 0 3 0 0 0 0 3 0\n");
    CHECK_THROWS_WITH(readCameraCalib(dir / "cam.txt"),
                      Contains("cam.txt:2") && Contains("not a rotation"));
}

TEST_CASE("readers: NaN and huge counts or indices are errors, not casts",
          "[io][hardening]") {
    test::TempDir dir;
    const std::string pcd_head = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n";
    test::writeText(dir / "nan.pcd", pcd_head + "COUNT 1 1 1\nWIDTH nan\nHEIGHT 1\nDATA ascii\n");
    CHECK_THAT(test::ioErrorMessage([&] { readPcd(dir / "nan.pcd"); }),
               Contains("nan.pcd:6") && Contains("non-negative integer"));
    test::writeText(dir / "count.pcd", pcd_head + "COUNT 1 nan 1\nWIDTH 1\nDATA ascii\n");
    CHECK_THAT(test::ioErrorMessage([&] { readPcd(dir / "count.pcd"); }),
               Contains("invalid COUNT"));
    test::writeText(dir / "wide.pcd",
                    pcd_head + "WIDTH 999999999999999\nHEIGHT 999999999999999\nDATA ascii\n");
    CHECK_THAT(test::ioErrorMessage([&] { readPcd(dir / "wide.pcd"); }), Contains("overflows"));

    const std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                            "property float y\nproperty float z\nelement face 1\n"
                            "property list uchar int vertex_indices\n";
    test::writeText(dir / "nan.ply", ply + "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 nan 2\n");
    CHECK_THAT(test::ioErrorMessage([&] { readMeshPly(dir / "nan.ply"); }),
               Contains("refers to vertex"));
    test::writeText(dir / "label.ply",
                    ply + "property float label\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 300\n");
    CHECK_THAT(test::ioErrorMessage([&] { readMeshPly(dir / "label.ply"); }),
               Contains("label 300"));
    test::writeText(dir / "spin.ply", "ply\nformat binary_little_endian 1.0\n"
                                      "element nothing 1000000000000\nend_header\n");
    CHECK_THAT(test::ioErrorMessage([&] { readPlyPoints(dir / "spin.ply"); }),
               Contains("no properties"));
    test::writeText(dir / "huge.ply", "ply\nformat ascii 1.0\nelement vertex 1e300\nend_header\n");
    CHECK_THAT(test::ioErrorMessage([&] { readPlyPoints(dir / "huge.ply"); }),
               Contains("huge.ply:3"));

    test::writeText(dir / "nan.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 nan 3\n");
    CHECK_THAT(test::ioErrorMessage([&] { readObj(dir / "nan.obj"); }),
               Contains("nan.obj:4") && Contains("out of range"));

    test::writeText(dir / "labels.txt", "nan, road, 1 2 3\n");
    CHECK_THROWS_WITH(LabelSet::fromFile(dir / "labels.txt"), Contains("0..255"));
    test::writeText(dir / "colour.txt", "1, road, nan 2 3\n");
    CHECK_THROWS_WITH(LabelSet::fromFile(dir / "colour.txt"), Contains("0..255"));
}

TEST_CASE("pipeline: a stages.<index> override with a huge index is a config error",
          "[yaml][hardening]") {
    const std::string yaml = "stages:\n  - stage: integrate.atsdf\n";
    CHECK_THROWS_AS(Pipeline::fromString(yaml, "t.yaml", ".",
                                         {"stages.99999999999999999999999.voxel_size_m=1"}),
                    ConfigError);
}
