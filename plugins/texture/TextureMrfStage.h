// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include "TexturePipeline.h"
#include "vdbmap/pipeline/Report.h"
#include "vdbmap/pipeline/Stage.h"
#include "vdbmap/render/ScanOcclusion.h"

namespace vdbmap::texture {

/// Stage `texture.mrf` (paper Sec. 5): reads the mesh and the dataset's camera images, writes
/// `<output>/textured/mesh.obj`, `mesh.mtl` and the atlas PNGs, and the per-face chosen view
/// as the mesh face property "texture_view" (int, -1 = none). A thin adapter around
/// textureMesh() (TexturePipeline.h); visibility, adjacency and the MRF solver come from the
/// library. Each of the four steps (MRF, vignetting, photo-consistency, global adjustment) can
/// be switched off for ablations.
class TextureMrfStage : public Stage {
public:
    std::string_view name() const override { return "texture.mrf"; }
    std::string_view summary() const override {
        return "Textures the mesh from the camera images: MRF view selection, vignetting "
               "correction, photo-consistency, global colour adjustment, atlas + OBJ";
    }
    void declareOptions(OptionSpec& spec) override;
    void initialize() override;
    void declareLayers(LayerSpec& spec) const override;
    void run(Context& ctx) override;

private:
    /// Phase: the TextureOptions of the stage options for `num_cameras` cameras.
    TextureOptions textureOptions(std::size_t num_cameras, bool quiet) const;
    /// Phase: counts, timings and the vignetting used into report.json.
    void reportStats(Report& report, const TextureStats& stats, double export_s,
                     double total_s) const;

    bool mrf_ = true;
    double lambda_ = 1.0;
    int max_candidates_ = 0;
    bool vignetting_ = false;
    std::vector<double> vignetting_params_;
    bool estimate_vignetting_ = false;
    std::string exposure_gains_ = "auto";
    bool scan_occlusion_ = true;
    ScanOcclusionOptions scan_;
    std::string image_masks_;
    int image_masks_dilate_px_ = 2;
    std::string seam_space_ = "log_luminance";
    double seam_max_log_difference_ = 0.1;
    bool photo_consistency_ = true;
    double photo_max_distance_ = 2.5;
    int photo_min_views_ = 3;
    bool global_adjustment_ = true;
    double seam_smoothness_ = 0.1;
    int padding_px_ = 2;
    int atlas_max_size_px_ = 8192;
    double max_view_angle_deg_ = 80.0;
    double min_depth_m_ = 0.1;
    double max_depth_m_ = 200.0;
    bool occlusion_test_ = true;
    std::string output_subdir_ = "textured";
    std::string fill_ = "neighbour";
};

}  // namespace vdbmap::texture
