// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>

#include "vdbmap/pipeline/Stage.h"

namespace vdbmap_template {

/// `template.tile_summary`: a mesh stage written against the tile API, so it runs unchanged in
/// tiled runs (once per tile, on the tile's mesh and views) and untiled runs (once, on the whole
/// mesh). It reads the mesh (core faces only: halo faces belong to a neighbour), the views that
/// see it and their images (read on demand), and writes summary.json into its output folder
/// (the tile's folder in tiled runs) through Context::writeOutput.
class TileSummaryStage : public vdbmap::Stage {
public:
    std::string_view name() const override { return "template.tile_summary"; }
    std::string_view summary() const override {
        return "Example mesh stage: area, bounds, views and mean image colour of its (tile's) mesh";
    }
    void declareOptions(vdbmap::OptionSpec& spec) override;
    void initialize() override;
    void declareLayers(vdbmap::LayerSpec& spec) const override;
    void run(vdbmap::Context& ctx) override;

private:
    int max_images_ = 4;
    std::string file_name_;
};

}  // namespace vdbmap_template
