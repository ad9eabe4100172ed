// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/mesh/MarchingCubes.h"

#include <OpenMesh/Core/System/omstream.hh>
#include <openvdb/openvdb.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <tuple>
#include <array>
#include <vector>

#include "mesh/CubeTable.h"
#include "vdbmap/map/TsdfReader.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/Error.h"
#include "vdbmap/mesh/MeshCleanup.h"
#include "vdbmap/mesh/TileFaces.h"

namespace vdbmap {
namespace {

using openvdb::Coord;

/// 62-bit key of a grid edge: its lower voxel (20 bits per axis, offset 2^19) and its axis
/// (0 to 2; 3 = the grid point itself, for a crossing exactly on it).
std::uint64_t edgeKey(const Coord& lower, int axis) {
    constexpr int kOffset = 1 << 19;
    auto f = [](int v) { return static_cast<std::uint64_t>((v + kOffset) & 0xFFFFF); };
    return (f(lower.x()) << 42) | (f(lower.y()) << 22) | (f(lower.z()) << 2) |
           static_cast<std::uint64_t>(axis);
}

struct EdgeVertex {
    std::uint64_t key;
    openvdb::Vec3f pos;
};

/// Output of one leaf: its edge vertices and triangles (as edge keys), halo flag per triangle.
struct LeafMesh {
    std::vector<EdgeVertex> vertices;
    std::vector<std::array<std::uint64_t, 3>> triangles;
    std::vector<std::uint8_t> triangle_halo;
    std::size_t cubes = 0;
};

/// Which cubes to mesh: every cube (no region), or a region's core and halo cubes.
struct CubeSelection {
    const MeshRegion* region = nullptr;
    /// -1: skip the cube, 0: core, 1: halo.
    int classify(const Coord& min_corner) const {
        if (!region) return 0;
        const std::int32_t a = min_corner[region->axes[0]], b = min_corner[region->axes[1]];
        if (!region->inRegion(a, b)) return -1;
        return region->inCore(a, b) ? 0 : 1;
    }
    bool mayTouch(const Coord& leaf_origin) const {
        if (!region) return true;
        const int d = static_cast<int>(TsdfLeaf::DIM);
        const std::int32_t a = leaf_origin[region->axes[0]], b = leaf_origin[region->axes[1]];
        return a + d > region->core_min[0] - region->halo_vox &&
               a < region->core_max[0] + region->halo_vox &&
               b + d > region->core_min[1] - region->halo_vox &&
               b < region->core_max[1] + region->halo_vox;
    }
};

/// The welded mesh as arrays: one vertex per grid edge (sorted by key), faces, halo flags.
struct WeldedMesh {
    std::vector<EdgeVertex> vertices;
    std::vector<std::array<std::uint32_t, 3>> faces;
    std::vector<std::uint8_t> face_halo;
};

/// Phase 1: the triangles of each selected cube whose min corner is an observed voxel of a
/// leaf, parallel per leaf.
std::vector<LeafMesh> meshLeaves(const VoxelMap& map, const MarchingCubesConfig& config,
                                 const CubeSelection& selection) {
    const detail::CubeTable& table = detail::cubeTable();
    const TsdfCodec& codec = map.codec();
    const float vs = static_cast<float>(map.voxelSize());
    const float min_weight = static_cast<float>(config.min_weight);

    // Both stores of the TSDF (VoxelMap); after AtsdfIntegrator::finalize all leaves are compact.
    std::vector<TsdfLeafView> leaves = map.leafViews();
    if (selection.region) {
        leaves.erase(std::remove_if(leaves.begin(), leaves.end(),
                                    [&](const TsdfLeafView& l) { return !selection.mayTouch(l.origin); }),
                     leaves.end());
    }
    // One order whichever store holds a leaf (a map still being integrated has dense and
    // compact leaves): the face order, and so which face OpenMesh refuses at a complex edge,
    // must not depend on it.
    std::sort(leaves.begin(), leaves.end(), [](const TsdfLeafView& a, const TsdfLeafView& b) {
        return std::make_tuple(a.origin.x(), a.origin.y(), a.origin.z()) <
               std::make_tuple(b.origin.x(), b.origin.y(), b.origin.z());
    });
    std::vector<LeafMesh> out(leaves.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 4),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        TsdfReader ta(map);
        for (std::size_t li = r.begin(); li < r.end(); ++li) {
            LeafMesh& lm = out[li];
            const TsdfLeafView& leaf = leaves[li];
            leaf.forEachObserved([&](openvdb::Index offset) {
                const Coord c = leaf.origin + TsdfLeaf::offsetToLocalCoord(offset);
                const int kind = selection.classify(c);
                if (kind < 0) return;
                float val[8];
                int mask = 0;
                bool observed = true;
                for (int k = 0; k < 8 && observed; ++k) {
                    const Coord ck = c.offsetBy(k & 1, (k >> 1) & 1, (k >> 2) & 1);
                    std::uint32_t packed = 0;
                    observed = ta.probe(ck, packed);
                    const float w = codec.weight(packed);
                    val[k] = codec.sdf(packed);
                    observed = observed && w >= min_weight && w > 0.0f;
                    if (val[k] < 0.0f) mask |= 1 << k;
                }
                if (!observed || mask == 0 || mask == 255) return;
                ++lm.cubes;
                std::array<std::uint64_t, 12> keys{};
                std::uint16_t have = 0;
                for (const auto& tri : table.triangles[static_cast<std::size_t>(mask)]) {
                    std::array<std::uint64_t, 3> t{};
                    for (int j = 0; j < 3; ++j) {
                        const int e = tri[static_cast<std::size_t>(j)];
                        if (!(have & (1u << e))) {
                            have = static_cast<std::uint16_t>(have | (1u << e));
                            const int a = table.edge_corner[static_cast<std::size_t>(e)];
                            const int axis = table.edge_axis[static_cast<std::size_t>(e)];
                            const int b = a | (1 << axis);
                            const Coord ca = c.offsetBy(a & 1, (a >> 1) & 1, (a >> 2) & 1);
                            // Zero crossing along the edge; the same two values give the same
                            // float position in every cube that shares the edge.
                            const float s = val[a] / (val[a] - val[b]);
                            openvdb::Vec3f p(static_cast<float>(ca.x()), static_cast<float>(ca.y()),
                                             static_cast<float>(ca.z()));
                            p[axis] += s;
                            // A crossing on a corner (its value exactly 0) is that corner's
                            // vertex, whichever edge reaches it (key axis 3): the edges that
                            // meet there share one vertex, and the faces it collapses are
                            // dropped below instead of becoming zero-area duplicates.
                            keys[static_cast<std::size_t>(e)] =
                                s == 0.0f   ? edgeKey(ca, 3)
                                : s == 1.0f ? edgeKey(ca.offsetBy(axis == 0, axis == 1, axis == 2), 3)
                                            : edgeKey(ca, axis);
                            lm.vertices.push_back({keys[static_cast<std::size_t>(e)], p * vs});
                        }
                        t[static_cast<std::size_t>(j)] = keys[static_cast<std::size_t>(e)];
                    }
                    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;  // collapsed
                    lm.triangles.push_back(t);
                    lm.triangle_halo.push_back(static_cast<std::uint8_t>(kind));
                }
            });
        }
    });
    return out;
}

