// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include <set>

#include "vdbmap/Error.h"
#include "vdbmap/sim/Scenes.h"
#include "vdbmap/sim/SimScene.h"

using namespace vdbmap;

namespace {

Vec3f faceNormal(const SimScene& s, std::size_t f) {
    const auto& t = s.mesh.triangles[f];
    const Vec3f& a = s.mesh.positions[t.v[0]];
    return (s.mesh.positions[t.v[1]] - a).cross(s.mesh.positions[t.v[2]] - a).normalized();
}

Vec3f centroid(const SimScene& s, std::size_t f) {
    const auto& t = s.mesh.triangles[f];
    return (s.mesh.positions[t.v[0]] + s.mesh.positions[t.v[1]] + s.mesh.positions[t.v[2]]) /
           3.0f;
}

}  // namespace

TEST_CASE("addBox builds a closed box with outward normals", "[sim]") {
    SimScene s;
    const auto m = s.addMaterial("grey", cv::Mat(2, 2, CV_8UC3, cv::Scalar(128, 128, 128)));
    Isometry3d pose = Isometry3d::Identity();
    pose.linear() = Eigen::AngleAxisd(0.3, Vec3d::UnitZ()).toRotationMatrix();
    pose.translation() = Vec3d(1, 2, 3);
    s.addBox(pose, Vec3f(1.0f, 0.5f, 0.25f), 1.0f, m, 13);
    REQUIRE(s.numTriangles() == 12);
    REQUIRE(s.face_labels.size() == 12);
    double area = 0;
    for (std::size_t f = 0; f < s.numTriangles(); ++f) {
        CHECK(s.face_labels[f] == 13);
        const Vec3f out = centroid(s, f) - Vec3f(1, 2, 3);
        CHECK(faceNormal(s, f).dot(out) > 0.0f);
        const auto& t = s.mesh.triangles[f];
        area += 0.5 * (s.mesh.positions[t.v[1]] - s.mesh.positions[t.v[0]])
                          .cross(s.mesh.positions[t.v[2]] - s.mesh.positions[t.v[0]])
                          .norm();
    }
    // Closed-form surface area 2 (ab + bc + ca) of a 2 x 1 x 0.5 box.
    CHECK(area == Approx(2.0 * (2.0 * 1.0 + 1.0 * 0.5 + 0.5 * 2.0)).epsilon(1e-5));
    CHECK_THROWS_AS(s.addMaterial("empty", cv::Mat()), InvalidInput);
}

TEST_CASE("addQuad UVs tile every tile_m metres", "[sim]") {
    SimScene s;
    const auto m = s.addMaterial("t", cv::Mat(2, 2, CV_8UC3, cv::Scalar(0, 0, 0)));
    s.addQuad({0, 0, 0}, {4, 0, 0}, {4, 2, 0}, {0, 2, 0}, 2.0f, m, 0);
    REQUIRE(s.numTriangles() == 2);
    // Corner (4, 2) -> uv (2, 1).
    const auto& t = s.mesh.triangles[0];
    CHECK(s.mesh.uvs[t.vt[2]].isApprox(Eigen::Vector2f(2.0f, 1.0f)));
    CHECK(faceNormal(s, 0).z() == Approx(1.0f));
}

TEST_CASE("Street scene has every class and is deterministic", "[sim]") {
    StreetSceneOptions o;
    o.length_m = 40;
    o.frames = 5;
    o.seed = 3;
    o.spot_dir = std::string(VDBMAP_TEST_DATA_DIR) + "/meshes";
    const SceneSetup a = buildStreetScene(o);
    const SceneSetup b = buildStreetScene(o);
    REQUIRE(a.scene.numTriangles() == b.scene.numTriangles());
    CHECK(a.scene.mesh.positions == b.scene.mesh.positions);
    const std::set<int> labels(a.scene.face_labels.begin(), a.scene.face_labels.end());
    for (int id : {0, 1, 2, 5, 7, 8, 13, 19, 20}) {
        INFO("class " << id);
        CHECK(labels.count(id) == 1);
    }
    CHECK(a.scene.textures.size() == a.scene.mesh.materials.size());
    REQUIRE(a.T_S_V.size() == 5);
    // The vehicle drives along +x in the right lane.
    CHECK(a.T_S_V.back().translation().x() > a.T_S_V.front().translation().x());
    CHECK(a.T_S_V.front().translation().y() == Approx(-1.75));
    o.seed = 4;
    const SceneSetup c = buildStreetScene(o);
    CHECK(c.scene.mesh.positions != a.scene.mesh.positions);
    o.length_m = 5;
    CHECK_THROWS_AS(buildStreetScene(o), InvalidInput);
}

TEST_CASE("SUV scene: car-sized SUV, 10 m circle at 5 m/s and 10 Hz", "[sim]") {
    SuvSceneOptions o;
    o.frames = 126;
    const SceneSetup s = buildSuvScene(o);
    Vec3f lo = Vec3f::Constant(1e9f), hi = Vec3f::Constant(-1e9f);
    for (std::size_t f = 0; f < s.scene.numTriangles(); ++f) {
        if (s.scene.face_labels[f] != 13) continue;
        for (auto v : s.scene.mesh.triangles[f].v) {
            lo = lo.cwiseMin(s.scene.mesh.positions[v]);
            hi = hi.cwiseMax(s.scene.mesh.positions[v]);
        }
    }
    const Vec3f size = hi - lo;
    CHECK(size.x() == Approx(5.1).margin(0.3));
    CHECK(size.y() == Approx(2.0).margin(0.3));
    CHECK(size.z() == Approx(1.9).margin(0.2));
    CHECK(lo.z() == Approx(0.0).margin(0.01));  // wheels touch the ground
    REQUIRE(s.T_S_V.size() == 126);
    for (std::size_t f = 0; f + 1 < s.T_S_V.size(); ++f) {
        CHECK(s.T_S_V[f].translation().norm() == Approx(10.0));
        // 5 m/s at 10 Hz: 0.5 m of arc per frame.
        CHECK((s.T_S_V[f + 1].translation() - s.T_S_V[f].translation()).norm() ==
              Approx(0.5).epsilon(0.01));
    }
    CHECK(s.lidar_height_m == Approx(2.3));
}
