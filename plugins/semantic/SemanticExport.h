// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "vdbmap/io/LabelSet.h"
#include "vdbmap/mesh/TriMesh.h"

namespace vdbmap::semantic {

/// Face count and surface area of one class id (255 = unknown) on the labelled mesh.
struct ClassStats {
    std::size_t faces = 0;
    double area_m2 = 0;
};

/// Statistics per class id present in `face_labels` (size n_faces). Throws InvalidInput on a
/// size mismatch.
std::map<std::uint8_t, ClassStats> classStatistics(const TriMesh& mesh,
                                                   const std::vector<std::uint8_t>& face_labels);

/// Stores the labels as the uint8_t face property kFaceLabelProperty ("label"), adding it if
/// needed. Throws InvalidInput on a size mismatch.
void setFaceLabelProperty(TriMesh& mesh, const std::vector<std::uint8_t>& face_labels);

/// Stores the confidences as the float face property kFaceLabelConfidenceProperty, adding it
/// if needed. Throws InvalidInput on a size mismatch.
void setFaceConfidenceProperty(TriMesh& mesh, const std::vector<float>& confidence);

/// `semantic/mesh.ply` (docs/DATA.md): binary PLY with face uchar label and red green blue from the
/// label set's colours (black for 255), and float "confidence" if `confidence` is non-null.
/// Atomic. Throws IoError / InvalidInput.
void writeSemanticPly(const std::filesystem::path& path, const TriMesh& mesh,
                      const std::vector<std::uint8_t>& face_labels, const LabelSet& labels,
                      const std::vector<float>* confidence = nullptr);

/// Material name of a class in the OBJ: "class_<id>_<name>" (spaces -> '_'), "unknown" for 255.
std::string classMaterialName(std::uint8_t id, const LabelSet& labels);

/// `semantic/mesh.obj` + `mesh.mtl`: every face gets the material of its class; the MTL has
/// one material per class of the label set plus "unknown" (Kd = the class colour), so that
/// Blender shows the classes. Atomic. Throws IoError / InvalidInput.
void writeSemanticObj(const std::filesystem::path& path, const TriMesh& mesh,
                      const std::vector<std::uint8_t>& face_labels, const LabelSet& labels);

/// The faces of one class as their own mesh (only the vertices they use), for HD-map work
/// such as lane markings. Empty if no face has the class.
TriMesh extractClassMesh(const TriMesh& mesh, const std::vector<std::uint8_t>& face_labels,
                         std::uint8_t id);

/// File name of a class export: "class_<id>_<name>.ply", e.g. "class_19_lane_marking.ply".
std::string classMeshFileName(std::uint8_t id, const LabelSet& labels);

}  // namespace vdbmap::semantic
