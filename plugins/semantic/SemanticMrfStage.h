// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include "vdbmap/pipeline/Stage.h"
#include "vdbmap/render/Visibility.h"

namespace vdbmap::semantic {

/// Stage `semantic.mrf` (paper Sec. 6): labels every mesh face with a class from the semantic
/// id images and/or the per-point LiDAR labels. Reads layers `mesh` and `semantic_images`,
/// writes `labels` (the face property kFaceLabelProperty) and `semantic/mesh.ply` (with the
/// face confidence), `semantic/mesh.obj` + `.mtl`, optional class meshes and an optional
/// "label" grid in map.vdb. A thin adapter around SemanticVotes, LidarVotes,
/// VoteCombination, GeometricSmoothness, SemanticFusion, SemanticExport and LabelGrid.
class SemanticMrfStage : public Stage {
public:
    std::string_view name() const override { return "semantic.mrf"; }
    std::string_view summary() const override {
        return "Per-face class votes from semantic images and LiDAR labels, fused by a Potts MRF";
    }
    void declareOptions(OptionSpec& spec) override;
    void initialize() override;
    void declareLayers(LayerSpec& spec) const override;
    void run(Context& ctx) override;

private:
    double lambda_ = 0.5;
    double probability_floor_ = 1e-3;
    bool all_classes_ = false;
    int max_sweeps_ = 5;
    VisibilityOptions visibility_;
    std::string labels_file_;
    std::vector<int> export_classes_;
    bool label_grid_ = false;
    double label_grid_band_vox_ = 2.0;
    std::string output_subdir_ = "semantic";
    bool write_obj_ = true;
    int image_chunk_ = 64;
    // Sources.
    bool image_votes_ = true;
    bool lidar_labels_ = false;
    std::string label_map_;
    double lidar_weight_ = 1.0;
    double lidar_vote_radius_m_ = 0.1;
    // Fill of faces no source saw.
    std::string fill_ = "geometric";
    double fill_normal_sigma_deg_ = 20.0;
    double fill_height_sigma_m_ = 0.03;
};

}  // namespace vdbmap::semantic
