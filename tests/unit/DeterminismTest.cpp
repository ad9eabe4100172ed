// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include "support/MapTestUtil.h"
#include "support/PlainAtsdfConfig.h"
#include "support/SimLidar.h"
#include "vdbmap/map/AtsdfIntegrator.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/mesh/MarchingCubes.h"

using namespace vdbmap;
using namespace vdbmap::test;

namespace {

struct Result {
    std::unique_ptr<VoxelMap> map;
    std::shared_ptr<TriMesh> mesh;
};

Result runWithThreads(int threads, TruncationMode mode) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(threads));
    SimScene scene;
    scene.add(SimPlane{Vec3d(0, 0, -1.73), Vec3d::UnitZ()});
    scene.add(SimSphere{Vec3d(4.2, 1.1, -0.5), 1.0});
    scene.add(SimBox{Vec3d(-6, -3, -1.73), Vec3d(-3.5, -1.2, 0.2)});
    SimLidarConfig lidar;
    lidar.azimuth_steps = 1024;
    lidar.noise_sigma_m = 0.01;
    Result r;
    r.map = std::make_unique<VoxelMap>(0.1, 0.3f);
    AtsdfConfig c = plainAtsdfConfig();
    c.truncation.mode = mode;
    AtsdfIntegrator integrator(*r.map, c);
    integrateScans(integrator, scene, lidar,
                   {poseAt(Vec3d(0, 0, 0)), poseAt(Vec3d(0.8, 0.1, 0)), poseAt(Vec3d(1.6, 0.2, 0))});
    integrator.finalize();
    r.mesh = extractMesh(*r.map, MarchingCubesConfig{});
    return r;
}

}  // namespace

TEST_CASE("1 and N threads give the same map within 1e-6 on every voxel", "[tsdf][determinism]") {
    for (TruncationMode mode : {TruncationMode::Adaptive, TruncationMode::Paper, TruncationMode::Fixed}) {
        const Result one = runWithThreads(1, mode);
        const Result many = runWithThreads(4, mode);
        REQUIRE(one.map->activeVoxelCount() > 10000);
        CHECK(one.map->activeVoxelCount() == many.map->activeVoxelCount());
        CHECK(maxGridDifference(*one.map->surfaceGrid(), *many.map->surfaceGrid()) <= 1e-6);
        CHECK(maxGridDifference(*one.map->weightGrid(), *many.map->weightGrid()) <= 1e-6);
        // Topologies are identical (not only the values on the union).
        CHECK(one.map->workingLeafCount() == 0);
        CHECK(many.map->workingLeafCount() == 0);
        CHECK(one.map->compactTsdf().topology().hasSameTopology(many.map->compactTsdf().topology()));
        // The meshes are identical, vertex by vertex.
        REQUIRE(one.mesh->n_vertices() == many.mesh->n_vertices());
        REQUIRE(one.mesh->n_faces() == many.mesh->n_faces());
        double max_d = 0.0;
        for (auto v : one.mesh->vertices())
            max_d = std::max(max_d, static_cast<double>(
                                        (one.mesh->point(v) - many.mesh->point(v)).length()));
        CHECK(max_d == 0.0);
    }
}