/// Phase 2: one vertex per grid edge, ordered by key (deterministic for any thread count),
/// and the triangles as vertex indices. Consumes `leaves`.
WeldedMesh weldVertices(std::vector<LeafMesh>& leaves, MeshStats& stats) {
    WeldedMesh w;
    std::size_t total_v = 0, total_t = 0;
    for (const LeafMesh& lm : leaves) {
        total_v += lm.vertices.size();
        total_t += lm.triangles.size();
        stats.cubes_meshed += lm.cubes;
    }
    w.vertices.reserve(total_v);
    w.face_halo.reserve(total_t);
    for (const LeafMesh& lm : leaves) {
        w.vertices.insert(w.vertices.end(), lm.vertices.begin(), lm.vertices.end());
        w.face_halo.insert(w.face_halo.end(), lm.triangle_halo.begin(), lm.triangle_halo.end());
    }
    auto& verts = w.vertices;
    tbb::parallel_sort(verts.begin(), verts.end(),
                       [](const EdgeVertex& a, const EdgeVertex& b) { return a.key < b.key; });
    verts.erase(std::unique(verts.begin(), verts.end(),
                            [](const EdgeVertex& a, const EdgeVertex& b) { return a.key == b.key; }),
                verts.end());
    w.faces.resize(total_t);
    std::vector<std::size_t> tri_offset(leaves.size() + 1, 0);
    for (std::size_t i = 0; i < leaves.size(); ++i)
        tri_offset[i + 1] = tri_offset[i] + leaves[i].triangles.size();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 16),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t li = r.begin(); li < r.end(); ++li)
            for (std::size_t k = 0; k < leaves[li].triangles.size(); ++k)
                for (int j = 0; j < 3; ++j) {
                    const std::uint64_t key = leaves[li].triangles[k][static_cast<std::size_t>(j)];
                    const auto it = std::lower_bound(
                        verts.begin(), verts.end(), key,
                        [](const EdgeVertex& v, std::uint64_t kk) { return v.key < kk; });
                    w.faces[tri_offset[li] + k][static_cast<std::size_t>(j)] =
                        static_cast<std::uint32_t>(it - verts.begin());
                }
    });
    leaves.clear();
    return w;
}

