// SPDX-License-Identifier: Apache-2.0
#include "SemanticMrfStage.h"

#include <filesystem>
#include <sstream>

#include "LabelGrid.h"
#include "SemanticExport.h"
#include "SemanticFusion.h"
#include "SemanticVotes.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/core/Progress.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/io/Image.h"
#include "vdbmap/io/LabelSet.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/map/Layers.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/mesh/MeshAdjacency.h"
#include "vdbmap/mesh/TileFaces.h"
#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/Report.h"
#include "vdbmap/pipeline/Tiling.h"
#include "vdbmap/render/Raycaster.h"
#include "vdbmap/render/Visibility.h"

namespace vdbmap::semantic {

namespace {

std::string jsonEscape(const std::string& s) {
    std::string out;
    for (const char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out;
}

double perSecond(std::size_t n, double seconds) {
    return seconds > 0.0 ? static_cast<double>(n) / seconds : 0.0;
}

}  // namespace

void SemanticMrfStage::declareOptions(OptionSpec& spec) {
    spec.add("lambda", "Weight of the Potts smoothness between adjacent faces; 0 = naive voting",
             lambda_, 0.5);
    spec.add("probability_floor", "Data cost is -log(max(p, floor)) of the normalised votes",
             probability_floor_, 1e-3);
    spec.add("all_classes",
             "Observed faces may take unvoted classes (at the floor cost), not only voted ones",
             all_classes_, false);
    spec.add("max_sweeps", "Alpha-expansion sweeps over all classes at most", max_sweeps_, 5);
    spec.add("max_view_angle_deg", "Reject views seeing a face flatter than this",
             max_view_angle_deg_, 80.0, "deg");
    spec.add("min_depth_m", "Nearest visible depth", min_depth_m_, 0.1, "m");
    spec.add("max_depth_m", "Farthest visible depth", max_depth_m_, 200.0, "m");
    spec.add("occlusion_test", "Test occlusion by the mesh itself (Embree BVH)", occlusion_test_,
             true);
    spec.add("occlusion_tolerance_m", "A hit closer than this to the face is no occluder",
             occlusion_tolerance_m_, 0.02, "m");
    spec.add("labels_file",
             "Label set file 'id, name, r g b' (overrides the dataset's; '' = dataset's or the "
             "DATA.md default)",
             labels_file_, std::string());
    spec.add("export_classes", "Class ids also written as their own mesh (class_<id>_<name>.ply)",
             export_classes_, std::vector<int>{});
    spec.add("label_grid",
             "Write a float grid 'label' into map.vdb: class of the nearest face per voxel",
             label_grid_, false);
    spec.add("label_grid_band_vox", "Half width of the label grid around the mesh",
             label_grid_band_vox_, 2.0, "voxels");
    spec.add("output_subdir", "Folder below the output folder for mesh.ply / mesh.obj",
             output_subdir_, std::string("semantic"));
    spec.add("write_obj", "Also write mesh.obj + mesh.mtl with one material per class",
             write_obj_, true);
    spec.add("image_chunk", "Semantic images held in memory at once", image_chunk_, 64);
}

void SemanticMrfStage::initialize() {
    if (!(lambda_ >= 0.0)) failConfig("option 'lambda' must be >= 0, got " + std::to_string(lambda_));
    if (!(probability_floor_ > 0.0 && probability_floor_ < 1.0)) {
        failConfig("option 'probability_floor' must be in (0, 1), got " +
                   std::to_string(probability_floor_));
    }
    if (max_sweeps_ < 1) failConfig("option 'max_sweeps' must be >= 1, got " + std::to_string(max_sweeps_));
    if (!(max_view_angle_deg_ > 0.0 && max_view_angle_deg_ <= 90.0)) {
        failConfig("option 'max_view_angle_deg' must be in (0, 90], got " +
                   std::to_string(max_view_angle_deg_));
    }
    if (!(min_depth_m_ >= 0.0 && max_depth_m_ > min_depth_m_)) {
        failConfig("options 'min_depth_m' and 'max_depth_m' must satisfy 0 <= min < max, got " +
                   std::to_string(min_depth_m_) + " and " + std::to_string(max_depth_m_));
    }
    if (!(occlusion_tolerance_m_ >= 0.0)) {
        failConfig("option 'occlusion_tolerance_m' must be >= 0, got " +
                   std::to_string(occlusion_tolerance_m_));
    }
    for (const int id : export_classes_) {
        if (id < 0 || id > 254) {
            failConfig("option 'export_classes' holds " + std::to_string(id) +
                       "; class ids are 0..254");
        }
    }
    if (!(label_grid_band_vox_ >= 1.0)) {
        failConfig("option 'label_grid_band_vox' must be >= 1, got " +
                   std::to_string(label_grid_band_vox_));
    }
    if (output_subdir_.empty()) failConfig("option 'output_subdir' must not be empty");
    if (image_chunk_ < 1) failConfig("option 'image_chunk' must be >= 1, got " + std::to_string(image_chunk_));
}

void SemanticMrfStage::declareLayers(LayerSpec& spec) const {
    spec.reads(layers::kMesh);
    spec.reads(layers::kSemanticImages);
    spec.writes(layers::kFaceLabels);
}

void SemanticMrfStage::run(Context& ctx) {
    TriMesh& mesh = ctx.mesh();
    const Dataset& dataset = ctx.dataset();
    const std::string stage(name());
    Report& report = ctx.report();
    Timer total;
    if (mesh.n_faces() == 0) fail("the mesh has no faces: nothing to label");

    // Label set: the stage option, else the dataset's, else DATA.md's default.
    std::string file = labels_file_.empty() ? dataset.config().labels_file : labels_file_;
    LabelSet labels = LabelSet::defaults();
    if (!file.empty()) {
        std::filesystem::path path(file);
        if (path.is_relative() && !std::filesystem::exists(path) &&
            std::filesystem::exists(dataset.root() / path)) {
            path = dataset.root() / path;
        }
        labels = LabelSet::fromFile(path);
    }
    if (labels.size() == 0) fail("the label set '" + file + "' has no classes");
    for (const int id : export_classes_) {
        if (labels.indexOf(static_cast<std::uint8_t>(id)) < 0) {
            fail("option 'export_classes' holds " + std::to_string(id) +
                 ", which is not in the label set");
        }
    }

    // The views of the tile in a tiled run (Context::views), else every view.
    const std::vector<View> views = ctx.views(false, true);
    if (views.empty() && ctx.hasTile()) {
        logInfo(stage + ": no view sees tile " + ctx.tile().name() + ": not labelled");
        report.stage(stage, "skipped", std::string("no view sees the tile"));
        return;
    }
    if (views.empty()) {
        fail(
            "the dataset has no semantic images (KITTI semantic_2 / semantic_3, or a camera's "
            "semantic_dir in the generic layout)");
    }
    const std::size_t expected_views = dataset.numFrames() * dataset.cameras().size();
    if (!ctx.hasTile() && views.size() < expected_views) {
        logWarn(stage + ": " + std::to_string(expected_views - views.size()) + " of " +
                std::to_string(expected_views) +
                " frame x camera pairs have no semantic image and are skipped");
    }

    // 1. Visibility (shared with the texture plugin).
    Timer step;
    VisibilityOptions vis_options;
    vis_options.max_view_angle_deg = max_view_angle_deg_;
    vis_options.min_depth_m = min_depth_m_;
    vis_options.max_depth_m = max_depth_m_;
    vis_options.occlusion_test = occlusion_test_;
    vis_options.occlusion_tolerance_m = occlusion_tolerance_m_;
    Visibility visibility;
    {
        const Raycaster raycaster = Raycaster::fromMesh(ctx.occluderMesh());
        Progress progress(stage + " visibility", views.size(), ctx.quiet());
        visibility = computeVisibility(mesh, views, vis_options,
                                       occlusion_test_ ? &raycaster : nullptr, &progress);
    }
    const double t_visibility = step.elapsedSeconds();

    // 2. Votes: centre pixel, weighted by projected area.
    step.reset();
    auto load = [&](std::size_t v) {
        const auto path = dataset.semanticPath(views[v].frame, views[v].camera);
        if (!path) fail("semantic image of frame " + std::to_string(views[v].frame) + " vanished");
        cv::Mat image = readLabelImage(*path);
        if (image.cols != views[v].intrinsics.width || image.rows != views[v].intrinsics.height) {
            fail("semantic image " + path->string() + " is " + std::to_string(image.cols) + "x" +
                 std::to_string(image.rows) + " but the camera is " +
                 std::to_string(views[v].intrinsics.width) + "x" +
                 std::to_string(views[v].intrinsics.height));
        }
        return image;
    };
    const FaceVotes votes = accumulateVotes(visibility, views.size(), load, labels,
                                            static_cast<std::size_t>(image_chunk_));
    const std::size_t num_observations = visibility.obs.size();
    Visibility().offsets.swap(visibility.offsets);
    std::vector<FaceObservation>().swap(visibility.obs);
    const double t_votes = step.elapsedSeconds();

    // 3. MRF fusion.
    step.reset();
    FusionOptions fusion;
    fusion.lambda = lambda_;
    fusion.probability_floor = probability_floor_;
    fusion.all_classes = all_classes_;
    fusion.max_sweeps = max_sweeps_;
    const auto adjacency = faceAdjacency(mesh);
    const FusionResult result = fuseLabels(votes, adjacency, labels, fusion);
    const double t_mrf = step.elapsedSeconds();
    setFaceLabelProperty(mesh, result.face_labels);

    // 4. Exports (a tile writes its core faces only; the halo took part in the MRF).
    step.reset();
    const std::filesystem::path dir = ctx.outputDir() / output_subdir_;
    std::filesystem::create_directories(dir);
    {
        std::vector<std::uint32_t> core_faces;
        const TriMesh core = ctx.hasTile() ? coreSubmesh(mesh, &core_faces) : TriMesh();
        const TriMesh& out_mesh = ctx.hasTile() ? core : mesh;
        std::vector<std::uint8_t> out_labels;
        if (ctx.hasTile()) {
            for (const std::uint32_t f : core_faces) out_labels.push_back(result.face_labels[f]);
        }
        const std::vector<std::uint8_t>& written = ctx.hasTile() ? out_labels : result.face_labels;
        writeSemanticPly(dir / "mesh.ply", out_mesh, written, labels);
        if (write_obj_) writeSemanticObj(dir / "mesh.obj", out_mesh, written, labels);
        for (const int id : export_classes_) {
            const auto cls = static_cast<std::uint8_t>(id);
            const TriMesh part = extractClassMesh(out_mesh, written, cls);
            writeMeshPly(dir / classMeshFileName(cls, labels), part);
        }
    }
    if (label_grid_) {
        if (!ctx.hasMap()) fail("option 'label_grid' needs a map (an integrate stage before)");
        if (ctx.hasTile()) {
            fail("option 'label_grid' is not available in tiled runs yet (map.vdb is one file; "
                 "the tiles would overwrite each other's grid)");
        }
        VoxelMap& map = ctx.map();
        ctx.map().setExtraGrid("label", labelGrid(mesh, result.face_labels, *map.transform(),
                                                  static_cast<float>(label_grid_band_vox_)));
    }
    const double t_export = step.elapsedSeconds();

    // Report: counts, energies, timings, and area / faces per class.
    const std::size_t num_faces = mesh.n_faces();
    report.stage(stage, "faces", num_faces);
    report.stage(stage, "views", views.size());
    report.stage(stage, "observations", num_observations);
    report.stage(stage, "votes", votes.votes);
    report.stage(stage, "void_votes", votes.void_votes);
    report.stage(stage, "unknown_id_votes", votes.unknown_id_votes);
    report.stage(stage, "observed_faces", result.observed_faces);
    report.stage(stage, "filled_faces", result.filled_faces);
    report.stage(stage, "unlabelled_faces", result.unlabelled_faces);
    report.stage(stage, "unlabelled_components", result.unlabelled_components);
    report.stage(stage, "energy_initial", result.initial_energy);
    report.stage(stage, "energy_final", result.final_energy);
    report.stage(stage, "mrf_sweeps", result.sweeps);
    report.stage(stage, "time_visibility_s", t_visibility);
    report.stage(stage, "time_votes_s", t_votes);
    report.stage(stage, "time_mrf_s", t_mrf);
    report.stage(stage, "time_export_s", t_export);
    report.stage(stage, "faces_per_s_visibility", perSecond(num_faces, t_visibility));
    report.stage(stage, "faces_per_s_votes", perSecond(num_faces, t_votes));
    report.stage(stage, "faces_per_s_mrf", perSecond(num_faces, t_mrf));
    report.stage(stage, "faces_per_s_total", perSecond(num_faces, total.elapsedSeconds()));
    std::ostringstream classes;
    classes << "{";
    bool first = true;
    for (const auto& [id, s] : classStatistics(mesh, result.face_labels)) {
        classes << (first ? "" : ",") << "\"" << static_cast<int>(id) << "\":{\"name\":\""
                << jsonEscape(id == kUnknownLabel ? std::string("unknown") : labels.name(id))
                << "\",\"faces\":" << s.faces << ",\"area_m2\":" << s.area_m2 << "}";
        first = false;
    }
    classes << "}";
    report.setJson({"stages", stage, "classes"}, classes.str());

    std::ostringstream msg;
    msg << stage << ": " << num_faces << " faces, " << views.size() << " views, "
        << result.observed_faces << " observed, " << result.filled_faces << " filled, "
        << result.unlabelled_faces << " unlabelled; energy " << result.initial_energy << " -> "
        << result.final_energy << "; " << total.elapsedSeconds() << " s";
    logInfo(msg.str());
}

}  // namespace vdbmap::semantic
