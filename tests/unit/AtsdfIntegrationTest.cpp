// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "support/MapTestUtil.h"
#include "support/PlainAtsdfConfig.h"
#include "support/SimLidar.h"
#include "vdbmap/Error.h"
#include "vdbmap/map/AtsdfIntegrator.h"
#include "vdbmap/map/BlockStats.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/mesh/MarchingCubes.h"

using namespace vdbmap;
using namespace vdbmap::test;

TEST_CASE("Bad input is counted and skipped", "[tsdf][integrate]") {
    VoxelMap map(0.1, 0.3f);
    AtsdfIntegrator integrator(map, plainAtsdfConfig());
    const Vec3d origin(1, 2, 3);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    std::vector<Vec3f> pts = {Vec3f(nan, 0, 0), Vec3f(0, inf, 0), origin.cast<float>(),
                              Vec3f(1e9f, 0, 0), Vec3f(1, 2, 0), Vec3f(1.05f, 2, 0)};
    const IntegrationStats s = integrator.integrateScan(pts, origin);
    CHECK(s.points_in == 6);
    CHECK(s.dropped_non_finite == 2);
    CHECK(s.dropped_at_origin == 1);
    CHECK(s.dropped_range == 1);
    CHECK(s.points_integrated == 2);
    CHECK(s.voxel_updates > 0);
    CHECK(map.activeVoxelCount() > 0);

    SECTION("an empty scan is a no-op") {
        const auto before = map.activeVoxelCount();
        const IntegrationStats e = integrator.integrateScan(std::vector<Vec3f>{}, origin);
        CHECK(e.points_in == 0);
        CHECK(e.voxel_updates == 0);
        CHECK(map.activeVoxelCount() == before);
    }
    SECTION("a non-finite sensor origin drops the whole scan") {
        const IntegrationStats e =
            integrator.integrateScan(pts, Vec3d(std::numeric_limits<double>::quiet_NaN(), 0, 0));
        CHECK(e.dropped_non_finite == pts.size());
        CHECK(e.voxel_updates == 0);
    }
}

TEST_CASE("Bad configuration is rejected with the key name", "[tsdf][integrate]") {
    VoxelMap map(0.1);
    AtsdfConfig c = plainAtsdfConfig();
    c.weight_floor = 0.0;
    CHECK_THROWS_WITH(AtsdfIntegrator(map, c), Catch::Contains("weight_floor"));
    AtsdfConfig ws = plainAtsdfConfig();
    ws.working_set_scans = 0;
    CHECK_THROWS_WITH(AtsdfIntegrator(map, ws),
                      Catch::Contains("working_set_scans") && Catch::Contains("got 0"));
    AtsdfConfig merge = plainAtsdfConfig();
    merge.merge_divisions = 3;
    CHECK_THROWS_WITH(AtsdfIntegrator(map, merge),
                      Catch::Contains("merge_divisions") && Catch::Contains("got 3"));
    CHECK_THROWS_AS(VoxelMap(-0.1), InvalidInput);
    CHECK_THROWS_AS(VoxelMap(std::nan("")), InvalidInput);
}

