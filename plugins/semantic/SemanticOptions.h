// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include "vdbmap/render/ScanOcclusion.h"
#include "vdbmap/render/Visibility.h"

namespace vdbmap::semantic {

/// The options of `semantic.mrf` (SemanticMrfStage::declareOptions documents each one), in one
/// plain struct so that the stage's phases take what they need without the stage.
struct SemanticOptions {
    // The MRF (paper Sec. 6).
    double lambda = 0.5;
    double probability_floor = 1e-3;
    bool all_classes = false;
    int max_sweeps = 5;
    VisibilityOptions visibility;
    bool scan_occlusion = true;  ///< drop image votes the nearest-in-time scan hides
    ScanOcclusionOptions scan;
    std::string image_masks;        ///< folder of per-image masks ('' = none), texture.mrf's rule
    int image_masks_dilate_px = 2;
    std::string labels_file;
    // Outputs.
    std::vector<int> export_classes;
    bool label_grid = false;
    double label_grid_band_vox = 2.0;
    std::string output_subdir = "semantic";
    bool write_obj = true;
    int image_chunk = 64;
    // Sources.
    bool image_votes = true;
    bool lidar_labels = false;
    std::string label_map;
    double lidar_weight = 1.0;
    double lidar_vote_radius_m = 0.1;
    // Fill of faces no source saw.
    std::string fill = "geometric";
    double fill_normal_sigma_deg = 20.0;
    double fill_height_sigma_m = 0.03;
};

}  // namespace vdbmap::semantic
