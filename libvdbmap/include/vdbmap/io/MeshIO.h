// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/mesh/TriMesh.h"

namespace vdbmap {

/// What goes into a PLY besides positions and triangles.
struct PlyWriteOptions {
    bool vertex_normals = true;                              ///< nx ny nz (float)
    const std::vector<std::uint8_t>* face_labels = nullptr;  ///< uchar "label" per face
    const std::vector<std::array<std::uint8_t, 3>>* face_colors = nullptr;  ///< red green blue
    const std::vector<float>* face_confidence = nullptr;  ///< float "confidence" per face
    const std::vector<std::array<std::uint8_t, 3>>* vertex_colors = nullptr;
};

/// Writes binary little-endian PLY (docs/DATA.md), atomically. Throws IoError.
void writeMeshPly(const std::filesystem::path& path, const TriMesh& mesh,
                  const PlyWriteOptions& options = {});

/// Reads a triangle PLY (ascii or binary little-endian; extra properties ignored). If
/// `face_labels` is non-null and the file has a face "label" property, fills it. Throws
/// IoError naming the file and the problem.
TriMesh readMeshPly(const std::filesystem::path& path,
                    std::vector<std::uint8_t>* face_labels = nullptr);

/// What readMeshPly read: the faces of the file, the triangles they fan into, and those
/// OpenMesh refused (a third face on an edge, a face that makes a vertex non-manifold, a
/// repeated corner). Refused triangles are left out of the mesh (and of face_labels) and
/// logged as a warning; a caller that needs every face (ground truth) checks the count.
struct PlyReadStats {
    std::size_t file_faces = 0;
    std::size_t triangles = 0;
    std::size_t rejected_triangles = 0;
};
/// As above, and fills `stats`.
TriMesh readMeshPly(const std::filesystem::path& path, std::vector<std::uint8_t>* face_labels,
                    PlyReadStats* stats);

/// An OBJ with materials: positions, optional texture coordinates, and triangles that refer to
/// them by 0-based index, each triangle with a material.
struct ObjMaterial {
    std::string name;
    std::array<float, 3> diffuse{0.8f, 0.8f, 0.8f};  ///< Kd, 0..1
    std::string texture;                             ///< map_Kd, relative to the OBJ ("" = none)
};
struct ObjMesh {
    std::vector<Vec3f> positions;
    std::vector<Eigen::Vector2f> uvs;  ///< OBJ convention: v up, (0,0) bottom-left
    struct Triangle {
        std::array<std::uint32_t, 3> v;
        std::array<std::uint32_t, 3> vt;  ///< ignored if uvs is empty
        std::uint32_t material = 0;
    };
    std::vector<Triangle> triangles;
    std::vector<ObjMaterial> materials;
};

/// Writes `path` (.obj) and the .mtl beside it (same stem), both atomically, with relative
/// texture paths. Throws IoError.
void writeObj(const std::filesystem::path& path, const ObjMesh& mesh);

/// Reads an OBJ (v, vt, f with v/vt/vn forms, usemtl, mtllib + Kd/map_Kd). Polygons are
/// fan-triangulated. Throws IoError naming the file and line.
ObjMesh readObj(const std::filesystem::path& path);

}  // namespace vdbmap
