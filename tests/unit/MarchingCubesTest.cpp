// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>

#include "mesh/CubeTable.h"
#include "support/MapTestUtil.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/mesh/MarchingCubes.h"
#include "vdbmap/mesh/MeshCleanup.h"

using namespace vdbmap;
using namespace vdbmap::test;

namespace {

/// Writes the exact sphere SDF into the map's narrow band (weight 1) wherever `observed`.
template <typename Observed>
void writeSphere(VoxelMap& map, const Vec3d& c, double r, Observed observed) {
    const double vs = map.voxelSize();
    const int lo_x = static_cast<int>(std::floor((c.x() - r) / vs)) - 4;
    const int hi_x = static_cast<int>(std::ceil((c.x() + r) / vs)) + 4;
    const int lo_y = static_cast<int>(std::floor((c.y() - r) / vs)) - 4;
    const int hi_y = static_cast<int>(std::ceil((c.y() + r) / vs)) + 4;
    const int lo_z = static_cast<int>(std::floor((c.z() - r) / vs)) - 4;
    const int hi_z = static_cast<int>(std::ceil((c.z() + r) / vs)) + 4;
    for (int x = lo_x; x <= hi_x; ++x)
        for (int y = lo_y; y <= hi_y; ++y)
            for (int z = lo_z; z <= hi_z; ++z) {
                const Vec3d p(x * vs, y * vs, z * vs);
                const double d = (p - c).norm() - r;
                if (std::abs(d) > 3 * vs || !observed(p)) continue;
                map.setVoxel(openvdb::Coord(x, y, z), static_cast<float>(d), 1.0f);
            }
}

}  // namespace

TEST_CASE("Generated case table: complementary cases have the same triangle count",
          "[mesh][mc]") {
    const auto& t = detail::cubeTable();
    CHECK(t.triangles[0].empty());
    CHECK(t.triangles[255].empty());
    CHECK(t.triangles[1].size() == 1);  // one corner cut off
    for (int m = 1; m < 255; ++m) {
        INFO("case " << m);
        CHECK(!t.triangles[static_cast<std::size_t>(m)].empty());
    }
}

TEST_CASE("Sphere SDF: vertices on the sphere, watertight, welded, outward normals",
          "[mesh][mc]") {
    const double vs = 0.05, r = 1.0;
    const Vec3d c(0.013, 0.021, -0.037);
    VoxelMap map(vs, 0.15f);
    writeSphere(map, c, r, [](const Vec3d&) { return true; });
    MeshStats stats;
    const auto mesh = extractMesh(map, MarchingCubesConfig{}, &stats);
    REQUIRE(mesh->n_faces() > 1000);
    CHECK(stats.faces_rejected_nonmanifold == 0);
    double max_err = 0.0;
    for (auto v : mesh->vertices()) {
        const auto p = mesh->point(v);
        max_err = std::max(max_err, std::abs((Vec3d(p[0], p[1], p[2]) - c).norm() - r));
    }
    CHECK(max_err < 0.1 * vs);
    CHECK(boundaryEdgeCount(*mesh) == 0);
    // Welded closed sphere: Euler characteristic V - E + F = 2.
    CHECK(static_cast<long>(mesh->n_vertices()) - static_cast<long>(mesh->n_edges()) +
              static_cast<long>(mesh->n_faces()) == 2);
    float min_dot = 1.0f;
    for (auto f : mesh->faces()) {
        const auto centre = mesh->calc_face_centroid(f);
        const Vec3d radial = (Vec3d(centre[0], centre[1], centre[2]) - c).normalized();
        const auto n = mesh->normal(f);
        min_dot = std::min(min_dot, static_cast<float>(radial.dot(Vec3d(n[0], n[1], n[2]))));
    }
    CHECK(min_dot > 0.5f);
    for (auto v : mesh->vertices()) {
        const auto p = mesh->point(v);
        const Vec3d radial = (Vec3d(p[0], p[1], p[2]) - c).normalized();
        const auto n = mesh->normal(v);
        min_dot = std::min(min_dot, static_cast<float>(radial.dot(Vec3d(n[0], n[1], n[2]))));
    }
    CHECK(min_dot > 0.9f);
}

TEST_CASE("No faces between observed and unobserved space", "[mesh][mc]") {
    const double vs = 0.05;
    const Vec3d c(0, 0, 0);
    VoxelMap map(vs, 0.15f);
    writeSphere(map, c, 1.0, [](const Vec3d& p) { return p.x() < 0.3; });
    const auto mesh = extractMesh(map, MarchingCubesConfig{});
    REQUIRE(mesh->n_faces() > 500);
    float max_x = -1e9f;
    for (auto v : mesh->vertices()) max_x = std::max(max_x, mesh->point(v)[0]);
    CHECK(max_x <= 0.3f);
    CHECK(boundaryEdgeCount(*mesh) > 0);  // open where the data stop

    SECTION("min_weight excludes weakly observed voxels") {
        const TsdfCodec& codec = map.codec();
        std::vector<std::pair<openvdb::Coord, float>> weak;
        map.forEachVoxel([&](const openvdb::Coord& c, std::uint32_t packed) {
            if (c.x() * vs < -0.5) weak.emplace_back(c, codec.sdf(packed));
        });
        REQUIRE(!weak.empty());
        for (const auto& [c, sdf] : weak) map.setVoxel(c, sdf, 0.05f);
        MarchingCubesConfig cfg;
        cfg.min_weight = 0.1;
        const auto cut = extractMesh(map, cfg);
        float min_x = 1e9f;
        for (auto v : cut->vertices()) min_x = std::min(min_x, cut->point(v)[0]);
        CHECK(min_x >= -0.5f);
        CHECK(cut->n_faces() < mesh->n_faces());
    }
}

