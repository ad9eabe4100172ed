// SPDX-License-Identifier: Apache-2.0
// Region meshing for tiled runs (issue 13): the core faces of the tiles of a partition are the
// untiled mesh, face for face at the same float positions, with no duplicates and no cracks.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>

#include "support/MapTestUtil.h"
#include "vdbmap/Error.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/mesh/MarchingCubes.h"
#include "vdbmap/mesh/TileFaces.h"
#include "vdbmap/pipeline/Tiling.h"

using namespace vdbmap;
using namespace vdbmap::test;

namespace {

using Point = std::array<float, 3>;
using Face = std::array<Point, 3>;

/// A face as its corner positions, rotated so the smallest corner comes first (keeps the
/// orientation).
Face canonical(const TriMesh& mesh, TriMesh::FaceHandle fh) {
    Face f{};
    int k = 0;
    for (const auto vh : mesh.fv_range(fh)) {
        const auto p = mesh.point(vh);
        f[static_cast<std::size_t>(k++)] = {p[0], p[1], p[2]};
    }
    const auto first = std::min_element(f.begin(), f.end()) - f.begin();
    std::rotate(f.begin(), f.begin() + first, f.end());
    return f;
}

std::multiset<Face> facesOf(const TriMesh& mesh, bool core_only) {
    const std::vector<std::uint8_t> halo = haloFaceMask(mesh);
    std::multiset<Face> faces;
    for (const auto fh : mesh.faces()) {
        if (core_only && halo[static_cast<std::size_t>(fh.idx())]) continue;
        faces.insert(canonical(mesh, fh));
    }
    return faces;
}

/// Exact SDF of a sphere and of the ground plane y = plane_y, min of both (union).
void writeScene(VoxelMap& map, const Vec3d& c, double r, double plane_y, int half_extent) {
    const double vs = map.voxelSize();
    for (int x = -half_extent; x <= half_extent; ++x)
        for (int y = -half_extent; y <= half_extent; ++y)
            for (int z = -half_extent; z <= half_extent; ++z) {
                const Vec3d p(x * vs, y * vs, z * vs);
                const double d = std::min((p - c).norm() - r, plane_y - p.y());
                if (std::abs(d) > 3 * vs) continue;
                map.setVoxel(openvdb::Coord(x, y, z), static_cast<float>(d), 1.0f);
            }
}

/// Number of edges of the welded union with one face (cracks) or more than two.
std::size_t badEdges(const std::multiset<Face>& faces) {
    std::map<std::pair<Point, Point>, int> edges;
    for (const Face& f : faces)
        for (int k = 0; k < 3; ++k) {
            Point a = f[static_cast<std::size_t>(k)], b = f[static_cast<std::size_t>((k + 1) % 3)];
            if (b < a) std::swap(a, b);
            ++edges[{a, b}];
        }
    std::size_t bad = 0;
    for (const auto& [edge, n] : edges) bad += n != 2 ? 1 : 0;
    return bad;
}

}  // namespace

