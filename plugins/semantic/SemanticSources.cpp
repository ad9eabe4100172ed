// SPDX-License-Identifier: Apache-2.0
#include "SemanticSources.h"

#include <optional>

#include "LidarVotes.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/core/Progress.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/io/Image.h"
#include "vdbmap/io/LidarLabels.h"
#include "vdbmap/io/PointCloudIO.h"
#include "vdbmap/map/Layers.h"
#include "vdbmap/mesh/MeshArrays.h"
#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/StageVisibility.h"
#include "vdbmap/pipeline/Tiling.h"
#include "vdbmap/dynamic/MovingReturns.h"
#include "vdbmap/render/ImageMasks.h"
#include "vdbmap/render/ScanOcclusion.h"
#include "vdbmap/render/VisibilitySetup.h"

namespace vdbmap::semantic {

void failIn(const std::string& stage, const std::string& message) {
    throw Error(stage + ": " + message);
}

std::filesystem::path resolveFile(const std::string& file, const Dataset& dataset) {
    std::filesystem::path path(file);
    if (path.is_relative() && !std::filesystem::exists(path) &&
        std::filesystem::exists(dataset.root() / path)) {
        path = dataset.root() / path;
    }
    return path;
}

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

LabelSet loadLabelSet(const std::string& stage, const std::string& labels_file,
                      const Dataset& dataset, const std::vector<int>& export_classes) {
    const std::string file = labels_file.empty() ? dataset.config().labels_file : labels_file;
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

// ---------------------------------------------------------------------------------------------
// Image votes

namespace {

// The semantic image of view v, checked against its camera's size.
cv::Mat loadViewLabels(const std::string& stage, const Dataset& dataset, const View& view) {
    const auto path = dataset.semanticPath(view.frame, view.camera);
    if (!path) failIn(stage, "semantic image of frame " + std::to_string(view.frame) + " vanished");
    cv::Mat image = readLabelImage(*path);
    if (image.cols != view.intrinsics.width || image.rows != view.intrinsics.height) {
        failIn(stage, "semantic image " + path->string() + " is " + std::to_string(image.cols) +
                          "x" + std::to_string(image.rows) + " but the camera is " +
                          std::to_string(view.intrinsics.width) + "x" +
                          std::to_string(view.intrinsics.height));
    }
    return image;
}

}  // namespace

ImageVotes imageVotes(const std::string& stage, Context& ctx, const VisibilityOptions& options,
                      const LabelSet& labels, int image_chunk, const ScanOcclusionOptions* scan,
                      const std::string& image_masks, int masks_dilate_px) {
    const Dataset& dataset = ctx.dataset();
    ImageVotes out;
    // The views of the tile in a tiled run (Context::views), else every view.
    const std::vector<View> views = ctx.views(false, true);
    if (views.empty() && ctx.hasTile()) {
        logInfo(stage + ": no view sees tile " + ctx.tile().name() + ": no image votes");
        return out;
    }
    if (views.empty()) {
        failIn(stage,
               "the dataset has no semantic images (KITTI semantic_2 / semantic_3, or a camera's "
               "semantic_dir in the generic layout); set image_votes: false for LiDAR labels only");
    }
    const std::size_t expected_views = dataset.numFrames() * dataset.cameras().size();
    if (!ctx.hasTile() && views.size() < expected_views) {
        logWarn(stage + ": " + std::to_string(expected_views - views.size()) + " of " +
                std::to_string(expected_views) +
                " frame x camera pairs have no semantic image and are skipped");
    }
    Timer step;
    // texture.mrf before or after this stage sees the same faces from the same views: the
    // visibility one computed serves the other (stageVisibility, Context::keepVisibility).
    const MeshArrays mesh = meshArrays(ctx.mesh(), DeletedFaces::Collapse);
    StageVisibility seen = stageVisibility(ctx, mesh, views, options, scan, stage);
    SharedVisibility& shared = seen.shared;
    out.visibility_reused = seen.reused;
    out.scan_hidden = shared.scan_hidden_cos.size();
    if (!image_masks.empty()) {
        // Pixels the user marked (e.g. a 2D detector's moving objects) vote for no face.
        out.masked = removeMaskedObservations(shared.visibility, views,
                                              directoryViewMasks(dataset, views, image_masks),
                                              masks_dilate_px);
    }
    const Visibility& visibility = shared.visibility;
    out.visibility_s = step.elapsedSeconds();

    step.reset();
    auto load = [&](std::size_t v) { return loadViewLabels(stage, dataset, views[v]); };
    out.votes = accumulateVotes(visibility, views.size(), load, labels,
                                static_cast<std::size_t>(image_chunk));
    out.views = views.size();
    out.observations = visibility.obs.size();
    out.votes_s = step.elapsedSeconds();
    // texture.mrf after this stage may see the same faces from the same views (not after the
    // masks changed them).
    if (image_masks.empty()) ctx.keepVisibility(seen.key, std::move(shared));
    return out;
}

// ---------------------------------------------------------------------------------------------
// LiDAR votes

namespace {

// The LiDAR label ids -> label set map of the option `label_map`: "semantickitti", a file, or
// "" (the ids are the label set's own, and 255; any other id is an error).
LabelMap lidarLabelMap(const std::string& option, const LabelSet& labels, const Dataset& dataset) {
    if (option == "semantickitti") return LabelMap::semanticKitti();
    if (!option.empty()) return LabelMap::fromFile(resolveFile(option, dataset));
    std::string own_ids = "255 255\n";
    for (const LabelClass& c : labels.classes()) {
        own_ids += std::to_string(c.id) + " " + std::to_string(c.id) + "\n";
    }
    return LabelMap::parse(own_ids, "(none: the ids of the label set; set label_map)");
}

// Squared distance from p to the box (0 inside).
double squaredDistance(const Box3d& box, const Vec3d& p) {
    const Vec3d d = (box.min_W - p).cwiseMax(p - box.max_W).cwiseMax(0.0);
    return d.squaredNorm();
}

// Where labelled points can vote: everywhere untiled; in a tile, its halo box grown by the
// vote radius r (no point outside reaches one of the tile's faces), then out to whole merge
// cells of LidarVoteAccumulator (r / 2, from the origin), so that every cell the tile keeps
// holds the same points, and merges to the same mean, as in an untiled run.
std::optional<Box3d> voteBox(const Context& ctx, double radius_m) {
    if (!ctx.hasTile()) return std::nullopt;
    const double cell_m = 0.5 * radius_m;
    Box3d box = ctx.tile().halo_W;
    box.min_W = ((box.min_W.array() - radius_m) / cell_m).floor() * cell_m;
    box.max_W = ((box.max_W.array() + radius_m) / cell_m).ceil() * cell_m;
    return box;
}

// The points of one labelled scan that vote, in W, with their class index (kNoClass = void).
struct LabelledPoints {
    std::vector<Vec3f> points_W;
    std::vector<std::uint32_t> classes;
};

LabelledPoints labelledPoints(const PointCloud& cloud, const std::vector<std::uint8_t>& ids,
                              const FrameInfo& frame, const DatasetConfig& config,
                              const LabelSet& labels, const std::optional<Box3d>& box,
                              LidarVoteResult& counts) {
    const double min2 = config.min_range_m * config.min_range_m;
    const double max2 = config.max_range_m * config.max_range_m;
    const Eigen::Matrix3f R = frame.T_W_L.rotation().cast<float>();
    const Vec3f t = frame.T_W_L.translation().cast<float>();
    LabelledPoints out;
    out.points_W.reserve(cloud.size());
    out.classes.reserve(cloud.size());
    for (std::size_t k = 0; k < cloud.size(); ++k) {
        const Vec3f& p = cloud.points[k];
        const double r2 = p.cast<double>().squaredNorm();
        if (!p.allFinite() || r2 < min2 || r2 > max2) {
            ++counts.points_dropped;
            continue;
        }
        const Vec3f p_W = R * p + t;
        if (box && squaredDistance(*box, p_W.cast<double>()) > 0.0) continue;
        std::uint32_t cls = LidarVoteAccumulator::kNoClass;
        if (ids[k] != kUnknownLabel) {
            const int index = labels.indexOf(ids[k]);
            if (index >= 0) {
                cls = static_cast<std::uint32_t>(index);
            } else {
                ++counts.points_unknown_id;
            }
        }
        out.points_W.push_back(p_W);
        out.classes.push_back(cls);
    }
    return out;
}

// Throws unless some frame of the dataset has a label file.
void requireSomeLabelFile(const std::string& stage, const Dataset& dataset) {
    if (dataset.lidarLabelDir().empty()) {
        failIn(stage, "option 'lidar_labels' is on but the dataset has no LiDAR labels (KITTI: "
                      "SEQ/labels/NNNNNN.label; generic: the dataset key 'labels_dir')");
    }
    for (std::size_t i = 0; i < dataset.numFrames(); ++i) {
        if (dataset.lidarLabelPath(i)) return;
    }
    failIn(stage, "option 'lidar_labels' is on but no selected frame has a label file in " +
                      dataset.lidarLabelDir().string());
}

}  // namespace

LidarVoteResult lidarVotes(const std::string& stage, Context& ctx, const FaceArrays& faces,
                           const LabelSet& labels, const std::string& label_map,
                           double radius_m) {
    const Dataset& dataset = ctx.dataset();
    Timer timer;
    requireSomeLabelFile(stage, dataset);
    const LabelMap map = lidarLabelMap(label_map, labels, dataset);
    const std::optional<Box3d> box = voteBox(ctx, radius_m);
    const double reach2 = dataset.config().max_range_m * dataset.config().max_range_m;
    LidarVoteAccumulator accumulator(faces.vertices, faces.triangles, labels.size(),
                                     static_cast<float>(radius_m));
    LidarVoteResult out;
    Progress progress(stage + " LiDAR votes", dataset.numFrames(), ctx.quiet());
    for (std::size_t i = 0; i < dataset.numFrames(); ++i) {
        progress.tick();
        const FrameInfo& frame = dataset.frame(i);
        if (box && squaredDistance(*box, frame.T_W_L.translation()) > reach2) {
            ++out.scans_out_of_reach;
            continue;
        }
        const auto label_path = dataset.lidarLabelPath(i);
        if (!label_path) {
            ++out.scans_without_labels;
            continue;
        }
        const PointCloud cloud = readPointCloud(frame.scan_path);
        const LidarLabels raw = readLidarLabels(*label_path);
        checkLabelCount(raw.size(), *label_path, cloud.size(), frame.scan_path);
        const std::vector<std::uint8_t> ids = mapLidarLabels(raw, *label_path, map);
        const LabelledPoints points =
            labelledPoints(cloud, ids, frame, dataset.config(), labels, box, out);
        accumulator.add(points.points_W, points.classes);
        out.points += cloud.size();
        ++out.scans;
    }
    progress.finish();
    if (out.scans_without_labels > 0) {
        logWarn(stage + ": " + std::to_string(out.scans_without_labels) + " of " +
                std::to_string(dataset.numFrames() - out.scans_out_of_reach) +
                " scans have no label file in " + dataset.lidarLabelDir().string() +
                " and do not vote");
    }
    out.votes = accumulator.finish();
    out.points_void = out.votes.void_votes - out.points_unknown_id;
    out.points_without_face = accumulator.pointsWithoutFace();
    out.seconds = timer.elapsedSeconds();
    return out;
}

}  // namespace vdbmap::semantic
