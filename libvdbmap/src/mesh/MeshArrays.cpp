// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/mesh/MeshArrays.h"

#include <string>

#include "vdbmap/Error.h"

namespace vdbmap {

MeshArrays meshArrays(const TriMesh& mesh, DeletedFaces deleted) {
    MeshArrays arrays;
    arrays.vertices_W.reserve(mesh.n_vertices());
    for (const auto vh : mesh.all_vertices()) {
        const auto& p = mesh.point(vh);
        arrays.vertices_W.emplace_back(p[0], p[1], p[2]);
    }
    arrays.faces.reserve(mesh.n_faces());
    arrays.face_index.reserve(mesh.n_faces());
    for (const auto fh : mesh.all_faces()) {
        const bool is_deleted = mesh.has_face_status() && mesh.status(fh).deleted();
        if (is_deleted && deleted == DeletedFaces::Skip) continue;
        std::array<std::uint32_t, 3> tri{0, 0, 0};
        int k = 0;
        for (const auto fv : mesh.fv_range(fh)) {
            if (k < 3) tri[k] = static_cast<std::uint32_t>(fv.idx());
            ++k;
        }
        if (k != 3) {
            throw InvalidInput("mesh face " + std::to_string(fh.idx()) + " has " +
                               std::to_string(k) + " vertices, expected a triangle");
        }
        if (is_deleted) tri[1] = tri[2] = tri[0];
        arrays.faces.push_back(tri);
        arrays.face_index.push_back(static_cast<std::uint32_t>(fh.idx()));
    }
    return arrays;
}

}  // namespace vdbmap