TEST_CASE("Tiles crossing a sphere's centre: core faces are the untiled mesh, no cracks",
          "[mesh][tiles]") {
    const double vs = 0.05;
    VoxelMap map(vs, 0.15f);
    // The sphere's centre sits near the corner of four tiles (x = z = 0), y is up.
    const Vec3d centre(0.013, 0.021, -0.037);
    const double r = 0.9;
    {
        const int n = static_cast<int>(std::ceil((r + 0.3) / vs));
        for (int x = -n; x <= n; ++x)
            for (int y = -n; y <= n; ++y)
                for (int z = -n; z <= n; ++z) {
                    const Vec3d p(x * vs, y * vs, z * vs);
                    const double d = (p - centre).norm() - r;
                    if (std::abs(d) <= 3 * vs) map.setVoxel(openvdb::Coord(x, y, z), float(d), 1.0f);
                }
    }
    const auto untiled = extractMesh(map, MarchingCubesConfig{});
    const auto reference = facesOf(*untiled, false);
    REQUIRE(reference.size() > 2000);
    REQUIRE(badEdges(reference) == 0);  // a closed sphere

    for (const double tile_m : {0.4, 0.8}) {
        for (const double halo_m : {0.0, 0.15}) {
            INFO("tile " << tile_m << " m, halo " << halo_m << " m");
            TilingConfig config;
            config.tile_size_m = tile_m;
            config.halo_m = halo_m;
            const TileGrid grid(config, vs, 1);
            const std::vector<Tile> tiles = grid.tilesOf(map);
            REQUIRE(tiles.size() >= 9);
            std::multiset<Face> union_core;
            std::size_t halo_faces = 0;
            for (const Tile& tile : tiles) {
                CHECK(tile.region.axes[0] == 0);
                CHECK(tile.region.axes[1] == 2);
                MeshStats stats;
                const auto mesh = extractMeshRegion(map, MarchingCubesConfig{}, tile.region, &stats);
                const auto core = facesOf(*mesh, true);
                union_core.insert(core.begin(), core.end());
                halo_faces += stats.halo_faces;
                // Halo faces are faces of the untiled mesh too (the same cubes).
                for (const Face& f : facesOf(*mesh, false)) CHECK(reference.count(f) == 1);
                // Core faces lie within the tile's core bounds (ground axes x, z).
                for (const Face& f : core)
                    for (const Point& p : f) {
                        CHECK(p[0] >= tile.core_W.min_W.x() - 1e-5);
                        CHECK(p[0] <= tile.core_W.max_W.x() + vs + 1e-5);
                        CHECK(p[2] >= tile.core_W.min_W.z() - 1e-5);
                        CHECK(p[2] <= tile.core_W.max_W.z() + vs + 1e-5);
                    }
            }
            CHECK(union_core == reference);  // same faces, none twice, none missing
            CHECK(badEdges(union_core) == 0);
            if (halo_m > 0) {
                CHECK(halo_faces > 0);
            } else {
                CHECK(halo_faces == 0);
            }
        }
    }
}

TEST_CASE("Tiles over a ground plane and a sphere: a cube is owned by one tile", "[mesh][tiles]") {
    const double vs = 0.1;
    VoxelMap map(vs, 0.3f);
    writeScene(map, Vec3d(0.03, 0.4, 0.02), 1.1, 0.0, 40);  // crosses 4 x 4 corners
    const auto untiled = extractMesh(map, MarchingCubesConfig{});
    const auto reference = facesOf(*untiled, false);
    TilingConfig config;
    config.tile_size_m = 1.6;
    config.halo_m = 0.5;
    const TileGrid grid(config, vs, 1);
    CHECK(grid.tileVoxels() == 16);
    CHECK(grid.haloVoxels() == 5);
    std::multiset<Face> union_core;
    const auto tiles = grid.tilesOf(map);
    REQUIRE(tiles.size() == 36);  // voxels -40..40 on x and z: tiles -3..2
    for (const Tile& tile : tiles) {
        const auto mesh = extractMeshRegion(map, MarchingCubesConfig{}, tile.region);
        const auto core = facesOf(*mesh, true);
        union_core.insert(core.begin(), core.end());
        // The core submesh written per tile has exactly the core faces.
        const TriMesh written = coreSubmesh(*mesh);
        CHECK(facesOf(written, false) == core);
    }
    CHECK(union_core == reference);
}

TEST_CASE("Tile grid: leaf-aligned size, world bounds, bad regions", "[mesh][tiles]") {
    TilingConfig config;
    config.tile_size_m = 6.5;  // 65 voxels of 0.1 m -> 8 leaves = 6.4 m
    config.halo_m = 0.25;
    const TileGrid grid(config, 0.1, 2);
    CHECK(grid.tileVoxels() == 64);
    CHECK(grid.haloVoxels() == 3);
    CHECK(grid.tileSizeM() == Approx(6.4));
    VoxelMap map(0.1, 0.3f);
    map.setVoxel(openvdb::Coord(-1, 70, 5), 0.1f, 1.0f);
    const auto tiles = grid.tilesOf(map);
    REQUIRE(tiles.size() == 1);
    CHECK(tiles[0].ix == -1);
    CHECK(tiles[0].iy == 1);
    CHECK(tiles[0].name() == "-1_1");
    CHECK(tiles[0].core_W.min_W.x() == Approx(-6.4));
    CHECK(tiles[0].core_W.max_W.y() == Approx(12.8));
    CHECK(tiles[0].halo_W.min_W.x() == Approx(-6.7));

    MeshRegion bad;
    bad.core_max[0] = bad.core_max[1] = 8;
    bad.halo_vox = -1;
    CHECK_THROWS_AS(extractMeshRegion(map, MarchingCubesConfig{}, bad), InvalidInput);
}

