// SPDX-License-Identifier: Apache-2.0
// The compact (observed voxels only) store of the TSDF and the working set of dense leaves:
// storing is lossless, readers see one map whichever store holds a leaf, and the working-set
// size changes the memory but never the map.
#include <catch2/catch.hpp>

#include <random>

#include "support/MapTestUtil.h"
#include "support/PlainAtsdfConfig.h"
#include "support/SimLidar.h"
#include "vdbmap/map/AtsdfIntegrator.h"
#include "vdbmap/map/CompactTsdf.h"
#include "vdbmap/map/TsdfReader.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/mesh/MarchingCubes.h"

using namespace vdbmap;
using namespace vdbmap::test;
using openvdb::Coord;

namespace {

/// A dense leaf with a random observed set of about `fill` of its voxels and random values.
void randomLeaf(std::mt19937_64& rng, double fill, CompactTsdf::Mask& mask, std::uint32_t* dense) {
    std::bernoulli_distribution on(fill);
    mask.setOff();
    for (openvdb::Index i = 0; i < TsdfLeaf::SIZE; ++i) {
        dense[i] = static_cast<std::uint32_t>(rng());
        if (on(rng)) mask.setOn(i);
    }
}

struct Drive {
    std::unique_ptr<VoxelMap> map;
    IntegrationStats stats;
    std::shared_ptr<TriMesh> mesh;
    std::size_t mixed_checks = 0;  ///< voxels compared mid-drive (both stores in use)
};

/// A short-range LiDAR driving 12 m along x and back: leaves leave its reach, go compact, and
/// come back into the working set on the way back.
Drive drive(int working_set_scans, bool carving) {
    SimScene scene;
    scene.add(SimPlane{Vec3d(0, 0, -1.73), Vec3d::UnitZ()});
    scene.add(SimSphere{Vec3d(4.2, 3.1, -0.5), 1.0});
    scene.add(SimBox{Vec3d(9, -4, -1.73), Vec3d(11, -2.5, 0.2)});
    SimLidarConfig lidar;
    lidar.azimuth_steps = 512;
    lidar.max_range_m = 9.0;
    lidar.noise_sigma_m = 0.01;
    Drive d;
    d.map = std::make_unique<VoxelMap>(0.1, 0.3f);
    AtsdfConfig c = plainAtsdfConfig();
    c.working_set_scans = working_set_scans;
    c.space_carving = carving;
    AtsdfIntegrator integrator(*d.map, c);
    std::vector<Isometry3d> poses;
    for (int i = 0; i <= 12; ++i) poses.push_back(poseAt(Vec3d(1.0 * i, 0.1 * i, 0)));
    for (int i = 11; i >= 0; --i) poses.push_back(poseAt(Vec3d(1.0 * i + 0.5, 0.1 * i, 0)));
    for (std::size_t i = 0; i < poses.size(); ++i) {
        d.stats += integrator.integrateScan(simulateScan(scene, lidar, poses[i], i), poses[i]);
        if (i == 15) {  // mid-drive: the three read paths agree, whichever store holds a leaf
            TsdfReader reader(*d.map);
            d.map->forEachVoxel([&](const Coord& ijk, std::uint32_t packed) {
                std::uint32_t via_reader = 0;
                float sdf = 0, w = 0;
                const bool r_on = reader.probe(ijk, via_reader);
                const bool p_on = d.map->probeVoxel(ijk, sdf, w);
                if (!(r_on && p_on && via_reader == packed && sdf == d.map->codec().sdf(packed) &&
                      w == d.map->codec().weight(packed)))
                    FAIL("read paths disagree at " << ijk);
                ++d.mixed_checks;
            });
        }
    }
    integrator.finalize();
    d.mesh = extractMesh(*d.map, MarchingCubesConfig{});
    return d;
}

}  // namespace

TEST_CASE("CompactTsdf stores the observed voxels of a leaf losslessly", "[tsdf][compact]") {
    std::mt19937_64 rng(7);
    CompactTsdf store;
    std::vector<std::uint32_t> dense(TsdfLeaf::SIZE);
    std::vector<std::uint32_t> back(TsdfLeaf::SIZE);
    std::size_t expected_voxels = 0;
    for (int leaf = 0; leaf < 40; ++leaf) {
        const double fill = leaf == 0 ? 1.0 : (leaf % 5) * 0.2 + 0.01;
        CompactTsdf::Mask mask;
        randomLeaf(rng, fill, mask, dense.data());
        const Coord origin(8 * leaf, -8 * (leaf % 3), 16);
        store.insert(origin, mask, CompactTsdf::encode(mask, dense.data()));
        expected_voxels += mask.countOn();

        const TsdfLeafView view = store.view(origin);
        REQUIRE(view.mask != nullptr);
        std::size_t rank = 0;
        for (openvdb::Index i = 0; i < TsdfLeaf::SIZE; ++i) {
            REQUIRE(view.observed(i) == mask.isOn(i));
            if (!mask.isOn(i)) continue;
            REQUIRE(view.rank(i) == rank++);  // mask order
            REQUIRE(view.value(i) == dense[i]);
        }
        // Decode restores the mask and the observed values, and leaves the others alone.
        std::fill(back.begin(), back.end(), 0xDEADBEEFu);
        CompactTsdf::Mask decoded;
        CompactTsdf::decode(view, decoded, back.data());
        CHECK(decoded == mask);
        for (openvdb::Index i = 0; i < TsdfLeaf::SIZE; ++i)
            REQUIRE(back[i] == (mask.isOn(i) ? dense[i] : 0xDEADBEEFu));
    }
    CHECK(store.leafCount() == 40);
    CHECK(store.voxelCount() == expected_voxels);

    SECTION("findObserved gives a writable value, nullptr where unobserved") {
        openvdb::tree::ValueAccessor<const CompactTsdf::TopologyTree, false> acc(store.topology());
        const Coord full(0, 0, 16);  // leaf 0: every voxel observed
        std::uint32_t* v = store.findObserved(full.offsetBy(3, 4, 5), acc);
        REQUIRE(v != nullptr);
        *v = 42u;
        CHECK(store.view(full).value(TsdfLeaf::coordToOffset(full.offsetBy(3, 4, 5))) == 42u);
        CHECK(store.findObserved(Coord(-800, 0, 0), acc) == nullptr);  // no leaf
        CompactTsdf::Mask none;
        store.insert(Coord(800, 0, 0), none, CompactTsdf::encode(none, dense.data()));
        CHECK(store.view(Coord(800, 0, 0)).mask == nullptr);  // an empty leaf is not stored
    }
    SECTION("replacing and erasing keep the counts") {
        CompactTsdf::Mask one;
        one.setOn(17);
        dense[17] = 5u;
        store.insert(Coord(0, 0, 16), one, CompactTsdf::encode(one, dense.data()));
        CHECK(store.leafCount() == 40);
        CHECK(store.voxelCount() == expected_voxels - TsdfLeaf::SIZE + 1);
        CHECK(store.view(Coord(0, 0, 16)).value(17) == 5u);
        store.erase(Coord(0, 0, 16));
        store.erase(Coord(0, 0, 16));  // absent: no-op
        CHECK(store.leafCount() == 39);
        CHECK(store.voxelCount() == expected_voxels - TsdfLeaf::SIZE);
        CHECK(store.view(Coord(0, 0, 16)).mask == nullptr);
    }
}

