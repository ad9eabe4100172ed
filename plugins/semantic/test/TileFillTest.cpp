// SPDX-License-Identifier: Apache-2.0
// fillFromWiderTile (issue 13): a tile whose MRF left an unobserved region unlabelled takes
// the region's labels from the tile grown by its occluder margin, but only for regions that
// reach the outer edge of the tile's mesh region (the surface goes on beyond it); a closed
// unseen object inside the region, and labelled faces, are left alone.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <memory>

#include "TileFill.h"
#include "pipeline/ContextBuilder.h"
#include "vdbmap/map/Layers.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/mesh/MarchingCubes.h"
#include "vdbmap/mesh/TileFaces.h"
#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/Report.h"
#include "vdbmap/pipeline/Tiling.h"

using namespace vdbmap;
using namespace vdbmap::semantic;

namespace {

/// A ground plane y = 0.05 over x, z in [-4, 4] m and a small sphere (r = 0.25 m) floating at
/// (0.5, 1, 0.5) inside tile (0, 0) of a 1.6 m grid: the exact SDF, voxel 0.1 m.
void writeScene(VoxelMap& map) {
    const double vs = map.voxelSize();
    for (int x = -40; x <= 40; ++x)
        for (int y = -4; y <= 16; ++y)
            for (int z = -40; z <= 40; ++z) {
                const Vec3d p(x * vs, y * vs, z * vs);
                const double d = std::min(p.y() - 0.05, (p - Vec3d(0.5, 1.0, 0.5)).norm() - 0.25);
                if (std::abs(d) > 3 * vs) continue;
                map.setVoxel(openvdb::Coord(x, y, z), static_cast<float>(d), 1.0f);
            }
}

}  // namespace

TEST_CASE("Unlabelled regions cut by the tile's edge are filled from the wider tile",
          "[semantic][tiles]") {
    VoxelMap map(0.1, 0.3f);
    writeScene(map);
    TilingConfig config;
    config.tile_size_m = 1.6;
    config.halo_m = 0.3;
    config.occluder_margin_m = 1.0;
    const TileGrid grid(config, 0.1, 1);
    auto tile = std::make_shared<Tile>(grid.tile(0, 0));
    REQUIRE(grid.fitToMap(*tile, map));

    Report report;
    Context ctx(std::filesystem::temp_directory_path(), report, true);
    // What the pipeline sets for a tile's stages (the library's private ContextBuilder).
    ContextBuilder::setMap(ctx, std::shared_ptr<VoxelMap>(&map, [](VoxelMap*) {}));
    ContextBuilder::setTile(ctx, tile);
    ctx.setMesh(extractMeshRegion(map, MarchingCubesConfig{}, tile->region));
    ctx.setOccluderMesh(extractMeshRegion(map, MarchingCubesConfig{}, tile->occluder_region));
    const TriMesh& mesh = ctx.mesh();
    REQUIRE(mesh.n_faces() > 500);

    // Nothing in the tile was observed: the ground and the sphere are unlabelled. The wider
    // tile labels every face 2.
    FusionResult result;
    result.face_labels.assign(mesh.n_faces(), kUnknownLabel);
    std::vector<bool> sphere(mesh.n_faces(), false);
    for (const auto fh : mesh.faces()) {
        sphere[static_cast<std::size_t>(fh.idx())] = mesh.calc_face_centroid(fh)[1] > 0.5f;
    }
    const std::size_t unlabelled = mesh.n_faces();
    result.unlabelled_faces = unlabelled;
    std::size_t wide_faces = 0;
    const TileFillWidening widened = fillFromWiderTile(ctx, result, [&](Context& wide) {
        // The wider context: the occluder mesh, the tile's core unchanged, the halo grown.
        CHECK(wide.hasTile());
        CHECK(wide.tile().region.halo_vox == tile->occluder_region.halo_vox);
        CHECK(wide.mesh().n_faces() == ctx.occluderMesh().n_faces());
        wide_faces = wide.mesh().n_faces();
        return std::vector<std::uint8_t>(wide.mesh().n_faces(), 2);
    });
    CHECK(wide_faces > mesh.n_faces());
    CHECK(widened.regions == 1);  // the ground; the sphere touches no edge of the region
    std::size_t ground = 0;
    for (const auto fh : mesh.faces()) {
        const auto f = static_cast<std::size_t>(fh.idx());
        // The ground goes on beyond the region: filled. The sphere is closed: untouched.
        CHECK(result.face_labels[f] == (sphere[f] ? kUnknownLabel : 2));
        ground += sphere[f] ? 0 : 1;
    }
    REQUIRE(ground > 0);
    REQUIRE(ground < mesh.n_faces());
    CHECK(widened.faces_relabelled == ground);
    CHECK(result.unlabelled_faces == unlabelled - ground);

    // A closed unseen object alone (the ground labelled) widens nothing.
    for (const auto fh : mesh.faces()) {
        const auto f = static_cast<std::size_t>(fh.idx());
        result.face_labels[f] = sphere[f] ? kUnknownLabel : 1;
    }
    result.unlabelled_faces = 1;
    bool called = false;
    const TileFillWidening none = fillFromWiderTile(ctx, result, [&](Context&) {
        called = true;
        return std::vector<std::uint8_t>();
    });
    CHECK_FALSE(called);
    CHECK(none.regions == 0);
    CHECK(none.faces_relabelled == 0);
}
