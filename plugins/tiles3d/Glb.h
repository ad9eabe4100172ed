// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "TileMesh.h"

namespace vdbmap::tiles3d {

/// One class of the label set, as the GLB's class property table holds it.
struct ClassInfo {
    std::uint8_t id = 255;
    std::string name;
    std::array<std::uint8_t, 3> rgb{0, 0, 0};
};

struct GlbOptions {
    bool jpeg = true;        ///< atlas pages as JPEG (else PNG)
    int jpeg_quality = 90;   ///< 1..100
    bool meshopt = true;     ///< EXT_meshopt_compression on the vertex attributes
};

/// The tile as a binary glTF 2.0 (docs/tiles3d.md "The GLB"):
/// - one node, translation = origin_W in glTF axes (relative-to-centre), one mesh with one
///   primitive per atlas page (plus one without texture for untextured faces), unindexed;
/// - glTF is y-up: a point p of W (z up) is stored as (p.x, p.z, -p.y) - origin, so that the
///   3D Tiles runtime's y-up to z-up rotation gives W back;
/// - EXT_mesh_features: feature id set 0 (`_FEATURE_ID_0`) = the face's index, row of property
///   table 0 "face" (class_id, confidence); set 1 (`_FEATURE_ID_1`) = row of table 1 "semantic_class"
///   (class_id, name, color) - EXT_structural_metadata;
/// - atlas pages as JPEG or PNG images in the binary chunk; EXT_meshopt_compression
///   (required, no fallback data) on the vertex attributes when options.meshopt.
/// `classes` must hold every label of the mesh (else InvalidInput). Deterministic bytes.
std::string writeGlb(const TileMesh& mesh, const std::vector<ClassInfo>& classes,
                     const GlbOptions& options);

/// What readGlb found besides the mesh.
struct GlbInfo {
    std::vector<ClassInfo> classes;
    std::vector<std::string> image_mime_types;
    bool meshopt = false;
};

/// Reads a GLB written by writeGlb back (faces in feature-id order, pages decoded). Throws
/// InvalidInput naming `what` and the problem.
TileMesh readGlb(const std::string& bytes, const std::string& what, GlbInfo* info = nullptr);

/// glTF axes (y up) from W (z up) and back.
inline Eigen::Vector3d gltfFromW(const Eigen::Vector3d& p_W) { return {p_W.x(), p_W.z(), -p_W.y()}; }
inline Eigen::Vector3d wFromGltf(const Eigen::Vector3d& g) { return {g.x(), -g.z(), g.y()}; }

}  // namespace vdbmap::tiles3d
