// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <opencv2/core.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/io/MeshIO.h"

namespace vdbmap {

/// A ground-truth scene of the simulator: a textured triangle mesh (world frame, metres) with a
/// class id per face (docs/DATA.md label set). Materials carry a BGR8 texture; UVs follow the OBJ
/// convention (v up) and repeat outside [0, 1].
struct SimScene {
    ObjMesh mesh;                            ///< positions, UVs, triangles, materials
    std::vector<cv::Mat> textures;           ///< per material, 8-bit BGR (same size as materials)
    std::vector<std::uint8_t> face_labels;   ///< per triangle, class id

    std::size_t numTriangles() const { return mesh.triangles.size(); }

    /// Adds a material with a texture (8-bit BGR, non-empty); returns its index.
    std::uint32_t addMaterial(const std::string& name, const cv::Mat& texture_bgr);
    /// Adds one triangle with per-corner UVs.
    void addTriangle(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Eigen::Vector2f& uv_a,
                     const Eigen::Vector2f& uv_b, const Eigen::Vector2f& uv_c,
                     std::uint32_t material, std::uint8_t label);
    /// Adds the planar quad a-b-c-d (counter-clockwise seen from the front), textured with a
    /// texture tile every `tile_m` metres along the edges a->b and a->d.
    void addQuad(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec3f& d, float tile_m,
                 std::uint32_t material, std::uint8_t label);
    /// Adds a closed box (6 quads facing outwards) with `pose` mapping the box frame (centred,
    /// axis-aligned, half extents `half_m`) into the world.
    void addBox(const Isometry3d& pose, const Vec3f& half_m, float tile_m, std::uint32_t material,
                std::uint8_t label);
    /// Adds a closed cylinder along the z axis of `pose` (from its origin up by `height_m`).
    void addCylinder(const Isometry3d& pose, float radius_m, float height_m, int segments,
                     float tile_m, std::uint32_t material, std::uint8_t label);
    /// Adds a closed, bumpy sphere-like blob (vegetation): radius modulated by `bumpiness`
    /// (0 = sphere), deterministic for a seed.
    void addBlob(const Vec3f& centre, float radius_m, float bumpiness, std::uint32_t seed,
                 float tile_m, std::uint32_t material, std::uint8_t label);
    /// Appends an OBJ mesh transformed by `pose`, all its faces with `label`. Its materials and
    /// `textures` (one per material of `other`) are appended too.
    void append(const ObjMesh& other, const std::vector<cv::Mat>& other_textures,
                const Isometry3d& pose, std::uint8_t label);
    /// Applies a rigid transform to every vertex.
    void transform(const Isometry3d& T_new_old);

    /// The triangles as index triples (for Raycaster).
    std::vector<std::array<std::uint32_t, 3>> triangleIndices() const;
    /// The scene as an OpenMesh TriMesh (faces in triangle order).
    TriMesh toTriMesh() const;
    /// Writes the scene as a textured OBJ (+ .mtl + one PNG per material, named
    /// `<stem>_<material>.png`) beside `obj_path`. Throws IoError.
    void writeTexturedObj(const std::filesystem::path& obj_path) const;
};

/// Loads an OBJ with its textures (map_Kd, read as BGR; a material without texture gets a
/// 1x1 texture of its Kd colour). Throws IoError naming the file.
void loadTexturedObj(const std::filesystem::path& obj_path, ObjMesh& mesh,
                     std::vector<cv::Mat>& textures);

}  // namespace vdbmap
