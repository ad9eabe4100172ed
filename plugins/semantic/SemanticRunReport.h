// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "SemanticFusion.h"
#include "SemanticSources.h"

namespace vdbmap {
class Report;
}

namespace vdbmap::semantic {

/// Everything one run of `semantic.mrf` measured, for report.json and the log line.
struct SemanticRunFigures {
    const FaceArrays* faces = nullptr;
    const ImageVotes* images = nullptr;
    const LidarVoteResult* lidar = nullptr;  ///< null when lidar_labels is off
    const FaceVotes* votes = nullptr;        ///< the combined votes
    const std::vector<std::uint8_t>* sources = nullptr;  ///< kSourceImages | kSourceLidar per face
    const FusionResult* result = nullptr;
    const LabelSet* labels = nullptr;
    std::string label_map;  ///< the option (reported with the LiDAR counts)
    std::string fill;
    double mrf_s = 0, export_s = 0, total_s = 0;
};

/// Writes the stage's figures below stages.<stage> of `report`: counts, sources, energies,
/// timings, the share of faces and area by the sources that labelled them, the area-weighted
/// confidence and the faces and area per class; then logs a one-line summary.
void reportSemanticRun(Report& report, const std::string& stage, const TriMesh& mesh,
                       const SemanticRunFigures& figures);

}  // namespace vdbmap::semantic
