// SPDX-License-Identifier: Apache-2.0
#include "ObjExport.h"

#include "vdbmap/io/Image.h"

namespace vdbmap::texture {

std::string atlasFileName(std::size_t page) {
    return "mesh_atlas_" + std::to_string(page) + ".png";
}

ObjMesh makeTexturedObj(const MeshArrays& mesh, const TextureResult& texture) {
    ObjMesh obj;
    obj.positions = mesh.vertices_W;
    obj.uvs.reserve(3 * mesh.faces.size());
    obj.triangles.reserve(mesh.faces.size());
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        ObjMesh::Triangle tri;
        tri.v = mesh.faces[f];
        for (int k = 0; k < 3; ++k) {
            tri.vt[k] = static_cast<std::uint32_t>(obj.uvs.size());
            obj.uvs.push_back(texture.face_uvs[f][k]);
        }
        tri.material = texture.face_page[f];
        obj.triangles.push_back(tri);
    }
    for (std::size_t p = 0; p < texture.pages.size(); ++p) {
        ObjMaterial material;
        material.name = "atlas_" + std::to_string(p);
        material.diffuse = {1.0f, 1.0f, 1.0f};
        material.texture = atlasFileName(p);
        obj.materials.push_back(material);
    }
    return obj;
}

void writeTexturedMesh(const std::filesystem::path& dir, const MeshArrays& mesh,
                       const TextureResult& texture) {
    for (std::size_t p = 0; p < texture.pages.size(); ++p) {
        writePng(dir / atlasFileName(p), texture.pages[p]);
    }
    writeObj(dir / "mesh.obj", makeTexturedObj(mesh, texture));
}

}  // namespace vdbmap::texture