/// Phase 3: removes small components, keeping the halo flag of each remaining face.
void removeSmallComponentsOf(WeldedMesh& w, const MarchingCubesConfig& config, MeshStats& stats) {
    if (config.min_component_faces <= 1) return;
    const auto before = w.faces;
    stats.components_removed = removeSmallComponents(w.faces, w.vertices.size(),
                                                     config.min_component_faces,
                                                     &stats.faces_removed_small_components);
    // The remaining faces keep their order, and no two faces are equal.
    std::vector<std::uint8_t> halo;
    halo.reserve(w.faces.size());
    std::size_t j = 0;
    for (std::size_t i = 0; i < before.size() && j < w.faces.size(); ++i) {
        if (before[i] == w.faces[j]) {
            halo.push_back(w.face_halo[i]);
            ++j;
        }
    }
    w.face_halo.swap(halo);
}

/// Phase 4: the OpenMesh mesh with the referenced vertices only, normals, halo flags.
std::shared_ptr<TriMesh> buildTriMesh(const WeldedMesh& w, bool mark_halo, MeshStats& stats) {
    auto mesh = std::make_shared<TriMesh>();
    std::vector<std::int64_t> handle(w.vertices.size(), -1);
    for (const auto& f : w.faces)
        for (std::uint32_t v : f) handle[v] = 0;
    std::size_t used = 0;
    for (std::int64_t h : handle) used += h == 0 ? 1 : 0;
    mesh->reserve(used, w.faces.size() * 3 / 2 + 3, w.faces.size());
    for (std::size_t v = 0; v < w.vertices.size(); ++v) {
        if (handle[v] < 0) continue;
        const openvdb::Vec3f& p = w.vertices[v].pos;
        handle[v] = mesh->add_vertex(TriMesh::Point(p.x(), p.y(), p.z())).idx();
    }
    std::vector<std::uint8_t> halo;
    halo.reserve(w.faces.size());
    // OpenMesh reports complex edges on std::cerr; the library stays silent and counts them.
    const bool err_enabled = ::omerr().is_enabled();
    ::omerr().disable();
    for (std::size_t i = 0; i < w.faces.size(); ++i) {
        const auto& f = w.faces[i];
        const auto fh = mesh->add_face(TriMesh::VertexHandle(static_cast<int>(handle[f[0]])),
                                       TriMesh::VertexHandle(static_cast<int>(handle[f[1]])),
                                       TriMesh::VertexHandle(static_cast<int>(handle[f[2]])));
        if (!fh.is_valid()) {
            ++stats.faces_rejected_nonmanifold;
            continue;
        }
        halo.push_back(w.face_halo[i]);
        stats.halo_faces += w.face_halo[i];
    }
    if (err_enabled) ::omerr().enable();
    mesh->update_face_normals();
    mesh->update_vertex_normals();
    if (mark_halo) setHaloFaceMask(*mesh, halo);
    stats.faces = mesh->n_faces();
    stats.vertices = mesh->n_vertices();
    return mesh;
}

std::shared_ptr<TriMesh> extract(const VoxelMap& map, const MarchingCubesConfig& config,
                                 const CubeSelection& selection, MeshStats* stats_out) {
    MeshStats stats;
    std::vector<LeafMesh> leaves = meshLeaves(map, config, selection);
    WeldedMesh welded = weldVertices(leaves, stats);
    removeSmallComponentsOf(welded, config, stats);
    auto mesh = buildTriMesh(welded, selection.region != nullptr, stats);
    if (stats_out) *stats_out = stats;
    return mesh;
}

}  // namespace

std::shared_ptr<TriMesh> extractMesh(const VoxelMap& map, const MarchingCubesConfig& config,
                                     MeshStats* stats_out) {
    return extract(map, config, CubeSelection{}, stats_out);
}

std::shared_ptr<TriMesh> extractMeshRegion(const VoxelMap& map, const MarchingCubesConfig& config,
                                           const MeshRegion& region, MeshStats* stats_out) {
    const bool axes_ok = region.axes[0] >= 0 && region.axes[0] < 3 && region.axes[1] >= 0 &&
                         region.axes[1] < 3 && region.axes[0] != region.axes[1];
    if (!axes_ok || region.halo_vox < 0 || region.core_max[0] <= region.core_min[0] ||
        region.core_max[1] <= region.core_min[1]) {
        throw InvalidInput("extractMeshRegion: bad ground axes, empty region or negative halo");
    }
    CubeSelection selection;
    selection.region = &region;
    return extract(map, config, selection, stats_out);
}

}  // namespace vdbmap
