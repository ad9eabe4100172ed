// SPDX-License-Identifier: Apache-2.0
#pragma once

/// Names of the layers that stages read and write (LayerSpec). The pipeline checks, before
/// anything runs, that every layer a stage reads has an earlier writer. Plugins may add names.
namespace vdbmap::layers {

/// The TSDF map: grids "tsdf" (signed distance, m) and "weight", plus per-leaf statistics.
inline constexpr const char* kTsdf = "tsdf";
/// The triangle mesh (TriMesh) with per-vertex normals.
inline constexpr const char* kMesh = "mesh";
/// Per-face class ids on the mesh (face property kFaceLabelProperty).
inline constexpr const char* kFaceLabels = "labels";
/// Per-face chosen texture view and the written textured OBJ.
inline constexpr const char* kTexture = "texture";
/// Camera images of the dataset (always present when the dataset has cameras).
inline constexpr const char* kImages = "images";
/// Semantic id images of the dataset.
inline constexpr const char* kSemanticImages = "semantic_images";
/// LiDAR scans and poses of the dataset.
inline constexpr const char* kScans = "scans";

}  // namespace vdbmap::layers

namespace vdbmap {
/// OpenMesh face property (uint8_t) that holds the class id of each face; 255 = unknown.
inline constexpr const char* kFaceLabelProperty = "label";
/// Class id for void / unknown (DATA.md).
inline constexpr unsigned char kUnknownLabel = 255;
}  // namespace vdbmap
