// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "vdbmap/pipeline/Stage.h"

namespace vdbmap::cgal {

/// `mesh.simplify`: quadric edge-collapse decimation of the mesh, bounded by a maximum error
/// (CGAL Surface_mesh_simplification, GPL; see README.md).
class SimplifyStage : public Stage {
public:
    std::string_view name() const override { return "mesh.simplify"; }
    std::string_view summary() const override {
        return "Quadric edge-collapse decimation with a bounded error (CGAL, GPL, optional)";
    }
    void declareOptions(OptionSpec& spec) override;
    void initialize() override;
    void declareLayers(LayerSpec& spec) const override;
    void run(Context& ctx) override;

private:
    double target_ratio_ = 0.25;
    double max_error_m_ = 0.02;
};

}  // namespace vdbmap::cgal
