// SPDX-License-Identifier: Apache-2.0
#include "SemanticMrfStage.h"

#include <filesystem>
#include <sstream>

#include "GeometricSmoothness.h"
#include "LabelGrid.h"
#include "LidarVotes.h"
#include "SemanticExport.h"
#include "SemanticFusion.h"
#include "SemanticVotes.h"
#include "VoteCombination.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/core/Progress.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/io/Image.h"
#include "vdbmap/io/LabelSet.h"
#include "vdbmap/io/LidarLabels.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/io/PointCloudIO.h"
#include "vdbmap/map/Layers.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/mesh/MeshAdjacency.h"
#include "vdbmap/mesh/MeshArrays.h"
#include "vdbmap/mesh/TileFaces.h"
#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/Report.h"
#include "vdbmap/pipeline/Tiling.h"
#include "vdbmap/render/VisibilitySetup.h"

namespace vdbmap::semantic {

namespace {

double perSecond(std::size_t n, double seconds) {
    return seconds > 0.0 ? static_cast<double>(n) / seconds : 0.0;
}

// Stage::fail for the phase functions below: "<stage>: <message>", exit code 1.
[[noreturn]] void failIn(const Stage& stage, const std::string& message) {
    throw Error(std::string(stage.name()) + ": " + message);
}

// A file option: as given if it exists, else relative to the dataset folder.
std::filesystem::path resolveFile(const std::string& file, const Dataset& dataset) {
    std::filesystem::path path(file);
    if (path.is_relative() && !std::filesystem::exists(path) &&
        std::filesystem::exists(dataset.root() / path)) {
        path = dataset.root() / path;
    }
    return path;
}

// The mesh as plain arrays (vertex positions, triangles by vertex index).
// The mesh as arrays (vdbmap::meshArrays, every face slot kept so triangle i is face i) plus
// the area of each triangle.
struct FaceArrays {
    std::vector<Vec3f> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<double> area_m2;
};

FaceArrays faceArrays(const TriMesh& mesh) {
    MeshArrays arrays = meshArrays(mesh, DeletedFaces::Collapse);
    FaceArrays a;
    a.vertices = std::move(arrays.vertices_W);
    a.triangles = std::move(arrays.faces);
    a.area_m2.reserve(a.triangles.size());
    for (const auto& t : a.triangles) {
        const Vec3f& p0 = a.vertices[t[0]];
        a.area_m2.push_back(
            0.5 * static_cast<double>((a.vertices[t[1]] - p0).cross(a.vertices[t[2]] - p0).norm()));
    }
    return a;
}

// World up: the mean z axis of the LiDAR poses (a vehicle's LiDAR is mounted level).
Vec3f worldUp(const Dataset& dataset) {
    Vec3d up = Vec3d::Zero();
    for (std::size_t i = 0; i < dataset.numFrames(); ++i) {
        up += dataset.frame(i).T_W_L.rotation().col(2);
    }
    return up.norm() > 0.0 ? Vec3f(up.normalized().cast<float>()) : Vec3f::UnitZ();
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
             visibility_.max_view_angle_deg, 80.0, "deg");
    spec.add("min_depth_m", "Nearest visible depth", visibility_.min_depth_m, 0.1, "m");
    spec.add("max_depth_m", "Farthest visible depth", visibility_.max_depth_m, 200.0, "m");
    spec.add("occlusion_test", "Test occlusion by the mesh itself (Embree BVH)",
             visibility_.occlusion_test, true);
    spec.add("occlusion_tolerance_m", "A hit closer than this to the face is no occluder",
             visibility_.occlusion_tolerance_m, 0.02, "m");
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
    spec.add("image_votes", "Votes from the semantic images (semantic_2/3, semantic_dir)",
             image_votes_, true);
    spec.add("lidar_labels",
             "Votes from per-point LiDAR labels (KITTI SEQ/labels, generic labels_dir)",
             lidar_labels_, false);
    spec.add("label_map",
             "LiDAR label ids -> label set: 'semantickitti' (built in, = "
             "config/label_maps/semantickitti.txt), a file of 'source target' lines, or '' "
             "(the ids are the label set's)",
             label_map_, std::string());
    spec.add("lidar_weight", "Weight w_L of the LiDAR distribution against the images' in E_D",
             lidar_weight_, 1.0);
    spec.add("lidar_vote_radius_m", "A labelled point votes for the faces closer than this",
             lidar_vote_radius_m_, 0.1, "m");
    spec.add("fill",
             "Fill of faces no source saw: 'geometric' (the Potts weight of an edge next to such "
             "a face falls across normal changes and height steps) or 'uniform' (the paper: "
             "all weights 1)",
             fill_, std::string("geometric"));
    spec.add("fill_normal_sigma_deg", "geometric fill: angle scale of the edge weight",
             fill_normal_sigma_deg_, 20.0, "deg");
    spec.add("fill_height_sigma_m", "geometric fill: height-step scale of the edge weight",
             fill_height_sigma_m_, 0.03, "m");
}

void SemanticMrfStage::initialize() {
    if (!(lambda_ >= 0.0)) failConfig("option 'lambda' must be >= 0, got " + std::to_string(lambda_));
    if (!(probability_floor_ > 0.0 && probability_floor_ < 1.0)) {
        failConfig("option 'probability_floor' must be in (0, 1), got " +
                   std::to_string(probability_floor_));
    }
    if (max_sweeps_ < 1) failConfig("option 'max_sweeps' must be >= 1, got " + std::to_string(max_sweeps_));
    try {
        checkVisibilityOptions(visibility_);
    } catch (const InvalidInput& e) {
        failConfig(e.what());
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
    if (!image_votes_ && !lidar_labels_) {
        failConfig("options 'image_votes' and 'lidar_labels' are both false: no source to label from");
    }
    if (!(lidar_weight_ >= 0.0)) {
        failConfig("option 'lidar_weight' must be >= 0, got " + std::to_string(lidar_weight_));
    }
    if (!(lidar_vote_radius_m_ > 0.0)) {
        failConfig("option 'lidar_vote_radius_m' must be > 0, got " +
                   std::to_string(lidar_vote_radius_m_));
    }
    if (fill_ != "geometric" && fill_ != "uniform") {
        failConfig("option 'fill' must be 'geometric' or 'uniform', got '" + fill_ + "'");
    }
    if (!(fill_normal_sigma_deg_ > 0.0) || !(fill_height_sigma_m_ > 0.0)) {
        failConfig("options 'fill_normal_sigma_deg' and 'fill_height_sigma_m' must be > 0, got " +
                   std::to_string(fill_normal_sigma_deg_) + " and " +
                   std::to_string(fill_height_sigma_m_));
    }
}

void SemanticMrfStage::declareLayers(LayerSpec& spec) const {
    spec.reads(layers::kMesh);
    if (image_votes_) spec.reads(layers::kSemanticImages);
    if (lidar_labels_) spec.reads(layers::kScans);  // with their labels, from the dataset
    spec.writes(layers::kFaceLabels);
}

namespace {

// What the image phase produced.
struct ImageVotes {
    FaceVotes votes;
    std::size_t views = 0;
    std::size_t observations = 0;
    double visibility_s = 0, votes_s = 0;
};

// What the LiDAR phase produced.
struct LidarVoteResult {
    FaceVotes votes;
    std::size_t scans = 0;
    std::size_t scans_without_labels = 0;
    std::size_t points = 0;
    std::size_t points_dropped = 0;     // non-finite or outside the range limits
    std::size_t points_void = 0;        // mapped to 255
    std::size_t points_unknown_id = 0;  // mapped to an id outside the label set
    std::size_t points_without_face = 0;
    double seconds = 0;
};

}  // namespace

// Phase: label set (the stage option, else the dataset's, else DATA.md's default).
static LabelSet loadLabelSet(const SemanticMrfStage& stage, const std::string& option,
                             const Dataset& dataset, const std::vector<int>& export_classes) {
    const std::string file = option.empty() ? dataset.config().labels_file : option;
    LabelSet labels = LabelSet::defaults();
    if (!file.empty()) labels = LabelSet::fromFile(resolveFile(file, dataset));
    if (labels.size() == 0) failIn(stage, "the label set '" + file + "' has no classes");
    for (const int id : export_classes) {
        if (labels.indexOf(static_cast<std::uint8_t>(id)) < 0) {
            failIn(stage, "option 'export_classes' holds " + std::to_string(id) +
                       ", which is not in the label set");
        }
    }
    return labels;
}

// Phase: image votes (visibility shared with the texture plugin, then centre-pixel votes).
static ImageVotes imageVotes(const SemanticMrfStage& stage, Context& ctx,
                             const VisibilityOptions& vis_options, const LabelSet& labels,
                             int image_chunk) {
    const Dataset& dataset = ctx.dataset();
    const std::string name(stage.name());
    ImageVotes out;
    // The views of the tile in a tiled run (Context::views), else every view.
    const std::vector<View> views = ctx.views(false, true);
    if (views.empty() && ctx.hasTile()) {
        logInfo(name + ": no view sees tile " + ctx.tile().name() + ": no image votes");
        return out;
    }
    if (views.empty()) {
        failIn(stage, 
            "the dataset has no semantic images (KITTI semantic_2 / semantic_3, or a camera's "
            "semantic_dir in the generic layout); set image_votes: false for LiDAR labels only");
    }
    const std::size_t expected_views = dataset.numFrames() * dataset.cameras().size();
    if (!ctx.hasTile() && views.size() < expected_views) {
        logWarn(name + ": " + std::to_string(expected_views - views.size()) + " of " +
                std::to_string(expected_views) +
                " frame x camera pairs have no semantic image and are skipped");
    }
    Timer step;
    Visibility visibility =
        meshVisibility(ctx.mesh(), views, vis_options, name + " visibility", ctx.quiet(),
                       &ctx.occluderMesh());
    out.visibility_s = step.elapsedSeconds();

    step.reset();
    auto load = [&](std::size_t v) {
        const auto path = dataset.semanticPath(views[v].frame, views[v].camera);
        if (!path) failIn(stage, "semantic image of frame " + std::to_string(views[v].frame) + " vanished");
        cv::Mat image = readLabelImage(*path);
        if (image.cols != views[v].intrinsics.width || image.rows != views[v].intrinsics.height) {
            failIn(stage, "semantic image " + path->string() + " is " + std::to_string(image.cols) +
                       "x" + std::to_string(image.rows) + " but the camera is " +
                       std::to_string(views[v].intrinsics.width) + "x" +
                       std::to_string(views[v].intrinsics.height));
        }
        return image;
    };
    out.votes = accumulateVotes(visibility, views.size(), load, labels,
                                static_cast<std::size_t>(image_chunk));
    out.views = views.size();
    out.observations = visibility.obs.size();
    out.votes_s = step.elapsedSeconds();
    return out;
}

// Phase: LiDAR votes. Each labelled scan is read as stored (the labels are per stored point),
// checked against its label file, filtered as Dataset::loadScan filters, moved into the world
// and splatted onto the faces within the vote radius.
static LidarVoteResult lidarVotes(const SemanticMrfStage& stage, Context& ctx,
                                  const FaceArrays& faces, const LabelSet& labels,
                                  const std::string& label_map_option, double radius_m) {
    const Dataset& dataset = ctx.dataset();
    const std::string name(stage.name());
    Timer timer;
    // No label_map: the ids are the label set's own (and 255); any other id is an error.
    std::string own_ids = "255 255\n";
    for (const LabelClass& c : labels.classes()) {
        own_ids += std::to_string(c.id) + " " + std::to_string(c.id) + "\n";
    }
    LabelMap map = LabelMap::parse(own_ids, "(none: the ids of the label set; set label_map)");
    if (label_map_option == "semantickitti") {
        map = LabelMap::semanticKitti();
    } else if (!label_map_option.empty()) {
        map = LabelMap::fromFile(resolveFile(label_map_option, dataset));
    }
    if (dataset.lidarLabelDir().empty()) {
        failIn(stage, "option 'lidar_labels' is on but the dataset has no LiDAR labels (KITTI: "
                   "SEQ/labels/NNNNNN.label; generic: the dataset key 'labels_dir')");
    }
    LidarVoteAccumulator accumulator(faces.vertices, faces.triangles, labels.size(),
                                     static_cast<float>(radius_m));
    LidarVoteResult out;
    const double min2 = dataset.config().min_range_m * dataset.config().min_range_m;
    const double max2 = dataset.config().max_range_m * dataset.config().max_range_m;
    Progress progress(name + " LiDAR votes", dataset.numFrames(), ctx.quiet());
    for (std::size_t i = 0; i < dataset.numFrames(); ++i) {
        progress.tick();
        const FrameInfo& frame = dataset.frame(i);
        const auto label_path = dataset.lidarLabelPath(i);
        if (!label_path) {
            ++out.scans_without_labels;
            continue;
        }
        const PointCloud cloud = readPointCloud(frame.scan_path);
        const LidarLabels raw = readLidarLabels(*label_path);
        checkLabelCount(raw.size(), *label_path, cloud.size(), frame.scan_path);
        const std::vector<std::uint8_t> ids = mapLidarLabels(raw, *label_path, map);
        std::vector<Vec3f> points_W;
        std::vector<std::uint32_t> classes;
        points_W.reserve(cloud.size());
        classes.reserve(cloud.size());
        const Eigen::Matrix3f R = frame.T_W_L.rotation().cast<float>();
        const Vec3f t = frame.T_W_L.translation().cast<float>();
        for (std::size_t k = 0; k < cloud.size(); ++k) {
            const Vec3f& p = cloud.points[k];
            const double r2 = p.cast<double>().squaredNorm();
            if (!p.allFinite() || r2 < min2 || r2 > max2) {
                ++out.points_dropped;
                continue;
            }
            std::uint32_t cls = LidarVoteAccumulator::kNoClass;
            if (ids[k] != kUnknownLabel) {
                const int index = labels.indexOf(ids[k]);
                if (index >= 0) {
                    cls = static_cast<std::uint32_t>(index);
                } else {
                    ++out.points_unknown_id;
                }
            }
            points_W.push_back(R * p + t);
            classes.push_back(cls);
        }
        accumulator.add(points_W, classes);
        out.points += cloud.size();
        ++out.scans;
    }
    progress.finish();
    if (out.scans == 0) {
        failIn(stage, "option 'lidar_labels' is on but no selected frame has a label file in " +
                   dataset.lidarLabelDir().string());
    }
    if (out.scans_without_labels > 0) {
        logWarn(name + ": " + std::to_string(out.scans_without_labels) + " of " +
                std::to_string(dataset.numFrames()) + " scans have no label file in " +
                dataset.lidarLabelDir().string() + " and do not vote");
    }
    out.votes = accumulator.finish();
    out.points_void = out.votes.void_votes - out.points_unknown_id;
    out.points_without_face = accumulator.pointsWithoutFace();
    out.seconds = timer.elapsedSeconds();
    return out;
}

void SemanticMrfStage::run(Context& ctx) {
    TriMesh& mesh = ctx.mesh();
    const Dataset& dataset = ctx.dataset();
    const std::string stage(name());
    Report& report = ctx.report();
    Timer total;
    if (mesh.n_faces() == 0) fail("the mesh has no faces: nothing to label");
    const LabelSet labels = loadLabelSet(*this, labels_file_, dataset, export_classes_);
    const FaceArrays faces = faceArrays(mesh);

    // 1. Sources: image votes and LiDAR votes, combined into one distribution per face.
    ImageVotes images;
    if (image_votes_) images = imageVotes(*this, ctx, visibility_, labels, image_chunk_);
    LidarVoteResult lidar;
    if (lidar_labels_) {
        lidar = lidarVotes(*this, ctx, faces, labels, label_map_, lidar_vote_radius_m_);
    }
    std::vector<std::uint8_t> sources;
    const FaceVotes votes = combineVotes(images.votes, lidar.votes, lidar_weight_, &sources);
    images.votes = FaceVotes();
    lidar.votes = FaceVotes();
    if (votes.numFaces() == 0 && ctx.hasTile()) {
        // A tile that no view sees and no labelled point reaches: nothing to label here.
        logInfo(stage + ": no source sees tile " + ctx.tile().name() + ": not labelled");
        report.stage(stage, "skipped", std::string("no view or labelled point sees the tile"));
        return;
    }

    // 2. MRF fusion with the geometry-aware (or the paper's uniform) smoothness.
    Timer step;
    FusionOptions fusion;
    fusion.lambda = lambda_;
    fusion.probability_floor = probability_floor_;
    fusion.all_classes = all_classes_;
    fusion.max_sweeps = max_sweeps_;
    const auto adjacency = faceAdjacency(mesh);
    std::vector<float> edge_weights;
    if (fill_ == "geometric") {
        GeometricSmoothnessOptions geo;
        geo.normal_sigma_deg = fill_normal_sigma_deg_;
        geo.height_sigma_m = fill_height_sigma_m_;
        edge_weights = geometricEdgeWeights(faces.vertices, faces.triangles, adjacency,
                                            worldUp(dataset), geo);
        // The fill only: between two observed faces the paper's uniform Potts term stays.
        uniformBetweenObserved(edge_weights, adjacency, votes);
        fusion.edge_weights = &edge_weights;
    }
    const FusionResult result = fuseLabels(votes, adjacency, labels, fusion);
    const double t_mrf = step.elapsedSeconds();
    setFaceLabelProperty(mesh, result.face_labels);

    // 3. Exports (a tile writes its core faces only; the halo took part in the MRF).
    step.reset();
    const std::filesystem::path dir = ctx.outputDir() / output_subdir_;
    std::filesystem::create_directories(dir);
    {
        std::vector<std::uint32_t> core_faces;
        const TriMesh core = ctx.hasTile() ? coreSubmesh(mesh, &core_faces) : TriMesh();
        const TriMesh& out_mesh = ctx.hasTile() ? core : mesh;
        std::vector<std::uint8_t> out_labels;
        std::vector<float> out_confidence;
        if (ctx.hasTile()) {
            for (const std::uint32_t f : core_faces) {
                out_labels.push_back(result.face_labels[f]);
                out_confidence.push_back(result.confidence[f]);
            }
        }
        const std::vector<std::uint8_t>& written = ctx.hasTile() ? out_labels : result.face_labels;
        const std::vector<float>& confidence = ctx.hasTile() ? out_confidence : result.confidence;
        writeSemanticPly(dir / "mesh.ply", out_mesh, written, labels, &confidence);
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
        ctx.map().setExtraGrid(grids::kLabel, labelGrid(mesh, result.face_labels, *map.transform(),
                                                  static_cast<float>(label_grid_band_vox_)));
    }
    const double t_export = step.elapsedSeconds();

    // 4. Report: counts, sources, energies, timings, and area / faces per class.
    const std::size_t num_faces = mesh.n_faces();
    report.stage(stage, "faces", num_faces);
    report.stage(stage, "views", images.views);
    report.stage(stage, "observations", images.observations);
    report.stage(stage, "votes", votes.votes);
    report.stage(stage, "void_votes", votes.void_votes);
    report.stage(stage, "unknown_id_votes", votes.unknown_id_votes);
    if (lidar_labels_) {
        report.stage(stage, "lidar_scans", lidar.scans);
        report.stage(stage, "lidar_scans_without_labels", lidar.scans_without_labels);
        report.stage(stage, "lidar_points", lidar.points);
        report.stage(stage, "lidar_points_dropped", lidar.points_dropped);
        report.stage(stage, "lidar_points_void", lidar.points_void);
        report.stage(stage, "lidar_points_unknown_id", lidar.points_unknown_id);
        report.stage(stage, "lidar_points_without_face", lidar.points_without_face);
        report.stage(stage, "label_map", label_map_.empty() ? std::string("identity") : label_map_);
    }
    report.stage(stage, "observed_faces", result.observed_faces);
    report.stage(stage, "filled_faces", result.filled_faces);
    report.stage(stage, "unlabelled_faces", result.unlabelled_faces);
    report.stage(stage, "unlabelled_components", result.unlabelled_components);
    report.stage(stage, "fill", fill_);
    report.stage(stage, "energy_initial", result.initial_energy);
    report.stage(stage, "energy_final", result.final_energy);
    report.stage(stage, "mrf_sweeps", result.sweeps);
    report.stage(stage, "time_visibility_s", images.visibility_s);
    report.stage(stage, "time_votes_s", images.votes_s);
    report.stage(stage, "time_lidar_votes_s", lidar.seconds);
    report.stage(stage, "time_mrf_s", t_mrf);
    report.stage(stage, "time_export_s", t_export);
    report.stage(stage, "faces_per_s_visibility", perSecond(num_faces, images.visibility_s));
    report.stage(stage, "faces_per_s_votes", perSecond(num_faces, images.votes_s));
    report.stage(stage, "faces_per_s_mrf", perSecond(num_faces, t_mrf));
    report.stage(stage, "faces_per_s_total", perSecond(num_faces, total.elapsedSeconds()));

    // Share of faces (and of area) by the sources that labelled them.
    std::array<std::size_t, 5> n{};  // images only, LiDAR only, both, fill only, unlabelled
    std::array<double, 5> area{};
    double confidence_sum = 0, total_area = 0;
    for (std::size_t f = 0; f < num_faces; ++f) {
        const int k = result.face_labels[f] == kUnknownLabel ? 4
                      : sources[f] == (kSourceImages | kSourceLidar) ? 2
                      : sources[f] == kSourceImages                  ? 0
                      : sources[f] == kSourceLidar                   ? 1
                                                                     : 3;
        ++n[k];
        area[k] += faces.area_m2[f];
        total_area += faces.area_m2[f];
        confidence_sum += result.confidence[f] * faces.area_m2[f];
    }
    const char* keys[5] = {"images", "lidar", "both", "fill_only", "unlabelled"};
    for (int k = 0; k < 5; ++k) {
        const std::vector<std::string> at{"stages", stage, "sources", keys[k]};
        auto key = [&](const char* leaf) {
            std::vector<std::string> path = at;
            path.emplace_back(leaf);
            return path;
        };
        report.set(key("faces"), n[k]);
        report.set(key("face_share"), num_faces ? double(n[k]) / double(num_faces) : 0.0);
        report.set(key("area_m2"), area[k]);
        report.set(key("area_share"), total_area > 0 ? area[k] / total_area : 0.0);
    }
    report.stage(stage, "mean_confidence_area_weighted",
                 total_area > 0 ? confidence_sum / total_area : 0.0);
    for (const auto& [id, c] : classStatistics(mesh, result.face_labels)) {
        const std::string cls = std::to_string(static_cast<int>(id));
        report.set({"stages", stage, "classes", cls, "name"},
                   id == kUnknownLabel ? std::string("unknown") : labels.name(id));
        report.set({"stages", stage, "classes", cls, "faces"}, c.faces);
        report.set({"stages", stage, "classes", cls, "area_m2"}, c.area_m2);
    }

    std::ostringstream msg;
    msg << stage << ": " << num_faces << " faces, " << images.views << " views, "
        << lidar.scans << " labelled scans; faces by images " << n[0] << ", LiDAR " << n[1]
        << ", both " << n[2] << ", fill " << n[3] << ", unlabelled " << n[4] << "; energy "
        << result.initial_energy << " -> " << result.final_energy << "; "
        << total.elapsedSeconds() << " s";
    logInfo(msg.str());
}

}  // namespace vdbmap::semantic