TEST_CASE("Tile pieces: the tile's core cut on leaf edges, the halo rule, the same core faces",
          "[mesh][tiles][split]") {
    const double vs = 0.1;
    VoxelMap map(vs, 0.3f);
    writeScene(map, Vec3d(0.03, 0.4, 0.02), 1.1, 0.0, 40);
    TilingConfig config;
    config.tile_size_m = 2.4;  // 24 voxels: 3 leaves, cut into 1 + 2
    config.halo_m = 0.5;
    config.occluder_margin_m = 1.0;
    const TileGrid grid(config, vs, 1);
    REQUIRE(grid.tileVoxels() == 24);
    std::size_t pieces_seen = 0;
    for (const Tile& tile : grid.tilesOf(map)) {
        INFO("tile " << tile.name());
        REQUIRE(grid.canSplit(tile));
        const std::vector<Tile> pieces = grid.split(tile);
        REQUIRE(pieces.size() == 4);
        const auto mesh = extractMeshRegion(map, MarchingCubesConfig{}, tile.region);
        const auto core = facesOf(*mesh, true);
        std::multiset<Face> union_core;
        std::int64_t area = 0;
        for (std::size_t k = 0; k < pieces.size(); ++k) {
            const Tile& p = pieces[k];
            CHECK(p.ix == tile.ix);
            CHECK(p.iy == tile.iy);
            CHECK(p.piece == std::to_string(k));
            CHECK(p.name() == tile.name() + "." + std::to_string(k));
            CHECK(p.region.halo_vox == tile.region.halo_vox);
            CHECK(p.occluder_region.halo_vox == tile.occluder_region.halo_vox);
            for (int a = 0; a < 2; ++a) {
                CHECK(p.region.core_min[a] % 8 == 0);  // whole leaves
                CHECK(p.region.core_max[a] % 8 == 0);
                CHECK(p.region.core_min[a] >= tile.region.core_min[a]);
                CHECK(p.region.core_max[a] <= tile.region.core_max[a]);
                CHECK(p.occluder_region.core_min[a] == p.region.core_min[a]);
                const int axis = grid.groundAxis(a);
                CHECK(p.core_W.min_W[axis] == Approx(p.region.core_min[a] * vs));
                CHECK(p.halo_W.min_W[axis] == Approx(p.core_W.min_W[axis] - grid.haloM()));
                CHECK(p.halo_W.max_W[axis] == Approx(p.core_W.max_W[axis] + grid.haloM()));
            }
            area += std::int64_t(p.region.core_max[0] - p.region.core_min[0]) *
                    (p.region.core_max[1] - p.region.core_min[1]);
            const auto piece_mesh = extractMeshRegion(map, MarchingCubesConfig{}, p.region);
            const auto piece_core = facesOf(*piece_mesh, true);
            union_core.insert(piece_core.begin(), piece_core.end());
            pieces_seen += piece_core.empty() ? 0 : 1;
        }
        CHECK(area == 24 * 24);  // the cores partition the tile's
        CHECK(union_core == core);
        // A piece of a piece: its path names both cuts.
        const std::vector<Tile> inner = grid.split(pieces[3]);  // 16 x 16 voxels: 4 pieces
        REQUIRE(inner.size() == 4);
        CHECK(inner[2].name() == tile.name() + ".3.2");
        CHECK_FALSE(grid.canSplit(inner[0]));  // one leaf wide
    }
    CHECK(pieces_seen > 4);
}