TEST_CASE("the working-set size changes the memory, never the map", "[tsdf][compact]") {
    for (bool carving : {false, true}) {
        INFO("space carving " << carving);
        const Drive small = drive(1, carving);
        const Drive large = drive(1000, carving);
        // The small working set really moved leaves both ways; the large one never did.
        CHECK(small.stats.leaves_retired > 100);
        CHECK(small.stats.leaves_reloaded > 50);
        CHECK(large.stats.leaves_retired == 0);
        CHECK(small.mixed_checks > 10000);
        if (carving) CHECK(small.stats.carving_updates > 0);
        CHECK(small.stats.carving_updates == large.stats.carving_updates);
        CHECK(small.stats.voxel_updates == large.stats.voxel_updates);
        // Bit-identical voxels, identical meshes.
        const auto a = voxelsOf(*small.map);
        const auto b = voxelsOf(*large.map);
        REQUIRE(a.size() > 20000);
        REQUIRE(a.size() == b.size());
        CHECK(a == b);
        REQUIRE(small.mesh->n_faces() == large.mesh->n_faces());
        REQUIRE(small.mesh->n_vertices() == large.mesh->n_vertices());
        bool same_points = true;
        for (auto v : small.mesh->vertices())
            same_points = same_points && small.mesh->point(v) == large.mesh->point(v);
        CHECK(same_points);
        // At rest every leaf is compact: far below the same topology held in dense leaves.
        CHECK(small.map->workingLeafCount() == 0);
        CHECK(large.map->workingLeafCount() == 0);
        TsdfTree dense(0u);
        for (const TsdfLeafView& v : small.map->leafViews()) {
            TsdfLeaf* leaf = dense.touchLeaf(v.origin);
            v.forEachObserved([&](openvdb::Index i) { leaf->setValueOn(i); });
        }
        CHECK(dense.activeVoxelCount() == small.map->activeVoxelCount());
        CHECK(static_cast<double>(small.map->tsdfMemoryBytes()) <
              0.6 * static_cast<double>(dense.memUsage()));
        // The budget, <= 16 B per active voxel (distance and weight, internal nodes
        // included), holds at rest even on this small map.
        const double bytes_per_voxel = static_cast<double>(small.map->tsdfMemoryBytes()) /
                                       static_cast<double>(small.map->activeVoxelCount());
        INFO("at rest: " << bytes_per_voxel << " B per active voxel");
        CHECK(bytes_per_voxel <= 16.0);
    }
}

TEST_CASE("setVoxel on a compact leaf moves it back to the working tree", "[tsdf][compact]") {
    VoxelMap map(0.1, 0.3f);
    map.setVoxel(Coord(1, 2, 3), 0.05f, 2.0f);
    map.setVoxel(Coord(9, 2, 3), -0.05f, 1.0f);
    map.compact();
    REQUIRE(map.workingLeafCount() == 0);
    REQUIRE(map.compactTsdf().leafCount() == 2);
    map.setVoxel(Coord(2, 2, 3), 0.1f, 3.0f);
    CHECK(map.workingLeafCount() == 1);
    CHECK(map.compactTsdf().leafCount() == 1);
    CHECK(map.activeVoxelCount() == 3);
    float sdf = 0, w = 0;
    REQUIRE(map.probeVoxel(Coord(1, 2, 3), sdf, w));  // kept from the compact store
    CHECK(sdf == Approx(0.05f).margin(1e-4));
    CHECK(w == Approx(2.0f).margin(1e-2));
    REQUIRE(map.probeVoxel(Coord(9, 2, 3), sdf, w));
    CHECK(sdf == Approx(-0.05f).margin(1e-4));
    CHECK_FALSE(map.probeVoxel(Coord(3, 2, 3), sdf, w));
    CHECK(map.surfaceGrid()->activeVoxelCount() == 3);
}
