// SPDX-License-Identifier: Apache-2.0
#include "TextureMrfStage.h"

#include <algorithm>
#include <array>
#include <filesystem>
#include <sstream>

#include "ObjExport.h"
#include "TexturePipeline.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/io/Image.h"
#include "vdbmap/map/Layers.h"
#include "vdbmap/mesh/MeshAdjacency.h"
#include "vdbmap/mrf/PottsMrf.h"
#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/StageVisibility.h"
#include "vdbmap/pipeline/Report.h"
#include "vdbmap/pipeline/Tiling.h"
#include "vdbmap/core/Progress.h"
#include "vdbmap/render/Raycaster.h"
#include "vdbmap/dynamic/MovingReturns.h"
#include "vdbmap/render/ImageMasks.h"
#include "vdbmap/render/ScanOcclusion.h"
#include "vdbmap/render/Visibility.h"
#include "vdbmap/render/VisibilitySetup.h"

namespace vdbmap::texture {

namespace {

/// The core faces of a tile's mesh and their texture (tiled runs write only the faces a tile
/// owns; halo faces took part in the MRF and the seam levelling). Unused vertices are dropped.
void keepCoreFaces(const std::vector<std::uint8_t>& halo, MeshArrays& mesh, TextureResult& tex) {
    std::vector<std::int64_t> vertex_map(mesh.vertices_W.size(), -1);
    MeshArrays core;
    std::size_t kept = 0;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
        if (halo[f]) continue;
        std::array<std::uint32_t, 3> face{};
        for (int k = 0; k < 3; ++k) {
            std::int64_t& v = vertex_map[mesh.faces[f][static_cast<std::size_t>(k)]];
            if (v < 0) {
                v = static_cast<std::int64_t>(core.vertices_W.size());
                core.vertices_W.push_back(mesh.vertices_W[mesh.faces[f][static_cast<std::size_t>(k)]]);
            }
            face[static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(v);
        }
        core.faces.push_back(face);
        tex.face_uvs[kept] = tex.face_uvs[f];
        tex.face_page[kept] = tex.face_page[f];
        tex.face_view[kept] = tex.face_view[f];
        ++kept;
    }
    tex.face_uvs.resize(kept);
    tex.face_page.resize(kept);
    tex.face_view.resize(kept);
    mesh = std::move(core);
}

}  // namespace

void TextureMrfStage::declareOptions(OptionSpec& spec) {
    spec.add("mrf", "View selection by the Potts MRF (alpha-expansion); false = per-face best view",
             mrf_, true);
    spec.add("lambda", "Weight of the Potts smoothness against the per-face data cost in [0, 1]",
             lambda_, 1.0);
    spec.add("max_candidates",
             "Views per face the MRF may choose from (highest E_Q first); 0 = all", max_candidates_,
             0);
    spec.add("vignetting", "Correct vignetting I' = g(r) I before anything else", vignetting_,
             false);
    spec.add("vignetting_params",
             "a b c of g(r) = 1 + a r^2 + b r^4 + c r^6: 3 values for every camera, or 3 per "
             "camera in dataset order",
             vignetting_params_, std::vector<double>{});
    spec.add("estimate_vignetting",
             "Estimate a b c per camera from overlapping observations (needs vignetting: true)",
             estimate_vignetting_, false);
    spec.add("exposure_gains",
             "Estimate one exposure gain per image jointly from the overlaps (least squares on "
             "log luminance, mean log gain 0) and texture from the corrected images: 'auto' (on "
             "when vignetting is corrected: uncorrected vignetting biases every overlap the same "
             "way and the gains drift, docs/texturing.md), 'true' or 'false'",
             exposure_gains_, std::string("auto"));
    spec.add("photo_consistency", "Reject outlier views per face (Waechter et al. 2014, HSV)",
             photo_consistency_, true);
    spec.add("photo_max_distance", "Photo-consistency: reject views farther than this (sigmas)",
             photo_max_distance_, 2.5);
    spec.add("photo_min_views", "Photo-consistency: only faces seen by at least this many views",
             photo_min_views_, 3);
    spec.add("global_adjustment", "Global colour adjustment (seam levelling, Lempitsky-Ivanov)",
             global_adjustment_, true);
    spec.add("seam_smoothness", "Global adjustment: weight of the smoothness of g inside patches",
             seam_smoothness_, 0.1);
    spec.add("seam_space",
             "Global adjustment: colour space of the levelling: 'log_luminance' (one gain for "
             "all channels: keeps every hue), 'log_bgr' (a gain per channel) or 'bgr' (additive "
             "offsets per channel, as published: shifts hues)",
             seam_space_, std::string("log_luminance"));
    spec.add("seam_max_log_difference",
             "Global adjustment (log spaces): seam vertices whose sides differ by more than this "
             "in log luminance are not levelled: after the exposure gains such a difference is "
             "mostly content, not exposure (0 = level all)",
             seam_max_log_difference_, 0.1);
    spec.add("padding_px", "Border of real image pixels around each chart against bleeding",
             padding_px_, 2, "px");
    spec.add("atlas_max_size_px", "Largest atlas page side", atlas_max_size_px_, 8192, "px");
    spec.add("max_view_angle_deg", "Reject views seeing a face flatter than this",
             max_view_angle_deg_, 80.0, "deg");
    spec.add("min_depth_m", "Nearest visible depth", min_depth_m_, 0.1, "m");
    spec.add("max_depth_m",
             "Farthest visible depth (40 m: about 2 px per 10 cm face at KITTI's focal "
             "length; nearer views win anyway, and the views per face, so the cost per metre "
             "of drive, stay bounded)",
             max_depth_m_, 40.0, "m");
    spec.add("occlusion_test", "Test occlusion by the mesh itself (Embree BVH)", occlusion_test_,
             true);
    spec.add("scan_occlusion",
             "A view does not texture a face that a return of the LiDAR scan nearest in time to "
             "its image hides (a moving car, anything in front that the map lacks)",
             scan_occlusion_, true);
    spec.add("scan_occlusion_margin_m",
             "Scan occlusion: a return hides a face at depth z when nearer than "
             "z * (1 - scan_occlusion_margin_rel) - this",
             scan_.margin_m, 0.3, "m");
    spec.add("scan_occlusion_margin_rel", "Scan occlusion: relative depth margin (see _margin_m)",
             scan_.margin_rel, 0.1);
    spec.add("scan_occlusion_dilate_px",
             "Scan occlusion: radius of the min filter along image rows that closes the gaps "
             "between a ring's returns",
             scan_.row_dilate_px, 2, "px");
    spec.add("scan_occlusion_gap_px",
             "Scan occlusion: the empty pixels of a column between two returns at most this many "
             "empty rows apart take the farther return (the gap between two rings)",
             scan_.gap_px, 8, "px");
    spec.add("scan_occlusion_moving_margin_m",
             "Scan occlusion: a return removed as moving (integrate.atsdf dynamic_removal) hides "
             "a face at depth z when nearer than z - this (it cannot be the face itself)",
             scan_.moving_margin_m, 0.1, "m");
    spec.add("scan_occlusion_moving_dilate_px",
             "Scan occlusion: radius of the min filter over the moving returns", scan_.moving_dilate_px,
             6, "px");
    spec.add("image_masks",
             "Folder of per-image masks (8-bit grey, the image's size and file name; in "
             "<folder>/<camera> with several cameras): a view does not texture a face that "
             "touches a non-zero pixel of its image's mask, e.g. the moving objects a 2D "
             "detector found. Images without a mask file are not masked ('' = no masks)",
             image_masks_, std::string());
    spec.add("image_masks_dilate_px", "Image masks: grown by this radius before the test",
             image_masks_dilate_px_, 2, "px");
    spec.add("fill",
             "Faces no view saw: 'smooth' (colours diffused from the textured border, a sparse "
             "Laplace solve), 'neighbour' (colour of the nearest textured face) or 'grey'",
             fill_, std::string("smooth"));
    spec.add("output_subdir", "Folder below the output folder for mesh.obj/.mtl and atlases",
             output_subdir_, std::string("textured"));
}

void TextureMrfStage::initialize() {
    if (lambda_ < 0) failConfig("option 'lambda' must be >= 0, got " + std::to_string(lambda_));
    if (max_candidates_ < 0) {
        failConfig("option 'max_candidates' must be >= 0, got " + std::to_string(max_candidates_));
    }
    if (vignetting_params_.size() % 3 != 0) {
        failConfig("option 'vignetting_params' needs 3 values per camera, got " +
                   std::to_string(vignetting_params_.size()));
    }
    if (estimate_vignetting_ && !vignetting_) {
        failConfig("option 'estimate_vignetting' needs 'vignetting: true'");
    }
    if (vignetting_ && !estimate_vignetting_ && vignetting_params_.empty()) {
        failConfig(
            "option 'vignetting' is on but 'vignetting_params' is empty and "
            "'estimate_vignetting' is off");
    }
    if (padding_px_ < 1 || padding_px_ > 64) {
        failConfig("option 'padding_px' must be in [1, 64], got " + std::to_string(padding_px_));
    }
    if (atlas_max_size_px_ < 64 || atlas_max_size_px_ > 8192) {
        failConfig("option 'atlas_max_size_px' must be in [64, 8192], got " +
                   std::to_string(atlas_max_size_px_));
    }
    if (!(max_view_angle_deg_ > 0 && max_view_angle_deg_ <= 90)) {
        failConfig("option 'max_view_angle_deg' must be in (0, 90], got " +
                   std::to_string(max_view_angle_deg_));
    }
    if (!(min_depth_m_ >= 0 && max_depth_m_ > min_depth_m_)) {
        failConfig("options 'min_depth_m' and 'max_depth_m' must satisfy 0 <= min < max, got " +
                   std::to_string(min_depth_m_) + " and " + std::to_string(max_depth_m_));
    }
    if (photo_max_distance_ <= 0) {
        failConfig("option 'photo_max_distance' must be > 0, got " +
                   std::to_string(photo_max_distance_));
    }
    if (seam_smoothness_ < 0) {
        failConfig("option 'seam_smoothness' must be >= 0, got " +
                   std::to_string(seam_smoothness_));
    }
    if (seam_space_ != "log_luminance" && seam_space_ != "log_bgr" && seam_space_ != "bgr") {
        failConfig("option 'seam_space' must be 'log_luminance', 'log_bgr' or 'bgr', got '" +
                   seam_space_ + "'");
    }
    if (scan_.margin_m < 0 || !(scan_.margin_rel >= 0 && scan_.margin_rel < 1) ||
        scan_.row_dilate_px < 0 || scan_.row_dilate_px > 32 || scan_.gap_px < 0 || scan_.gap_px > 64) {
        failConfig("options 'scan_occlusion_margin_m' >= 0, 'scan_occlusion_margin_rel' in [0, 1), "
                   "'scan_occlusion_dilate_px' in [0, 32] and 'scan_occlusion_gap_px' in [0, 64], got " +
                   std::to_string(scan_.margin_m) + ", " + std::to_string(scan_.margin_rel) +
                   ", " + std::to_string(scan_.row_dilate_px) + ", " + std::to_string(scan_.gap_px));
    }
    if (!(scan_.moving_margin_m >= 0) || scan_.moving_dilate_px < 0 || scan_.moving_dilate_px > 32) {
        failConfig("options 'scan_occlusion_moving_margin_m' >= 0 and "
                   "'scan_occlusion_moving_dilate_px' in [0, 32], got " +
                   std::to_string(scan_.moving_margin_m) + ", " + std::to_string(scan_.moving_dilate_px));
    }
    if (image_masks_dilate_px_ < 0 || image_masks_dilate_px_ > 32) {
        failConfig("option 'image_masks_dilate_px' must be in [0, 32], got " +
                   std::to_string(image_masks_dilate_px_));
    }
    if (!image_masks_.empty() && !std::filesystem::is_directory(image_masks_)) {
        failConfig("option 'image_masks': '" + image_masks_ + "' is not a directory");
    }
    if (exposure_gains_ != "auto" && exposure_gains_ != "true" && exposure_gains_ != "false") {
        failConfig("option 'exposure_gains' must be 'auto', 'true' or 'false', got '" +
                   exposure_gains_ + "'");
    }
    if (seam_max_log_difference_ < 0) {
        failConfig("option 'seam_max_log_difference' must be >= 0, got " +
                   std::to_string(seam_max_log_difference_));
    }
    if (output_subdir_.empty()) failConfig("option 'output_subdir' must not be empty");
    if (fill_ != "smooth" && fill_ != "neighbour" && fill_ != "grey") {
        failConfig("option 'fill' must be 'smooth', 'neighbour' or 'grey', got '" + fill_ + "'");
    }
}

void TextureMrfStage::declareLayers(LayerSpec& spec) const {
    spec.reads(layers::kMesh);
    spec.reads(layers::kImages);
    spec.writes(layers::kTexture);
}

TextureOptions TextureMrfStage::textureOptions(std::size_t num_cameras, bool quiet) const {
    TextureOptions options;
    options.use_mrf = mrf_;
    options.lambda = lambda_;
    options.max_candidates = static_cast<std::size_t>(max_candidates_);
    options.vignetting = vignetting_;
    options.estimate_vignetting = estimate_vignetting_;
    if (vignetting_params_.size() == 3) {
        options.vignetting_params.assign(
            num_cameras, {vignetting_params_[0], vignetting_params_[1], vignetting_params_[2]});
    } else if (!vignetting_params_.empty()) {
        if (vignetting_params_.size() != 3 * num_cameras) {
            fail("option 'vignetting_params' has " + std::to_string(vignetting_params_.size()) +
                 " values but the dataset has " + std::to_string(num_cameras) +
                 " cameras (3 values, or 3 per camera)");
        }
        for (std::size_t c = 0; c < num_cameras; ++c) {
            options.vignetting_params.push_back({vignetting_params_[3 * c],
                                                 vignetting_params_[3 * c + 1],
                                                 vignetting_params_[3 * c + 2]});
        }
    }
    options.exposure_gains =
        exposure_gains_ == "true" || (exposure_gains_ == "auto" && vignetting_);
    options.photo_consistency = photo_consistency_;
    options.photo.max_distance = photo_max_distance_;
    options.photo.min_views = photo_min_views_;
    options.global_adjustment = global_adjustment_;
    options.leveling.smoothness = seam_smoothness_;
    options.leveling.space = parseSeamSpace(seam_space_);
    options.leveling.max_log_difference = seam_max_log_difference_;
    options.padding_px = padding_px_;
    options.atlas_max_size_px = atlas_max_size_px_;
    options.quiet = quiet;
    options.fill_from_neighbours = fill_ == "neighbour" || fill_ == "smooth";
    options.smooth_fill = fill_ == "smooth";
    return options;
}

namespace {

// Phase: the "texture" layer, the chosen view per face on the shared mesh (-1 = fill).
void setTextureLayer(TriMesh& tri_mesh, const TextureResult& result) {
    OpenMesh::FPropHandleT<int> view_prop;
    if (!tri_mesh.get_property_handle(view_prop, kFaceTextureViewProperty)) {
        tri_mesh.add_property(view_prop, kFaceTextureViewProperty);
    }
    for (const auto fh : tri_mesh.faces()) {
        const std::uint32_t v = result.face_view[static_cast<std::size_t>(fh.idx())];
        tri_mesh.property(view_prop, fh) = v == kNoLabel ? -1 : static_cast<int>(v);
    }
    // The texture itself (UVs, page, atlas) for later stages of the same tile (export.3dtiles):
    // they need not read the textured OBJ back.
    OpenMesh::FPropHandleT<std::array<float, 6>> uv_prop;
    if (!tri_mesh.get_property_handle(uv_prop, kFaceTextureUvProperty)) {
        tri_mesh.add_property(uv_prop, kFaceTextureUvProperty);
    }
    OpenMesh::FPropHandleT<int> page_prop;
    if (!tri_mesh.get_property_handle(page_prop, kFaceTexturePageProperty)) {
        tri_mesh.add_property(page_prop, kFaceTexturePageProperty);
    }
    for (const auto fh : tri_mesh.faces()) {
        const auto f = static_cast<std::size_t>(fh.idx());
        std::array<float, 6> uv{};
        for (std::size_t k = 0; k < 3; ++k) {
            uv[2 * k] = result.face_uvs[f][k].x();
            uv[2 * k + 1] = result.face_uvs[f][k].y();
        }
        tri_mesh.property(uv_prop, fh) = uv;
        tri_mesh.property(page_prop, fh) = static_cast<int>(result.face_page[f]);
    }
    OpenMesh::MPropHandleT<std::vector<cv::Mat>> atlas_prop;
    if (!tri_mesh.get_property_handle(atlas_prop, kMeshTextureAtlasProperty)) {
        tri_mesh.add_property(atlas_prop, kMeshTextureAtlasProperty);
    }
    tri_mesh.property(atlas_prop) = result.pages;  // shares the pixels (cv::Mat)
}

}  // namespace

void TextureMrfStage::reportStats(Report& report, const TextureStats& s, double export_s,
                                  double total_s) const {
    const std::string stage(name());
    report.stage(stage, "faces", s.faces);
    report.stage(stage, "views", s.views);
    report.stage(stage, "observations", s.observations);
    report.stage(stage, "faces_untextured", s.faces_untextured);
    report.stage(stage, "untextured_fill",
                 fill_ == "smooth"
                     ? std::string("harmonic fill from the textured border (16 levels per channel)")
                 : fill_ == "neighbour"
                     ? std::string("colour of the nearest textured face (16 levels per channel)")
                     : std::string("grey (128, 128, 128)"));
    report.stage(stage, "photo_rejected_observations", s.photo_rejected);
    report.stage(stage, "patches", s.patches);
    report.stage(stage, "charts", s.charts);
    report.stage(stage, "atlas_pages", s.pages);
    report.stage(stage, "seam_edges", s.seam_edges);
    report.stage(stage, "mrf_energy_initial", s.energy_initial);
    report.stage(stage, "mrf_energy_final", s.energy_final);
    report.stage(stage, "mrf_sweeps", s.mrf_sweeps);
    report.stage(stage, "global_adjustment_unknowns", s.leveling_summary.unknowns);
    report.stage(stage, "global_adjustment_cg_iterations", s.leveling_summary.iterations);
    report.stage(stage, "global_adjustment_max_abs", s.leveling_summary.max_abs_correction);
    report.stage(stage, "global_adjustment_seam_terms", s.leveling_summary.seam_terms);
    report.stage(stage, "global_adjustment_seam_terms_dropped",
                 s.leveling_summary.seam_terms_dropped);
    for (std::size_t c = 0; c < s.vignetting_used.size(); ++c) {
        const auto& p = s.vignetting_used[c];
        report.set({"stages", stage, "vignetting_abc", "camera_" + std::to_string(c)},
                   std::vector<double>{p.a, p.b, p.c});
    }
    if (!s.exposure_gains.empty()) {
        const auto [lo, hi] = std::minmax_element(s.exposure_gains.begin(), s.exposure_gains.end());
        report.stage(stage, "exposure_faces", s.exposure_faces);
        report.stage(stage, "exposure_views_without_overlap", s.exposure_views_without_overlap);
        report.stage(stage, "exposure_gain_min", *lo);
        report.stage(stage, "exposure_gain_max", *hi);
        report.set({"stages", stage, "exposure_gains"}, s.exposure_gains);
    }
    for (const auto& [step_name, seconds] : s.timings_s) {
        report.set({"stages", stage, "timings_s", step_name}, seconds);
    }
    for (const auto& [step_name, bytes] : s.peak_memory_bytes) {
        report.set({"stages", stage, "peak_memory_bytes", step_name}, bytes);
    }
    report.set({"stages", stage, "timings_s", "export"}, export_s);
    report.set({"stages", stage, "timings_s", "total"}, total_s);
    report.stage(stage, "faces_per_s", total_s > 0 ? double(s.faces) / total_s : 0.0);
}

void TextureMrfStage::run(Context& ctx) {
    TriMesh& tri_mesh = ctx.mesh();
    const Dataset& dataset = ctx.dataset();
    const std::string stage(name());
    Report& report = ctx.report();
    Timer total;

    TextureOptions options = textureOptions(dataset.cameras().size(), ctx.quiet());

    const MeshArrays mesh = meshArrays(tri_mesh);
    if (mesh.faces.empty()) fail("the mesh has no faces: nothing to texture");
    // The views of the tile in a tiled run (Context::views), else every view.
    const std::vector<View> views = ctx.views(true, false);
    if (views.empty() && ctx.hasTile()) {
        logInfo(stage + ": no view sees tile " + ctx.tile().name() + ": not textured");
        report.stage(stage, "skipped", std::string("no view sees the tile"));
        return;
    }
    if (views.empty()) fail("the dataset has no colour images: nothing to texture from");

    Timer step;
    VisibilityOptions vis_options;
    vis_options.max_view_angle_deg = max_view_angle_deg_;
    vis_options.min_depth_m = min_depth_m_;
    vis_options.max_depth_m = max_depth_m_;
    vis_options.occlusion_test = occlusion_test_;
    // texture.mrf and semantic.mrf see the same faces from the same views: the visibility one
    // computed serves the other (stageVisibility, Context::keepVisibility).
    StageVisibility seen = stageVisibility(ctx, mesh, views, vis_options,
                                           scan_occlusion_ ? &scan_ : nullptr, stage);
    report.stage(stage, "visibility_reused", seen.reused);
    SharedVisibility& shared = seen.shared;
    if (scan_occlusion_) {
        report.set({"stages", stage, "timings_s", "scan_occlusion"}, seen.scan_occlusion_s);
    }
    Visibility& vis = shared.visibility;
    if (scan_occlusion_) {
        report.stage(stage, "scan_hidden_observations", shared.scan_hidden_cos.size());
        logInfo(stage + ": " + std::to_string(shared.scan_hidden_cos.size()) +
                " observations hidden by the scan nearest in time to their image");
    }
    if (!image_masks_.empty()) {
        // Pixels the user marked (e.g. a 2D detector's moving objects) give no face its colour.
        Timer mask_timer;
        const std::size_t masked = removeMaskedObservations(
            vis, views, directoryViewMasks(dataset, views, image_masks_), image_masks_dilate_px_);
        report.stage(stage, "masked_observations", masked);
        report.set({"stages", stage, "timings_s", "image_masks"}, mask_timer.elapsedSeconds());
        logInfo(stage + ": " + std::to_string(masked) + " observations on masked pixels (" +
                image_masks_ + ")");
    }
    const auto adjacency = faceAdjacency(tri_mesh);
    const double visibility_s = step.elapsedSeconds();
    report.set({"stages", stage, "timings_s", "visibility"}, visibility_s);
    report.set({"stages", stage, "peak_memory_bytes", "visibility"}, peakMemoryBytes());

    const ImageLoader load = [&](std::size_t v) {
        const auto path = dataset.imagePath(views[v].frame, views[v].camera);
        if (!path) {
            throw IoError("texture.mrf: image of frame " + std::to_string(views[v].frame) +
                          " camera " + std::to_string(views[v].camera) + " disappeared");
        }
        cv::Mat image = readColorImage(*path);
        requireImageSize(image, *path,
                         {views[v].intrinsics.width, views[v].intrinsics.height},
                         "camera '" + dataset.cameras()[views[v].camera].name +
                             "' (the size of its first image)");
        return image;
    };
    TextureResult result = textureMesh(mesh, views, vis, adjacency, load, options);
    // Hand the visibility on to a later stage (semantic.mrf) unless the masks changed it.
    if (image_masks_.empty()) ctx.keepVisibility(seen.key, std::move(shared));

    setTextureLayer(tri_mesh, result);

    // A tile writes its core faces only; the halo took part in the MRF and the seam levelling.
    step.reset();
    MeshArrays written = mesh;
    if (ctx.hasTile()) keepCoreFaces(ctx.haloFaces(), written, result);
    writeTexturedMesh(ctx.outputDir() / output_subdir_, written, result);
    const double export_s = step.elapsedSeconds();

    const double total_s = total.elapsedSeconds();
    reportStats(report, result.stats, export_s, total_s);
    const TextureStats& s = result.stats;
    std::ostringstream msg;
    msg << "texture.mrf: " << s.faces << " faces, " << s.views << " views, " << s.patches
        << " patches in " << s.pages << " atlas page(s), " << s.faces_untextured << " untextured, "
        << total_s << " s";
    logInfo(msg.str());
}

}  // namespace vdbmap::texture
