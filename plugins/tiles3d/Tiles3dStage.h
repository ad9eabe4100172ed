// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <atomic>
#include <string>
#include <vector>

#include "Glb.h"
#include "Tileset.h"
#include "vdbmap/pipeline/Stage.h"

namespace vdbmap::tiles3d {

/// `export.3dtiles` (issue 34, docs/tiles3d.md): the map as OGC 3D Tiles 1.1. Per tile (run):
/// the tile's core faces with their texture (texture.mrf's atlas, from the mesh) and class and
/// confidence (semantic.mrf) as 3dtiles/tile.glb, plus 3dtiles/tile.json (bounds, figures).
/// After the run (finishRun, process 0): the quadtree of simplified parents in
/// OUT/3dtiles/lod/, drive_path.json, and last, atomically, OUT/3dtiles/tileset.json.
class Tiles3dStage : public Stage {
public:
    std::string_view name() const override { return "export.3dtiles"; }
    std::string_view summary() const override {
        return "Write the map as OGC 3D Tiles 1.1 (GLB leaves per tile, LOD quadtree, tileset.json)";
    }
    void declareOptions(OptionSpec& spec) override;
    void initialize() override;
    void declareLayers(LayerSpec& spec) const override;
    void run(Context& ctx) override;
    void beginRun(Context& ctx) override;
    void finishRun(Context& ctx, const std::vector<FinishedTile>& tiles) override;

private:
    std::vector<ClassInfo> classes(const Context& ctx) const;
    GlbOptions glbOptions() const;

    std::string image_format_ = "jpeg";
    int jpeg_quality_ = 90;
    std::string compression_ = "meshopt";
    int lod_levels_ = -1;
    int lod_atlas_max_px_ = 4096;
    int lod_parents_in_flight_ = 2;
    std::string labels_file_;
    bool georef_ = false;
    double latitude_deg_ = 0, longitude_deg_ = 0, altitude_m_ = 0, heading_deg_ = 0;
    bool drive_path_ = true;
    /// Set by the first tile's run: a later untiled run() is tiling.merge's pass over the whole
    /// map, whose GLB nothing would use (the tileset's leaves are the tiles').
    std::atomic<bool> saw_tile_{false};
};

}  // namespace vdbmap::tiles3d
