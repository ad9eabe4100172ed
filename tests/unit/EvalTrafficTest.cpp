// SPDX-License-Identifier: Apache-2.0
// vdbmap eval's traffic scores (issue 33): the ghost area inside the movers' swept volume, the
// swept ground area, and the moving-point recall / precision of a dynamic_points.ply, each
// against a closed-form answer.
#include <catch2/catch.hpp>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "vdbmap/Error.h"
#include "vdbmap/eval/TrafficMetrics.h"
#include "vdbmap/io/LidarLabels.h"
#include "vdbmap/render/Raycaster.h"

using namespace vdbmap;
namespace fs = std::filesystem;

namespace {

Isometry3d poseXYZYaw(double x, double y, double z, double yaw) {
    Isometry3d T = Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(yaw, Vec3d::UnitZ()).toRotationMatrix();
    T.translation() = Vec3d(x, y, z);
    return T;
}

// One mover, a 6 x 4 x 2 m box standing on the ground (centre 1 m up), at x = 0 in frame 0
// and x = 2 in frame 1: with 0.1 m inflation it sweeps x in [-3.1, 5.1], y in [-2.1, 2.1],
// z in [-0.1, 2.1].
MoversFile oneBox(const Isometry3d& T_W_S = Isometry3d::Identity()) {
    MoversFile f;
    f.times_s = {0.0, 0.1};
    Mover m;
    m.name = "box";
    m.kind = "car";
    m.instance_id = 1;
    m.parts.push_back(MoverPart{Vec3f(0, 0, 1), Vec3f(3, 2, 1), "car_yellow"});
    m.T_W_O = {T_W_S * poseXYZYaw(0, 0, 0, 0), T_W_S * poseXYZYaw(2, 0, 0, 0)};
    f.movers.push_back(m);
    return f;
}

// Static ground truth: the ground z = 0, 200 m x 200 m.
Raycaster ground(const Isometry3d& T_W_S = Isometry3d::Identity()) {
    std::vector<Vec3f> v{{-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0}};
    for (auto& p : v) p = (T_W_S * p.cast<double>()).cast<float>();
    return Raycaster(v, {{0, 1, 2}, {0, 2, 3}});
}

// A vertical quad in the plane x = x0, y in [y0, y1], z in [z0, z1] (two triangles).
void addQuadX(std::vector<Vec3f>& v, std::vector<std::array<std::uint32_t, 3>>& t, float x0,
              float y0, float y1, float z0, float z1) {
    const auto b = static_cast<std::uint32_t>(v.size());
    v.insert(v.end(), {{x0, y0, z0}, {x0, y1, z0}, {x0, y1, z1}, {x0, y0, z1}});
    t.push_back({b, b + 1, b + 2});
    t.push_back({b, b + 2, b + 3});
}

double ghostOfQuad(float x0, float y0, float y1, float z0, float z1) {
    std::vector<Vec3f> v;
    std::vector<std::array<std::uint32_t, 3>> t;
    addQuadX(v, t, x0, y0, y1, z0, z1);
    const SweptVolume swept(oneBox(), 0.1);
    return ghostArea(v, t, ground(), swept, 0.1, 0.02);
}

void writeBytes(const fs::path& p, const std::string& bytes) {
    std::ofstream out(p, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

template <typename T>
void append(std::string& s, T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    s.append(b, sizeof(T));
}

}  // namespace

TEST_CASE("Ghost area: a 2 m x 1 m face inside the swept volume counts whole, outside not",
          "[eval][traffic]") {
    // Inside, 0.5 m above the ground: the whole 2 m^2.
    CHECK(ghostOfQuad(1.0f, -1.0f, 1.0f, 0.5f, 1.5f) == Approx(2.0).margin(0.01));
    // The same face 20 m away, outside the swept volume.
    CHECK(ghostOfQuad(20.0f, -1.0f, 1.0f, 0.5f, 1.5f) == 0.0);
    // Half in: y in [1.1, 3.1] crosses the volume's side y = 2.1, so 1 m x 1 m is inside.
    CHECK(ghostOfQuad(1.0f, 1.1f, 3.1f, 0.5f, 1.5f) == Approx(1.0).margin(0.03));
    // Within 0.1 m of the static ground (z in [0, 0.08]): not a ghost, though inside.
    CHECK(ghostOfQuad(1.0f, -1.0f, 1.0f, 0.0f, 0.08f) == 0.0);
    // z in [0, 1]: only the part above 0.1 m, 2 m x 0.9 m.
    CHECK(ghostOfQuad(1.0f, -1.0f, 1.0f, 0.0f, 1.0f) == Approx(1.8).margin(0.03));
}

TEST_CASE("Ghost area per face: each face its own share, the sum the total", "[eval][traffic]") {
    std::vector<Vec3f> v;
    std::vector<std::array<std::uint32_t, 3>> t;
    addQuadX(v, t, 1.0f, -1.0f, 1.0f, 0.5f, 1.5f);   // inside: 1 m^2 per triangle
    addQuadX(v, t, 20.0f, -1.0f, 1.0f, 0.5f, 1.5f);  // outside the swept volume
    const SweptVolume swept(oneBox(), 0.1);
    const std::vector<double> per_face = ghostAreaPerFace(v, t, ground(), swept, 0.1, 0.02);
    REQUIRE(per_face.size() == 4);
    CHECK(per_face[0] == Approx(1.0).margin(0.01));
    CHECK(per_face[1] == Approx(1.0).margin(0.01));
    CHECK(per_face[2] == 0.0);
    CHECK(per_face[3] == 0.0);
    CHECK(ghostArea(v, t, ground(), swept, 0.1, 0.02) == Approx(per_face[0] + per_face[1]));
}

TEST_CASE("Swept ground area: the union of the box footprints, in any world frame",
          "[eval][traffic]") {
    // Two 6.2 x 4.2 m footprints 2 m apart: 8.2 m x 4.2 m.
    const SweptVolume swept(oneBox(), 0.1);
    CHECK(swept.groundArea(0.01) == Approx(8.2 * 4.2).margin(0.1));
    CHECK(swept.contains(Vec3f(4.9f, 2.0f, 2.0f)));
    CHECK_FALSE(swept.contains(Vec3f(5.2f, 0.0f, 1.0f)));
    // A world whose y axis points down (KITTI's camera 0), rotated and shifted: same area.
    Isometry3d T_W_S = Isometry3d::Identity();
    T_W_S.linear() =
        (Eigen::AngleAxisd(-M_PI / 2, Vec3d::UnitX()) * Eigen::AngleAxisd(0.4, Vec3d::UnitZ()))
            .toRotationMatrix();
    T_W_S.translation() = Vec3d(3, -1, 7);
    const SweptVolume turned(oneBox(T_W_S), 0.1);
    CHECK(turned.groundArea(0.01) == Approx(8.2 * 4.2).margin(0.1));
    // The ghost face, moved with the world, still counts 2 m^2.
    std::vector<Vec3f> v;
    std::vector<std::array<std::uint32_t, 3>> t;
    addQuadX(v, t, 1.0f, -1.0f, 1.0f, 0.5f, 1.5f);
    for (auto& p : v) p = (T_W_S * p.cast<double>()).cast<float>();
    CHECK(ghostArea(v, t, ground(T_W_S), turned, 0.1, 0.02) == Approx(2.0).margin(0.01));
    // A box yawed by 30 deg: its own footprint, 6.2 x 4.2 m.
    MoversFile yawed = oneBox();
    yawed.movers[0].T_W_O = {poseXYZYaw(0, 0, 0, M_PI / 6)};
    yawed.times_s = {0.0};
    CHECK(SweptVolume(yawed, 0.1).groundArea(0.01) == Approx(6.2 * 4.2).margin(0.1));
    CHECK(SweptVolume(MoversFile{}, 0.1).groundArea(0.05) == 0.0);
}

TEST_CASE("Moving points: recall and precision of a hand-made dynamic_points.ply",
          "[eval][traffic]") {
    const fs::path dir = fs::temp_directory_path() / "vdbmap_evaltraffic_points";
    fs::remove_all(dir);
    fs::create_directories(dir / "labels");
    // Frame 0: 10 points, 2..4 moving (instance 1, class 13 as our ids write it).
    LidarLabels l0;
    for (std::uint32_t i = 0; i < 10; ++i)
        l0.raw.push_back(i >= 2 && i <= 4 ? (1u << 16) | 13 : 40);
    // Frame 1: 5 points, point 0 moving-car 252 without an instance (SemanticKITTI's own).
    LidarLabels l1;
    for (std::uint32_t i = 0; i < 5; ++i) l1.raw.push_back(i == 0 ? 252 : 10);
    writeLidarLabels(dir / "labels" / "000000.label", l0);
    writeLidarLabels(dir / "labels" / "000001.label", l1);
    const MovingTruth truth = readMovingTruth(dir / "labels", 2);
    REQUIRE(truth.size() == 2);

    // Removed: (0,2) (0,3) moving, (0,7) static, (1,0) moving, (1,0) again, (5,1) unknown.
    const std::vector<std::pair<std::uint32_t, std::uint32_t>> removed{{0, 2}, {0, 3}, {0, 7},
                                                                       {1, 0}, {1, 0}, {5, 1}};
    std::string ply = "ply\nformat binary_little_endian 1.0\ncomment hand-made\nelement vertex " +
                      std::to_string(removed.size()) +
                      "\nproperty float x\nproperty float y\nproperty float z\nproperty uint "
                      "frame\nproperty uchar flag\nproperty uint index\nend_header\n";
    for (const auto& [frame, index] : removed) {
        append(ply, 1.0f);
        append(ply, 2.0f);
        append(ply, 3.0f);
        append(ply, frame);
        append(ply, std::uint8_t{7});
        append(ply, index);
    }
    writeBytes(dir / "dynamic_points.ply", ply);
    const auto points = readRemovedPointsPly(dir / "dynamic_points.ply");
    REQUIRE(points.size() == 6);
    CHECK(points[3].frame == 1);
    CHECK(points[2].index == 7);

    const MovingPointScores s = scoreRemovedPoints(truth, points);
    CHECK(s.moving_points == 4);
    CHECK(s.static_points == 11);
    CHECK(s.removed == 5);
    CHECK(s.removed_duplicates == 1);
    CHECK(s.removed_moving == 3);
    CHECK(s.removed_static == 1);
    CHECK(s.removed_unmatched == 1);
    CHECK(s.recall == Approx(3.0 / 4.0));
    CHECK(s.precision == Approx(3.0 / 5.0));
    CHECK(s.static_retention == Approx(10.0 / 11.0));

    // Bad files name themselves.
    writeBytes(dir / "ascii.ply", "ply\nformat ascii 1.0\nelement vertex 0\nend_header\n");
    CHECK_THROWS_AS(readRemovedPointsPly(dir / "ascii.ply"), IoError);
    writeBytes(dir / "noindex.ply",
               "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\n"
               "property float y\nproperty float z\nproperty uint frame\nend_header\n");
    CHECK_THROWS_WITH(readRemovedPointsPly(dir / "noindex.ply"), Catch::Contains("index"));
    writeBytes(dir / "short.ply", ply.substr(0, ply.size() - 3));
    CHECK_THROWS_WITH(readRemovedPointsPly(dir / "short.ply"), Catch::Contains("truncated"));
    CHECK_THROWS_AS(readMovingTruth(dir / "labels", 3), IoError);  // no 000002.label
    fs::remove_all(dir);
}

TEST_CASE("The labels of every simulator layout are found from gt/", "[eval][traffic]") {
    const fs::path dir = fs::temp_directory_path() / "vdbmap_evaltraffic_layouts";
    fs::remove_all(dir);
    fs::create_directories(dir / "a" / "gt");
    CHECK(findSimLabelsDir(dir / "a" / "gt").empty());
    fs::create_directories(dir / "a" / "labels");  // sequence layout
    CHECK(findSimLabelsDir(dir / "a" / "gt") == dir / "a" / "labels");
    fs::create_directories(dir / "b" / "gt" / "labels");  // kitti360
    CHECK(findSimLabelsDir(dir / "b" / "gt") == dir / "b" / "gt" / "labels");
    fs::create_directories(dir / "c" / "gt");  // semantic-kitti
    fs::create_directories(dir / "c" / "dataset" / "sequences" / "04" / "labels");
    CHECK(findSimLabelsDir(dir / "c" / "gt") ==
          dir / "c" / "dataset" / "sequences" / "04" / "labels");
    fs::remove_all(dir);
}
