// SPDX-License-Identifier: Apache-2.0
#include "TileSummaryStage.h"

#include <vdbmap/core/Log.h>
#include <vdbmap/io/Dataset.h>
#include <vdbmap/io/Image.h>
#include <vdbmap/pipeline/Context.h>
#include <vdbmap/pipeline/Report.h>
#include <vdbmap/pipeline/Tiling.h>

#include <algorithm>
#include <limits>
#include <sstream>

namespace vdbmap_template {

void TileSummaryStage::declareOptions(vdbmap::OptionSpec& spec) {
    spec.add("max_images", "Images of the views read for the mean colour (0 = none)",
             max_images_, 4);
    spec.add("file_name", "File written into the stage's output folder", file_name_,
             std::string("summary.json"));
}

void TileSummaryStage::initialize() {
    if (max_images_ < 0) {
        failConfig("option 'max_images' must be >= 0, got " + std::to_string(max_images_));
    }
    if (file_name_.empty()) failConfig("option 'file_name' must not be empty");
}

void TileSummaryStage::declareLayers(vdbmap::LayerSpec& spec) const {
    spec.reads("mesh");
    spec.reads("images");
}

void TileSummaryStage::run(vdbmap::Context& ctx) {
    // Read-only view of the context: mesh, halo flags, the tile's views.
    const vdbmap::Context& in = ctx;
    const vdbmap::TriMesh& mesh = in.mesh();
    const std::vector<std::uint8_t> halo = in.haloFaces();
    double area_m2 = 0.0;
    std::size_t core_faces = 0;
    float lo[3], hi[3];
    std::fill(lo, lo + 3, std::numeric_limits<float>::max());
    std::fill(hi, hi + 3, std::numeric_limits<float>::lowest());
    for (const auto fh : mesh.faces()) {
        if (halo[static_cast<std::size_t>(fh.idx())]) continue;  // a neighbour's face
        ++core_faces;
        area_m2 += mesh.calc_face_area(fh);
        for (const auto vh : mesh.fv_range(fh)) {
            const auto p = mesh.point(vh);
            for (int k = 0; k < 3; ++k) {
                lo[k] = std::min(lo[k], p[k]);
                hi[k] = std::max(hi[k], p[k]);
            }
        }
    }

    // The views that see this tile (all views untiled); images read on demand, one at a time.
    const std::vector<vdbmap::View> views = in.views(true, false);
    double bgr_sum[3] = {0, 0, 0};
    std::size_t pixels = 0, images = 0;
    for (const vdbmap::View& view : views) {
        if (images >= static_cast<std::size_t>(max_images_)) break;
        const auto path = in.dataset().imagePath(view.frame, view.camera);
        if (!path) continue;
        const cv::Mat image = vdbmap::readColorImage(*path);
        const cv::Scalar mean = cv::mean(image);
        const auto n = static_cast<std::size_t>(image.total());
        for (int c = 0; c < 3; ++c) bgr_sum[c] += mean[c] * static_cast<double>(n);
        pixels += n;
        ++images;
    }

    std::ostringstream json;
    json << "{\"tile\": \"" << (in.hasTile() ? in.tile().name() : std::string("all")) << "\""
         << ", \"core_faces\": " << core_faces << ", \"halo_faces\": " << mesh.n_faces() - core_faces
         << ", \"area_m2\": " << area_m2 << ", \"views\": " << views.size()
         << ", \"images_read\": " << images;
    if (core_faces > 0) {
        json << ", \"mesh_min\": [" << lo[0] << ", " << lo[1] << ", " << lo[2] << "]"
             << ", \"mesh_max\": [" << hi[0] << ", " << hi[1] << ", " << hi[2] << "]";
    }
    if (in.hasTile()) {
        const auto& b = in.tile().core_W;
        json << ", \"tile_min\": [" << b.min_W.x() << ", " << b.min_W.y() << ", " << b.min_W.z()
             << "], \"tile_max\": [" << b.max_W.x() << ", " << b.max_W.y() << ", " << b.max_W.z()
             << "]";
    }
    if (pixels > 0) {
        json << ", \"mean_bgr\": [" << bgr_sum[0] / pixels << ", " << bgr_sum[1] / pixels << ", "
             << bgr_sum[2] / pixels << "]";
    }
    json << "}\n";
    // Outputs go through the context: atomically, into the tile's folder in tiled runs.
    in.writeOutput(file_name_, json.str());
    ctx.report().stage(std::string(name()), "core_faces", core_faces);
    ctx.report().stage(std::string(name()), "views", views.size());
    vdbmap::logInfo("template.tile_summary: " + std::to_string(core_faces) + " faces, " +
                    std::to_string(views.size()) + " views");
}

}  // namespace vdbmap_template
