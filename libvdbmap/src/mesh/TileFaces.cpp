// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/mesh/TileFaces.h"

#include "vdbmap/Error.h"

namespace vdbmap {

std::vector<std::uint8_t> haloFaceMask(const TriMesh& mesh) {
    std::vector<std::uint8_t> halo(mesh.n_faces(), 0);
    OpenMesh::FPropHandleT<bool> prop;
    if (!mesh.get_property_handle(prop, kHaloFaceProperty)) return halo;
    for (const auto fh : mesh.faces()) {
        halo[static_cast<std::size_t>(fh.idx())] = mesh.property(prop, fh) ? 1 : 0;
    }
    return halo;
}

void setHaloFaceMask(TriMesh& mesh, const std::vector<std::uint8_t>& halo) {
    if (halo.size() != mesh.n_faces()) {
        throw InvalidInput("setHaloFaceMask: " + std::to_string(halo.size()) + " flags for " +
                           std::to_string(mesh.n_faces()) + " faces");
    }
    OpenMesh::FPropHandleT<bool> prop;
    if (!mesh.get_property_handle(prop, kHaloFaceProperty)) {
        mesh.add_property(prop, kHaloFaceProperty);
    }
    for (const auto fh : mesh.faces()) {
        mesh.property(prop, fh) = halo[static_cast<std::size_t>(fh.idx())] != 0;
    }
}

TriMesh coreSubmesh(const TriMesh& mesh, std::vector<std::uint32_t>* core_faces) {
    const std::vector<std::uint8_t> halo = haloFaceMask(mesh);
    TriMesh out;
    std::vector<int> vertex_map(mesh.n_vertices(), -1);
    if (core_faces) core_faces->clear();
    for (const auto fh : mesh.faces()) {
        if (halo[static_cast<std::size_t>(fh.idx())]) continue;
        TriMesh::VertexHandle corners[3];
        int k = 0;
        for (const auto vh : mesh.fv_range(fh)) {
            int& mapped = vertex_map[static_cast<std::size_t>(vh.idx())];
            if (mapped < 0) {
                const auto nv = out.add_vertex(mesh.point(vh));
                out.set_normal(nv, mesh.normal(vh));
                mapped = nv.idx();
            }
            corners[k++] = TriMesh::VertexHandle(mapped);
        }
        // A face valid in the source stays valid in a subset of its faces.
        const auto nf = out.add_face(corners[0], corners[1], corners[2]);
        out.set_normal(nf, mesh.normal(fh));
        if (core_faces) core_faces->push_back(static_cast<std::uint32_t>(fh.idx()));
    }
    return out;
}

}  // namespace vdbmap