TEST_CASE("Plane at a non-voxel-aligned offset: SDF and mesh match the closed form",
          "[tsdf][integrate]") {
    const double vs = 0.1, z0 = -1.6663, sigma = 0.005;
    SimScene scene;
    scene.add(SimPlane{Vec3d(0, 0, z0), Vec3d::UnitZ()});
    SimLidarConfig lidar;
    lidar.azimuth_steps = 1024;
    lidar.noise_sigma_m = sigma;
    std::vector<Isometry3d> poses;
    for (int i = 0; i < 4; ++i) poses.push_back(poseAt(Vec3d(0.37 * i, 0.11 * i, 0.0)));

    VoxelMap map(vs, 0.3f);
    AtsdfIntegrator integrator(map, plainAtsdfConfig());
    const IntegrationStats s = integrateScans(integrator, scene, lidar, poses);
    REQUIRE(s.points_integrated > 20000);

    // Every observed voxel (weight >= 1, within 10 m, not clamped) against z - z0.
    std::size_t checked = 0;
    double max_err = 0.0;
    const TsdfCodec& codec = map.codec();
    const BlockStatsGrid& blocks = map.blockStats();
    map.forEachVoxel([&](const openvdb::Coord& c, std::uint32_t packed) {
        const Vec3d x(c.x() * vs, c.y() * vs, c.z() * vs);
        const double truth = x.z() - z0;
        if (std::hypot(x.x(), x.y()) > 10.0 || std::abs(truth) > 0.1 || codec.weight(packed) < 1.0f)
            return;
        const auto slot = blocks.find(BlockStatsGrid::blockOf(c));
        if (slot < 0 || !blocks.entry(slot).plane_valid) return;
        max_err = std::max(max_err, std::abs(codec.sdf(packed) - truth));
        ++checked;
    });
    INFO("checked " << checked << " voxels, max error " << max_err);
    REQUIRE(checked > 1000);
    CHECK(max_err <= 0.1 * vs + 3.0 * sigma);

    const auto mesh = extractMesh(map, MarchingCubesConfig{});
    REQUIRE(mesh->n_faces() > 1000);
    double max_v = 0.0;
    std::size_t near = 0;
    TriMesh::Point worst(0, 0, 0);
    for (auto v : mesh->vertices()) {
        const auto p = mesh->point(v);
        if (std::hypot(p[0], p[1]) > 10.0) continue;
        if (std::abs(p[2] - z0) > max_v) worst = p;
        max_v = std::max(max_v, std::abs(p[2] - z0));
        ++near;
    }
    INFO("vertices " << near << " max |z - z0| " << max_v << " at " << worst[0] << " " << worst[1]
                     << " " << worst[2]);
    CHECK(near > 1000);
    CHECK(max_v <= 0.1 * vs + 3.0 * sigma);
    // Normals point up, towards the sensor side.
    float min_nz = 1.0f;
    for (auto v : mesh->vertices())
        if (std::hypot(mesh->point(v)[0], mesh->point(v)[1]) < 10.0)
            min_nz = std::min(min_nz, mesh->normal(v)[2]);
    CHECK(min_nz > 0.9f);
}

TEST_CASE("Fixed mode runs through the same code path with eps_max everywhere",
          "[tsdf][integrate]") {
    SimScene scene;
    scene.add(SimPlane{Vec3d(0, 0, -1.7), Vec3d::UnitZ()});
    SimLidarConfig lidar;
    lidar.azimuth_steps = 512;
    VoxelMap map(0.1, 0.3f);
    AtsdfConfig c = plainAtsdfConfig();
    c.truncation.mode = TruncationMode::Fixed;
    AtsdfIntegrator integrator(map, c);
    integrateScans(integrator, scene, lidar, {poseAt(Vec3d::Zero())});
    const BlockStatsGrid& blocks = map.blockStats();
    REQUIRE(blocks.size() > 0);
    for (std::size_t i = 0; i < blocks.size(); ++i)
        CHECK(blocks.entry(static_cast<std::int32_t>(i)).truncation_m == Approx(0.3f));
    integrator.finalize();
    const auto trunc = map.truncationGrid(0.3f);
    REQUIRE(trunc->activeVoxelCount() == map.activeVoxelCount());
    for (auto it = trunc->cbeginValueOn(); it; ++it) CHECK(*it == Approx(0.3f));
}

TEST_CASE("Space carving pushes previously observed voxels towards free space",
          "[tsdf][integrate]") {
    // A wall at x = 5 is observed, then removed; the wall behind at x = 8 is seen instead.
    SimScene with_wall, without_wall;
    with_wall.add(SimPlane{Vec3d(5, 0, 0), -Vec3d::UnitX()});
    without_wall.add(SimPlane{Vec3d(8, 0, 0), -Vec3d::UnitX()});
    SimLidarConfig lidar;
    lidar.azimuth_steps = 256;
    lidar.elevation_min_deg = -10;
    lidar.elevation_max_deg = 10;
    lidar.beams = 32;
    auto run = [&](bool carve) {
        VoxelMap map(0.1, 0.3f);
        AtsdfConfig c = plainAtsdfConfig();
        c.space_carving = carve;
        AtsdfIntegrator integrator(map, c);
        integrateScans(integrator, with_wall, lidar, {poseAt(Vec3d::Zero())});
        IntegrationStats s;
        for (int i = 0; i < 5; ++i)
            s += integrateScans(integrator, without_wall, lidar, {poseAt(Vec3d::Zero())});
        float sdf = 0.0f, weight = 0.0f;
        map.probeVoxel(openvdb::Coord(51, 0, 0), sdf, weight);
        return std::make_pair(sdf, s.carving_updates);
    };
    const auto [kept, no_updates] = run(false);
    const auto [carved, updates] = run(true);
    CHECK(no_updates == 0);
    CHECK(updates > 0);
    CHECK(kept < 0.0f);    // just behind the old wall: still "inside"
    CHECK(carved > 0.0f);  // carving made it free space
}

