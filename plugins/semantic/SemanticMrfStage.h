// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include "vdbmap/pipeline/Stage.h"

namespace vdbmap::semantic {

/// Stage `semantic.mrf` (paper Sec. 6): labels every mesh face with a class from the semantic
/// id images. Reads layers `mesh` and `semantic_images`, writes `labels` (the face property
/// kFaceLabelProperty) and `semantic/mesh.ply`, `semantic/mesh.obj` + `.mtl`, optional class
/// meshes and an optional "label" grid in map.vdb. A thin adapter around SemanticVotes,
/// SemanticFusion, SemanticExport and LabelGrid.
class SemanticMrfStage : public Stage {
public:
    std::string_view name() const override { return "semantic.mrf"; }
    std::string_view summary() const override {
        return "Per-face class votes from semantic images, fused by a Potts MRF";
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
    double max_view_angle_deg_ = 80.0;
    double min_depth_m_ = 0.1;
    double max_depth_m_ = 200.0;
    bool occlusion_test_ = true;
    double occlusion_tolerance_m_ = 0.02;
    std::string labels_file_;
    std::vector<int> export_classes_;
    bool label_grid_ = false;
    double label_grid_band_vox_ = 2.0;
    std::string output_subdir_ = "semantic";
    bool write_obj_ = true;
    int image_chunk_ = 64;
};

}  // namespace vdbmap::semantic
