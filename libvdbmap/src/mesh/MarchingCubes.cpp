// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/mesh/MarchingCubes.h"

#include <OpenMesh/Core/System/omstream.hh>
#include <openvdb/openvdb.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <vector>

#include "mesh/CubeTable.h"
#include "vdbmap/map/TsdfReader.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/mesh/MeshCleanup.h"

namespace vdbmap {
namespace {

using openvdb::Coord;

/// 62-bit key of a grid edge: its lower voxel (20 bits per axis, offset 2^19) and its axis.
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

/// Output of one leaf: its edge vertices and triangles (as edge keys).
struct LeafMesh {
    std::vector<EdgeVertex> vertices;
    std::vector<std::array<std::uint64_t, 3>> triangles;
    std::size_t cubes = 0;
};

}  // namespace

std::shared_ptr<TriMesh> extractMesh(const VoxelMap& map, const MarchingCubesConfig& config,
                                     MeshStats* stats_out) {
    MeshStats stats;
    const detail::CubeTable& table = detail::cubeTable();
    const TsdfCodec& codec = map.codec();
    const float vs = static_cast<float>(map.voxelSize());
    const float min_weight = static_cast<float>(config.min_weight);

    // Both stores of the TSDF (VoxelMap); after AtsdfIntegrator::finalize all leaves are compact.
    const std::vector<TsdfLeafView> leaves = map.leafViews();
    std::vector<LeafMesh> out(leaves.size());

    // Parallel per leaf: each cube whose min corner is an active voxel of the leaf.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 4),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        TsdfReader ta(map);
        for (std::size_t li = r.begin(); li < r.end(); ++li) {
            LeafMesh& lm = out[li];
            const TsdfLeafView& leaf = leaves[li];
            leaf.forEachObserved([&](openvdb::Index offset) {
                const Coord c = leaf.origin + TsdfLeaf::offsetToLocalCoord(offset);
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
                            keys[static_cast<std::size_t>(e)] = edgeKey(ca, axis);
                            lm.vertices.push_back({keys[static_cast<std::size_t>(e)], p * vs});
                        }
                        t[static_cast<std::size_t>(j)] = keys[static_cast<std::size_t>(e)];
                    }
                    lm.triangles.push_back(t);
                }
            });
        }
    });

    // Weld: one vertex per grid edge, ordered by key (deterministic for any thread count).
    std::size_t total_v = 0, total_t = 0;
    for (const LeafMesh& lm : out) {
        total_v += lm.vertices.size();
        total_t += lm.triangles.size();
        stats.cubes_meshed += lm.cubes;
    }
    std::vector<EdgeVertex> verts;
    verts.reserve(total_v);
    for (const LeafMesh& lm : out) verts.insert(verts.end(), lm.vertices.begin(), lm.vertices.end());
    tbb::parallel_sort(verts.begin(), verts.end(),
                       [](const EdgeVertex& a, const EdgeVertex& b) { return a.key < b.key; });
    verts.erase(std::unique(verts.begin(), verts.end(),
                            [](const EdgeVertex& a, const EdgeVertex& b) { return a.key == b.key; }),
                verts.end());
    std::vector<std::array<std::uint32_t, 3>> faces(total_t);
    {
        std::vector<std::size_t> tri_offset(out.size() + 1, 0);
        for (std::size_t i = 0; i < out.size(); ++i)
            tri_offset[i + 1] = tri_offset[i] + out[i].triangles.size();
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, out.size(), 16),
                          [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t li = r.begin(); li < r.end(); ++li)
                for (std::size_t k = 0; k < out[li].triangles.size(); ++k)
                    for (int j = 0; j < 3; ++j) {
                        const std::uint64_t key = out[li].triangles[k][static_cast<std::size_t>(j)];
                        const auto it = std::lower_bound(
                            verts.begin(), verts.end(), key,
                            [](const EdgeVertex& v, std::uint64_t kk) { return v.key < kk; });
                        faces[tri_offset[li] + k][static_cast<std::size_t>(j)] =
                            static_cast<std::uint32_t>(it - verts.begin());
                    }
        });
    }
    out.clear();
    stats.components_removed = removeSmallComponents(faces, verts.size(), config.min_component_faces,
                                                     &stats.faces_removed_small_components);

    // Build the OpenMesh mesh with the referenced vertices only.
    auto mesh = std::make_shared<TriMesh>();
    std::vector<std::int64_t> handle(verts.size(), -1);
    for (const auto& f : faces)
        for (std::uint32_t v : f) handle[v] = 0;
    std::size_t used = 0;
    for (std::int64_t h : handle) used += h == 0 ? 1 : 0;
    mesh->reserve(used, faces.size() * 3 / 2 + 3, faces.size());
    for (std::size_t v = 0; v < verts.size(); ++v) {
        if (handle[v] < 0) continue;
        const openvdb::Vec3f& p = verts[v].pos;
        handle[v] = mesh->add_vertex(TriMesh::Point(p.x(), p.y(), p.z())).idx();
    }
    // OpenMesh reports complex edges on std::cerr; the library stays silent and counts them.
    const bool err_enabled = ::omerr().is_enabled();
    ::omerr().disable();
    for (const auto& f : faces) {
        const auto fh = mesh->add_face(TriMesh::VertexHandle(static_cast<int>(handle[f[0]])),
                                       TriMesh::VertexHandle(static_cast<int>(handle[f[1]])),
                                       TriMesh::VertexHandle(static_cast<int>(handle[f[2]])));
        if (!fh.is_valid()) ++stats.faces_rejected_nonmanifold;
    }
    if (err_enabled) ::omerr().enable();
    mesh->update_face_normals();
    mesh->update_vertex_normals();
    stats.faces = mesh->n_faces();
    stats.vertices = mesh->n_vertices();
    if (stats_out) *stats_out = stats;
    return mesh;
}

}  // namespace vdbmap
