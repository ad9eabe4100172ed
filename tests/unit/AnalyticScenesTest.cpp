// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include "support/MapTestUtil.h"
#include "support/PlainAtsdfConfig.h"
#include "support/SimLidar.h"
#include "vdbmap/map/AtsdfIntegrator.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/mesh/MarchingCubes.h"

using namespace vdbmap;
using namespace vdbmap::test;

namespace {

/// Scans `scene` from 14 directions around `centre` (fully observed) and meshes it.
std::shared_ptr<TriMesh> scanAndMesh(const SimScene& scene, const Vec3d& centre, double vs) {
    SimLidarConfig lidar;
    lidar.beams = 64;
    lidar.azimuth_steps = 1024;
    lidar.elevation_min_deg = -20.0;
    lidar.elevation_max_deg = 20.0;
    lidar.noise_sigma_m = 0.002;
    VoxelMap map(vs, 0.15f);
    AtsdfConfig c = plainAtsdfConfig();
    c.truncation.min_m = 2 * vs;
    c.truncation.max_m = 3 * vs;
    AtsdfIntegrator integrator(map, c);
    integrateScans(integrator, scene, lidar, posesAround(centre, 4.0));
    MarchingCubesConfig mc;
    mc.min_component_faces = 50;  // isolated specks at the truncation band's outer edge
    return extractMesh(map, mc);
}

}  // namespace

TEST_CASE("Sphere seen from all sides: mesh within one voxel, watertight", "[tsdf][analytic]") {
    const double vs = 0.05;
    const Vec3d c(0.013, -0.021, 0.034);
    SimScene scene;
    scene.add(SimSphere{c, 1.0});
    const auto mesh = scanAndMesh(scene, c, vs);
    REQUIRE(mesh->n_faces() > 2000);
    double max_err = 0.0;
    for (auto v : mesh->vertices()) {
        const auto p = mesh->point(v);
        max_err = std::max(max_err, std::abs(scene.sdf(Vec3d(p[0], p[1], p[2]))));
    }
    INFO("max vertex error " << max_err);
    CHECK(max_err <= vs);
    CHECK(boundaryEdgeCount(*mesh) == 0);
    CHECK(static_cast<long>(mesh->n_vertices()) - static_cast<long>(mesh->n_edges()) +
              static_cast<long>(mesh->n_faces()) == 2);
}

TEST_CASE("Box seen from all sides: mesh within one voxel, watertight", "[tsdf][analytic]") {
    const double vs = 0.05;
    const Vec3d lo(-0.61, -0.43, -0.29), hi(0.63, 0.38, 0.31);
    SimScene scene;
    scene.add(SimBox{lo, hi});
    const auto mesh = scanAndMesh(scene, 0.5 * (lo + hi), vs);
    REQUIRE(mesh->n_faces() > 1000);
    double max_err = 0.0;
    for (auto v : mesh->vertices()) {
        const auto p = mesh->point(v);
        max_err = std::max(max_err, std::abs(scene.sdf(Vec3d(p[0], p[1], p[2]))));
    }
    INFO("max vertex error " << max_err);
    CHECK(max_err <= vs);
    CHECK(boundaryEdgeCount(*mesh) == 0);
}