TEST_CASE("Small connected components are removed", "[mesh][mc]") {
    const double vs = 0.05;
    VoxelMap big_only(vs, 0.15f), both(vs, 0.15f);
    writeSphere(big_only, Vec3d(0, 0, 0), 1.0, [](const Vec3d&) { return true; });
    writeSphere(both, Vec3d(0, 0, 0), 1.0, [](const Vec3d&) { return true; });
    writeSphere(both, Vec3d(3, 0, 0), 0.15, [](const Vec3d&) { return true; });
    const auto ref = extractMesh(big_only, MarchingCubesConfig{});
    const auto all = extractMesh(both, MarchingCubesConfig{});
    REQUIRE(all->n_faces() > ref->n_faces());
    MarchingCubesConfig cfg;
    cfg.min_component_faces = 500;
    MeshStats stats;
    const auto cleaned = extractMesh(both, cfg, &stats);
    CHECK(stats.components_removed == 1);
    CHECK(cleaned->n_faces() == ref->n_faces());
    CHECK(cleaned->n_vertices() == ref->n_vertices());
    CHECK(stats.faces_removed_small_components == all->n_faces() - ref->n_faces());
}

TEST_CASE("removeSmallComponents on index triangles", "[mesh][mc]") {
    std::vector<std::array<std::uint32_t, 3>> faces = {{0, 1, 2}, {1, 2, 3}, {4, 5, 6}};
    std::size_t removed = 0;
    CHECK(removeSmallComponents(faces, 7, 2, &removed) == 1);
    CHECK(removed == 1);
    REQUIRE(faces.size() == 2);
    CHECK(faces[1] == std::array<std::uint32_t, 3>{1, 2, 3});
}

TEST_CASE("Empty map gives an empty mesh", "[mesh][mc]") {
    VoxelMap map(0.1);
    const auto mesh = extractMesh(map, MarchingCubesConfig{});
    CHECK(mesh->n_faces() == 0);
    CHECK(mesh->n_vertices() == 0);
}

TEST_CASE("Surfaces through grid points: no collapsed or duplicate faces, still closed",
          "[mesh][mc]") {
    // An octahedron |x| + |y| + |z| <= 1 m (L1 ball) at 0.1 m voxels: its faces pass exactly
    // through grid points (the TSDF is exactly 0 there) whose neighbours along two or three
    // axes are inside, so several grid edges of one cube cross the surface at the same point.
    // Each such point is one vertex (not one per grid edge reaching it), so no face has zero
    // area, no face appears twice and the surface stays closed.
    VoxelMap map(0.1, 0.3f);
    for (int x = -14; x <= 14; ++x)
        for (int y = -14; y <= 14; ++y)
            for (int z = -14; z <= 14; ++z) {
                const int d_vox = std::abs(x) + std::abs(y) + std::abs(z) - 10;
                if (std::abs(d_vox) > 4) continue;
                map.setVoxel(openvdb::Coord(x, y, z), static_cast<float>(0.1 * d_vox / std::sqrt(3.0)), 1.0f);
            }
    const auto mesh = extractMesh(map, MarchingCubesConfig{});
    REQUIRE(mesh->n_faces() > 500);
    std::set<std::array<std::array<float, 3>, 3>> faces;
    std::size_t collapsed = 0;
    for (const auto fh : mesh->faces()) {
        std::array<std::array<float, 3>, 3> f{};
        int k = 0;
        for (const auto vh : mesh->fv_range(fh)) {
            const auto p = mesh->point(vh);
            f[static_cast<std::size_t>(k++)] = {p[0], p[1], p[2]};
        }
        if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) ++collapsed;
        std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
        CHECK(faces.insert(f).second);
    }
    CHECK(collapsed == 0);
    std::set<std::array<float, 3>> positions;
    for (const auto vh : mesh->vertices()) {
        const auto p = mesh->point(vh);
        CHECK(positions.insert({p[0], p[1], p[2]}).second);  // one vertex per point
    }
    CHECK(boundaryEdgeCount(*mesh) == 0);
    CHECK(static_cast<long>(mesh->n_vertices()) - static_cast<long>(mesh->n_edges()) +
              static_cast<long>(mesh->n_faces()) == 2);  // a sphere's topology
}
