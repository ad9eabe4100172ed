// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "TexturePipeline.h"
#include "TextureTypes.h"
#include "vdbmap/io/MeshIO.h"

namespace vdbmap::texture {

/// File name of atlas page k, relative to the OBJ: "mesh_atlas_<k>.png".
std::string atlasFileName(std::size_t page);

/// The textured mesh as an ObjMesh: the mesh's positions, three UVs per face (one per corner,
/// so charts never share texture coordinates), one material per atlas page with map_Kd set to
/// atlasFileName(page).
ObjMesh makeTexturedObj(const MeshArrays& mesh, const TextureResult& texture);

/// Writes `dir`/mesh.obj, `dir`/mesh.mtl and the atlas PNGs (docs/DATA.md layout: relative texture
/// paths), each atomically; the PNGs are written first so that a reader of mesh.obj always
/// finds its textures. Throws IoError.
void writeTexturedMesh(const std::filesystem::path& dir, const MeshArrays& mesh,
                       const TextureResult& texture);

}  // namespace vdbmap::texture
