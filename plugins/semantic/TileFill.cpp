// SPDX-License-Identifier: Apache-2.0
#include "TileFill.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <utility>

#include "vdbmap/core/Log.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/core/UnionFind.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/map/Layers.h"
#include "vdbmap/mesh/MeshAdjacency.h"
#include "vdbmap/mesh/TileFaces.h"
#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/Report.h"
#include "vdbmap/pipeline/Tiling.h"
#include "vdbmap/render/ViewFrustum.h"

namespace vdbmap::semantic {
namespace {

/// A face by its three corners (float bits, corners sorted): equal faces of two meshes cut
/// from the same marching cubes have equal keys.
using FaceKey = std::array<std::uint32_t, 9>;

FaceKey faceKey(const TriMesh& mesh, TriMesh::FaceHandle fh) {
    std::array<std::array<std::uint32_t, 3>, 3> corners{};
    int k = 0;
    for (const auto vh : mesh.fv_range(fh)) {
        const auto p = mesh.point(vh);
        for (int a = 0; a < 3; ++a) std::memcpy(&corners[k][a], &p[a], sizeof(float));
        ++k;
    }
    std::sort(corners.begin(), corners.end());
    FaceKey key{};
    for (int c = 0; c < 3; ++c)
        for (int a = 0; a < 3; ++a) key[static_cast<std::size_t>(3 * c + a)] = corners[c][a];
    return key;
}

/// Whether face f has a mesh-boundary edge on the outer edge of the tile's mesh region (the
/// planes where the halo ends): there the surface goes on beyond what the tile sees.
bool cutByRegionEdge(const TriMesh& mesh, TriMesh::FaceHandle f, const Tile& tile) {
    const MeshRegion& r = tile.region;
    const double vs = tile.voxel_size_m;
    auto onPlane = [&](const TriMesh::Point& p) {
        for (int k = 0; k < 2; ++k) {
            const double x = p[r.axes[k]] / vs;
            if (std::abs(x - (r.core_min[k] - r.halo_vox)) < 1e-3 ||
                std::abs(x - (r.core_max[k] + r.halo_vox)) < 1e-3) {
                return true;
            }
        }
        return false;
    };
    for (const auto heh : mesh.fh_range(f)) {
        if (!mesh.is_boundary(mesh.opposite_halfedge_handle(heh))) continue;
        if (onPlane(mesh.point(mesh.from_vertex_handle(heh))) &&
            onPlane(mesh.point(mesh.to_vertex_handle(heh)))) {
            return true;
        }
    }
    return false;
}

/// Faces of the unlabelled components that hold a core face and reach the outer edge of the
/// tile's mesh region (a closed unseen object inside it has nothing beyond to be filled from).
std::vector<std::uint32_t> cutRegionFaces(const TriMesh& mesh, const Tile& tile,
                                          const std::vector<std::uint8_t>& labels,
                                          const std::vector<std::uint8_t>& halo,
                                          const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                                          std::size_t& regions) {
    const std::size_t n = labels.size();
    std::vector<std::uint32_t> parent = makeDisjointSets(n);
    for (const auto& e : adjacency) uniteSets(parent, e[0], e[1]);
    std::vector<std::uint8_t> has_core(n, 0), open(n, 0);
    for (std::size_t f = 0; f < n; ++f) {
        if (labels[f] != kUnknownLabel) continue;
        const std::uint32_t root = findRoot(parent, static_cast<std::uint32_t>(f));
        if (!halo[f]) has_core[root] = 1;
        if (!open[root] && cutByRegionEdge(mesh, TriMesh::FaceHandle(static_cast<int>(f)), tile)) {
            open[root] = 1;
        }
    }
    std::vector<std::uint32_t> faces;
    regions = 0;
    for (std::size_t f = 0; f < n; ++f) {
        if (labels[f] != kUnknownLabel) continue;
        const std::uint32_t root = findRoot(parent, static_cast<std::uint32_t>(f));
        if (!has_core[root] || !open[root]) continue;
        faces.push_back(static_cast<std::uint32_t>(f));
        regions += root == f ? 1 : 0;
    }
    return faces;
}

/// The tile grown to its occluder margin, with the views of the grown box.
std::shared_ptr<Tile> widerTile(const Tile& tile, const TriMesh& occluders, const Dataset* dataset) {
    auto wide = std::make_shared<Tile>(tile);
    wide->region = tile.occluder_region;
    const double grow_m = (tile.occluder_region.halo_vox - tile.region.halo_vox) * tile.voxel_size_m;
    for (int k = 0; k < 2; ++k) {
        const int axis = tile.region.axes[k];
        wide->halo_W.min_W[axis] -= grow_m;
        wide->halo_W.max_W[axis] += grow_m;
    }
    // Up axis: what the wider mesh spans.
    for (const auto vh : occluders.vertices()) {
        const double up = occluders.point(vh)[tile.up_axis];
        wide->halo_W.min_W[tile.up_axis] = std::min(wide->halo_W.min_W[tile.up_axis], up);
        wide->halo_W.max_W[tile.up_axis] = std::max(wide->halo_W.max_W[tile.up_axis], up);
    }
    if (dataset) {
        TileGrid::assignViews(*wide, datasetViews(*dataset, false, false), tile.max_view_distance_m);
    }
    return wide;
}

}  // namespace

TileFillWidening fillFromWiderTile(
    Context& ctx, FusionResult& result,
    const std::function<std::vector<std::uint8_t>(Context&)>& label) {
    TileFillWidening out;
    if (!ctx.hasTile() || result.unlabelled_faces == 0) return out;
    const Tile& tile = ctx.tile();
    if (tile.occluder_region.halo_vox <= tile.region.halo_vox) return out;
    const std::vector<std::uint32_t> cut =
        cutRegionFaces(ctx.mesh(), tile, result.face_labels, ctx.haloFaces(),
                       faceAdjacency(ctx.mesh()), out.regions);
    if (cut.empty()) return out;
    Timer timer;

    // The wider context: the occluder mesh as the mesh, the grown tile, nothing written.
    const TriMesh& occluders = ctx.occluderMesh();
    Report scratch;
    std::unique_ptr<Context> wide = ctx.regionContext(
        widerTile(tile, occluders, ctx.hasDataset() ? &ctx.dataset() : nullptr), scratch);
    auto wide_mesh = std::make_shared<TriMesh>(occluders);
    wide->setMesh(wide_mesh);
    const std::vector<std::uint8_t> wide_labels = label(*wide);
    if (wide_labels.size() != wide_mesh->n_faces()) return out;

    std::vector<std::pair<FaceKey, std::uint32_t>> index;
    index.reserve(wide_mesh->n_faces());
    for (const auto fh : wide_mesh->faces()) {
        index.emplace_back(faceKey(*wide_mesh, fh), static_cast<std::uint32_t>(fh.idx()));
    }
    std::sort(index.begin(), index.end());
    const TriMesh& mesh = ctx.mesh();
    for (const std::uint32_t f : cut) {
        const FaceKey key = faceKey(mesh, TriMesh::FaceHandle(static_cast<int>(f)));
        const auto it = std::lower_bound(index.begin(), index.end(), std::make_pair(key, 0u));
        if (it == index.end() || it->first != key) continue;
        const std::uint8_t l = wide_labels[it->second];
        if (l == kUnknownLabel) continue;
        result.face_labels[f] = l;
        ++out.faces_relabelled;
    }
    result.unlabelled_faces -= out.faces_relabelled;
    result.filled_faces += out.faces_relabelled;
    out.seconds = timer.elapsedSeconds();
    logInfo("semantic.mrf: tile " + tile.name() + ": " + std::to_string(out.regions) +
            " unobserved region(s) cut by the halo, " + std::to_string(out.faces_relabelled) +
            " of " + std::to_string(cut.size()) + " faces labelled from the tile grown to its "
            "occluder margin");
    return out;
}

}  // namespace vdbmap::semantic
