// SPDX-License-Identifier: Apache-2.0
#include "TextureTypes.h"

namespace vdbmap::texture {

MeshArrays meshArrays(const TriMesh& mesh) {
    MeshArrays arrays;
    arrays.vertices_W.reserve(mesh.n_vertices());
    for (const auto vh : mesh.vertices()) {
        const auto& p = mesh.point(vh);
        arrays.vertices_W.emplace_back(p[0], p[1], p[2]);
    }
    arrays.faces.reserve(mesh.n_faces());
    for (const auto fh : mesh.faces()) {
        std::array<std::uint32_t, 3> face{};
        int k = 0;
        for (const auto vh : mesh.fv_range(fh)) {
            if (k < 3) face[k] = static_cast<std::uint32_t>(vh.idx());
            ++k;
        }
        arrays.faces.push_back(face);
    }
    return arrays;
}

}  // namespace vdbmap::texture
