// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "SemanticOptions.h"
#include "vdbmap/pipeline/Stage.h"

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
    SemanticOptions opt_;
};

}  // namespace vdbmap::semantic
