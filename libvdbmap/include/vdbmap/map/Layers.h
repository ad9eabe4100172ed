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

/// Names of the grids in map.vdb (VoxelMap, VdbIO). Further names come from
/// VoxelMap::setExtraGrid.
namespace vdbmap::grids {

/// The packed TSDF grid of a VoxelMap while it is integrated (not written to map.vdb).
inline constexpr const char* kTsdf = "tsdf";
/// Signed distance (m), level set class.
inline constexpr const char* kSurface = "surface";
/// Accumulated weight of each voxel.
inline constexpr const char* kWeight = "weight";
/// Truncation eps (m) of each voxel's 8^3 block.
inline constexpr const char* kTruncation = "truncation";
/// Class id of each voxel (semantic plugin, optional).
inline constexpr const char* kLabel = "label";

}  // namespace vdbmap::grids

namespace vdbmap {
/// OpenMesh face property (uint8_t) that holds the class id of each face; 255 = unknown.
inline constexpr const char* kFaceLabelProperty = "label";
/// OpenMesh face property (int) that holds the view chosen to texture each face; -1 = none.
inline constexpr const char* kFaceTextureViewProperty = "texture_view";
/// OpenMesh face property (float) that holds the confidence of each face's class in [0, 1]
/// (semantic.mrf).
inline constexpr const char* kFaceLabelConfidenceProperty = "label_confidence";
/// OpenMesh face property (std::array<float, 6>) that holds each face's texture coordinates,
/// u v per corner in the face's vertex order, OBJ convention (v up); texture.mrf.
inline constexpr const char* kFaceTextureUvProperty = "texture_uv";
/// OpenMesh face property (int) that holds each face's atlas page (kFaceTextureUvProperty).
inline constexpr const char* kFaceTexturePageProperty = "texture_page";
/// OpenMesh mesh property (std::vector<cv::Mat>, CV_8UC3 BGR) that holds the atlas pages, so
/// that later stages of the same tile need not read them back (texture.mrf).
inline constexpr const char* kMeshTextureAtlasProperty = "texture_atlas";
/// Class id for void / unknown (docs/DATA.md).
inline constexpr unsigned char kUnknownLabel = 255;
}  // namespace vdbmap