TEST_CASE("The band to the next ring stops where that ring lands off the surface",
          "[tsdf][integrate]") {
    // A flat roof (a van's, 0.73 m above the ground) seen at grazing incidence from 5 to 8 m.
    // Behind a point near its far edge the scan's next ring lands on the ground, not on the
    // roof, so the band behind must not carry the roof's plane past the edge (issue 16: the
    // extrapolated roofs cost F at [0.4, 0.8]). The landing check looks up the block the next
    // ring lands in, so the edge is put at a block boundary (x = 7.95 is where the blocks of
    // 8 voxels of 0.1 m start; the roof ends at 7.9).
    SimScene scene;
    scene.add(SimPlane{Vec3d(0, 0, -1.73), Vec3d::UnitZ()});
    scene.add(SimBox{Vec3d(5.0, -1.0, -1.73), Vec3d(7.9, 1.0, -1.0)});
    SimLidarConfig lidar;
    lidar.azimuth_steps = 2048;
    std::vector<Isometry3d> poses;
    for (int i = 0; i < 4; ++i) poses.push_back(poseAt(Vec3d(-0.25 * i, 0.0, 0.0)));
    // Voxels observed at the roof's height from 0.2 m beyond its edge (past the short band's
    // reach), and on the roof itself, per setting of the band behind.
    struct Counts {
        std::size_t beyond_edge = 0, roof = 0;
    };
    auto run = [&](bool next_ring, bool both_sides) {
        VoxelMap map(0.1, 0.3f);
        AtsdfConfig c = plainAtsdfConfig();
        c.truncation.min_m = 0.1;
        c.truncation.max_m = 0.3;
        c.truncation.max_along_ray_m = 1.0;  // lets the band behind reach g ~ 0.6 m here
        c.truncation.grazing_band_to_next_ring = next_ring;
        c.truncation.grazing_band_both_sides = both_sides;
        AtsdfIntegrator integrator(map, c);
        integrateScans(integrator, scene, lidar, poses);
        Counts n;
        const TsdfCodec& codec = map.codec();
        map.forEachVoxel([&](const openvdb::Coord& v, std::uint32_t packed) {
            if (!(codec.weight(packed) > 0.0f) || std::abs(v.y()) > 8 || v.z() < -12 || v.z() > -9) return;
            if (v.x() >= 81 && v.x() <= 90) ++n.beyond_edge;
            if (v.x() >= 55 && v.x() <= 75) ++n.roof;
        });
        return n;
    };
    const Counts short_band = run(false, false), next_ring = run(true, false), both = run(false, true);
    INFO("beyond the edge: short " << short_band.beyond_edge << ", next ring " << next_ring.beyond_edge
                                   << ", both sides " << both.beyond_edge << "; on the roof: short "
                                   << short_band.roof << ", next ring " << next_ring.roof
                                   << ", both sides " << both.roof);
    // The band that always reaches on (both sides, to L_max) does fill the space past the edge:
    // the region is within reach of the roof's rays.
    REQUIRE(both.beyond_edge > 100);
    // The band to the next ring reaches further behind the roof's own points...
    CHECK(next_ring.roof > short_band.roof);
    // ...but not past its edge. Measured: short 0, next ring 0, both sides 136 beyond the edge
    // (689 / 912 / 1102 on the roof); the reference integrator without the landing check puts
    // 62 voxels there.
    CHECK(next_ring.beyond_edge <= short_band.beyond_edge + both.beyond_edge / 20);
}
