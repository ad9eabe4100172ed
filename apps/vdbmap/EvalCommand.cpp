// SPDX-License-Identifier: Apache-2.0
// `vdbmap eval --gt SEQ/gt --run OUTDIR`: geometry, semantic and texture scores of a run.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "Commands.h"
#include "EvalTraffic.h"
#include "vdbmap/Error.h"
#include "vdbmap/eval/CameraCoverage.h"
#include "vdbmap/eval/GeometryMetrics.h"
#include "vdbmap/eval/GtViews.h"
#include "vdbmap/eval/SemanticBoundary.h"
#include "vdbmap/eval/SemanticMetrics.h"
#include "vdbmap/eval/TextureMetrics.h"
#include "vdbmap/io/AtomicFile.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/io/Image.h"
#include "vdbmap/io/LabelSet.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/io/PointCloudIO.h"
#include "vdbmap/mesh/MeshAdjacency.h"
#include "vdbmap/pipeline/DatasetSection.h"
#include "vdbmap/render/Raycaster.h"
#include "vdbmap/render/Visibility.h"
#include "vdbmap/sim/SimScene.h"

namespace fs = std::filesystem;

namespace {

struct EvalArgs {
    std::string gt_dir;
    std::string run_dir;
    std::string json_path;
    std::string error_ply;
    std::string ghost_ply;
    std::string render_dir;
    std::string seq_dir;
    std::string dataset_yaml;
    std::vector<std::string> dataset_sets;
    std::string tau = "0.05,0.1,0.2";
    double cutoff_m = 0.5;
    double sample_spacing_m = 0.02;
    double stack_tolerance_m = 0.01;
    double boundary_band_m = 0.1;
    std::vector<int> classes;
    bool quiet = false;
};

std::vector<double> parseTau(const std::string& text) {
    std::vector<double> out;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        try {
            std::size_t used = 0;
            const double v = std::stod(item, &used);
            if (used != item.size() || !(v > 0)) throw std::invalid_argument(item);
            out.push_back(v);
        } catch (const std::exception&) {
            throw vdbmap::ConfigError("vdbmap eval: --tau must be positive numbers separated by "
                                      "commas, got '" + item + "' in '" + text + "'");
        }
    }
    if (out.empty()) throw vdbmap::ConfigError("vdbmap eval: --tau is empty");
    return out;
}

// Jet-like colour ramp: blue (0) -> green -> red (>= max).
std::array<std::uint8_t, 3> errorColor(float e, float max_e) {
    const float t = std::clamp(e / max_e, 0.0f, 1.0f);
    const float r = std::clamp(1.5f - std::abs(4.0f * t - 3.0f), 0.0f, 1.0f);
    const float g = std::clamp(1.5f - std::abs(4.0f * t - 2.0f), 0.0f, 1.0f);
    const float b = std::clamp(1.5f - std::abs(4.0f * t - 1.0f), 0.0f, 1.0f);
    return {static_cast<std::uint8_t>(255 * r), static_cast<std::uint8_t>(255 * g),
            static_cast<std::uint8_t>(255 * b)};
}

nlohmann::json statsJson(const vdbmap::DistanceStats& s) {
    return {{"count", s.count}, {"mean_m", s.mean}, {"median_m", s.median},
            {"p90_m", s.p90},   {"max_m", s.max},   {"rms_m", s.rms}};
}

nlohmann::json semanticJson(const vdbmap::SemanticMetrics& s) {
    const vdbmap::LabelSet label_set = vdbmap::LabelSet::defaults();
    nlohmann::json j;
    j["overall_accuracy"] = s.overall_accuracy;
    j["mean_class_accuracy"] = s.mean_class_accuracy;
    j["miou"] = s.miou;
    j["unlabelled_fraction"] = s.unlabelled_fraction;
    j["matched_area_m2"] = s.matched_area_m2;
    j["unmatched_area_m2"] = s.unmatched_area_m2;
    j["classes"] = nlohmann::json::array();
    for (const auto& c : s.classes) {
        nlohmann::json confused = nlohmann::json::array();
        for (const auto& [id, area] : c.confused_m2) {
            confused.push_back(
                {{"id", id},
                 {"name", id == 255 ? std::string("unlabelled") : label_set.name(id)},
                 {"area_m2", area}});
        }
        j["classes"].push_back({{"id", c.id},
                                {"name", label_set.name(c.id)},
                                {"area_m2", c.gt_area_m2},
                                {"accuracy", c.accuracy},
                                {"iou", c.iou},
                                {"confused_with", confused}});
    }
    return j;
}

// "  overall accuracy .. mean class accuracy .. mIoU .. unlabelled .." (no newline).
void printScores(std::ostringstream& table, const vdbmap::SemanticMetrics& m) {
    table << "  overall accuracy " << m.overall_accuracy << "  mean class accuracy "
          << m.mean_class_accuracy << "  mIoU " << m.miou << "  unlabelled " << m.unlabelled_fraction;
}

// The input cameras that define the camera-seen area: the dataset section of --dataset (a
// pipeline or dataset YAML, read as `vdbmap run` reads it, with --set dataset.<key>=value),
// else SEQ/dataset.yaml (written by `vdbmap-sim --rig surround`), else SEQ as a KITTI layout
// (calib.txt + poses.txt). `source` says which; null if there is none.
std::shared_ptr<vdbmap::Dataset> cameraDataset(const EvalArgs& args, const fs::path& seq,
                                               std::string& source) {
    fs::path yaml = args.dataset_yaml;
    if (yaml.empty() && fs::exists(seq / "dataset.yaml")) yaml = seq / "dataset.yaml";
    if (!yaml.empty()) {
        const vdbmap::DatasetSection section = vdbmap::loadDatasetSection(yaml, args.dataset_sets);
        source = yaml.string();
        return vdbmap::Dataset::open(section.config, section.base_dir);
    }
    if (!args.dataset_sets.empty()) {
        throw vdbmap::ConfigError("vdbmap eval: --set needs a dataset YAML (--dataset, or " +
                                  (seq / "dataset.yaml").string() + ")");
    }
    if (!fs::exists(seq / "calib.txt") || !fs::exists(seq / "poses.txt")) return nullptr;
    vdbmap::DatasetConfig config;
    config.format = "kitti";
    config.path = fs::absolute(seq).string();
    source = seq.string() + " (KITTI layout)";
    return vdbmap::Dataset::open(config);
}

// Prediction faces whose ground-truth point some input camera of `dataset` (every camera with
// images, every selected frame) sees.
std::vector<std::uint8_t> cameraSeenFaces(
    const vdbmap::Dataset& dataset, const vdbmap::GtLabelTransfer& transfer,
    const std::vector<vdbmap::Vec3f>& gt_vertices,
    const std::vector<std::array<std::uint32_t, 3>>& gt_triangles, const vdbmap::Raycaster& gt_rc) {
    const std::vector<vdbmap::View> views = vdbmap::datasetViews(dataset, true, false);
    std::vector<vdbmap::Vec3f> normals(transfer.gt_face.size(), vdbmap::Vec3f::UnitZ());
    for (std::size_t f = 0; f < normals.size(); ++f) {
        const auto& t = gt_triangles[transfer.gt_face[f]];
        const vdbmap::Vec3f n = (gt_vertices[t[1]] - gt_vertices[t[0]])
                                    .cross(gt_vertices[t[2]] - gt_vertices[t[0]]);
        if (n.norm() > 0.0f) normals[f] = n.normalized();
    }
    return vdbmap::pointsSeenByViews(transfer.gt_point_W, normals, views, gt_rc);
}

/// The ground-truth mesh with its face labels (every section needs it).
struct GroundTruth {
    fs::path mesh_path;
    std::vector<std::uint8_t> labels;  ///< per OpenMesh face (empty: none)
    std::vector<vdbmap::Vec3f> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<std::uint32_t> face_index;  ///< OpenMesh face of each triangle
    std::unique_ptr<vdbmap::Raycaster> raycaster;

    /// Label of each triangle (empty if the mesh has none).
    std::vector<std::uint8_t> triangleLabels() const {
        std::vector<std::uint8_t> out;
        if (labels.empty()) return out;
        for (std::uint32_t f : face_index) out.push_back(labels[f]);
        return out;
    }
};

GroundTruth loadGroundTruth(const fs::path& gt) {
    GroundTruth g;
    g.mesh_path = gt / "mesh.ply";
    if (!fs::exists(g.mesh_path)) throw vdbmap::IoError("vdbmap eval: " + g.mesh_path.string() + ": missing");
    vdbmap::PlyReadStats read;
    const vdbmap::TriMesh mesh = vdbmap::readMeshPly(g.mesh_path, &g.labels, &read);
    if (read.rejected_triangles > 0) {  // scores against part of the truth would mislead
        throw vdbmap::IoError("vdbmap eval: ground truth " + g.mesh_path.string() + " lost " +
                              std::to_string(read.rejected_triangles) + " of " +
                              std::to_string(read.triangles) +
                              " triangles on reading (non-manifold or repeated corners); "
                              "refusing to score against an incomplete ground truth");
    }
    vdbmap::triMeshArrays(mesh, g.vertices, g.triangles, &g.face_index);
    g.raycaster = std::make_unique<vdbmap::Raycaster>(g.vertices, g.triangles);
    return g;
}

// ---- Geometry: compute, JSON, table.

struct GeometryResult {
    fs::path mesh_path;
    std::string note;  ///< e.g. the observed points were missing
    std::size_t observed_points = 0;
    vdbmap::GeometryMetrics metrics;
};

GeometryResult computeGeometry(const EvalArgs& args, const fs::path& gt_dir, const GroundTruth& gt,
                               const std::vector<double>& tau) {
    GeometryResult r;
    r.mesh_path = fs::path(args.run_dir) / "mesh.ply";
    const vdbmap::TriMesh pred_mesh = vdbmap::readMeshPly(r.mesh_path);
    std::vector<vdbmap::Vec3f> pv;
    std::vector<std::array<std::uint32_t, 3>> pt;
    vdbmap::triMeshArrays(pred_mesh, pv, pt);
    std::vector<vdbmap::Vec3f> observed;
    const fs::path obs_path = gt_dir / "observed_points.ply";
    if (fs::exists(obs_path)) {
        observed = vdbmap::readPlyPoints(obs_path).points;
    } else {
        r.note = obs_path.string() + " missing: completeness uses ground-truth mesh vertices";
        observed = gt.vertices;
    }
    r.observed_points = observed.size();
    vdbmap::GeometryEvalOptions go;
    go.tau_m = tau;
    go.observed_cutoff_m = args.cutoff_m;
    go.sample_spacing_m = args.sample_spacing_m;
    go.gt_face_class = gt.triangleLabels();  // per-class completeness and recall
    if (!args.classes.empty()) {
        if (gt.labels.empty()) {
            throw vdbmap::IoError("vdbmap eval: --classes needs face labels in " + gt.mesh_path.string());
        }
        for (std::uint32_t f : gt.face_index) {
            go.gt_face_mask.push_back(std::find(args.classes.begin(), args.classes.end(),
                                                gt.labels[f]) != args.classes.end());
        }
    }
    std::vector<float> vertex_error;
    r.metrics = vdbmap::evaluateGeometry(pv, pt, *gt.raycaster, observed, go,
                                         args.error_ply.empty() ? nullptr : &vertex_error);
    if (!args.error_ply.empty()) {
        std::vector<std::array<std::uint8_t, 3>> colors;
        colors.reserve(vertex_error.size());
        const float max_e = static_cast<float>(*std::max_element(tau.begin(), tau.end()));
        for (float e : vertex_error) colors.push_back(errorColor(e, max_e));
        vdbmap::PlyWriteOptions opt;
        opt.vertex_colors = &colors;
        opt.vertex_normals = false;
        vdbmap::writeMeshPly(args.error_ply, pred_mesh, opt);
    }
    return r;
}

nlohmann::json geometryJson(const GeometryResult& r, const EvalArgs& args) {
    const vdbmap::GeometryMetrics& g = r.metrics;
    const vdbmap::LabelSet label_set = vdbmap::LabelSet::defaults();
    nlohmann::json j;
    j["mesh"] = r.mesh_path.string();
    j["faces"] = g.pred_faces;
    j["accuracy"] = statsJson(g.accuracy);
    j["completeness"] = statsJson(g.completeness);
    j["chamfer_l1_m"] = g.chamfer_l1;
    j["pred_samples"] = g.pred_samples;
    j["pred_samples_scored"] = g.pred_samples_used;
    j["observed_cutoff_m"] = args.cutoff_m;
    j["observed_points"] = r.observed_points;
    j["observed_points_scored"] = g.gt_points_used;
    j["classes"] = args.classes;
    for (const auto& f : g.fscores) {
        j["fscore"].push_back(
            {{"tau_m", f.tau_m}, {"precision", f.precision}, {"recall", f.recall}, {"fscore", f.fscore}});
    }
    j["per_class"] = nlohmann::json::array();
    for (const auto& c : g.per_class) {
        nlohmann::json recall = nlohmann::json::array();
        for (std::size_t t = 0; t < c.recall.size(); ++t)
            recall.push_back({{"tau_m", g.fscores[t].tau_m}, {"recall", c.recall[t]}});
        j["per_class"].push_back({{"id", c.class_id},
                                  {"name", label_set.name(static_cast<std::uint8_t>(c.class_id))},
                                  {"completeness", statsJson(c.completeness)},
                                  {"recall", recall}});
    }
    return j;
}

void geometryTable(const GeometryResult& r, const EvalArgs& args, const std::vector<double>& tau,
                   std::ostringstream& table) {
    const vdbmap::GeometryMetrics& g = r.metrics;
    if (!r.note.empty()) table << "note: " << r.note << "\n";
    table << std::setprecision(4) << "geometry (" << g.pred_faces << " faces"
          << (args.classes.empty() ? "" : ", scored on the selected classes only") << ")\n"
          << "  accuracy     mean " << g.accuracy.mean << "  median " << g.accuracy.median
          << "  p90 " << g.accuracy.p90 << "  max " << g.accuracy.max << " m\n"
          << "  completeness mean " << g.completeness.mean << "  median " << g.completeness.median
          << "  p90 " << g.completeness.p90 << "  max " << g.completeness.max << " m\n"
          << "  chamfer-L1   " << g.chamfer_l1 << " m\n";
    for (const auto& f : g.fscores) {
        table << "  tau " << f.tau_m << " m: precision " << f.precision << "  recall " << f.recall
              << "  F " << f.fscore << "\n";
    }
    if (!g.per_class.empty()) {
        const vdbmap::LabelSet label_set = vdbmap::LabelSet::defaults();
        table << "  recall per class (observed points):\n";
        for (const auto& c : g.per_class) {
            table << "    " << std::setw(14) << std::left
                  << label_set.name(static_cast<std::uint8_t>(c.class_id)) << std::right << " "
                  << std::setw(8) << c.completeness.count << " points";
            for (std::size_t t = 0; t < c.recall.size(); ++t)
                table << "  @" << g.fscores[t].tau_m << " " << c.recall[t];
            table << "\n";
        }
    }
    if (!args.error_ply.empty()) {
        table << "  error colouring (blue 0 -> red " << *std::max_element(tau.begin(), tau.end())
              << " m): " << args.error_ply << "\n";
    }
}

// ---- Semantics: compute, JSON, table.

struct BoundarySplit {
    vdbmap::SemanticMetrics near, inside;
};

BoundarySplit splitAtBoundaries(const vdbmap::GtLabelTransfer& transfer,
                                const std::vector<std::uint8_t>& labels,
                                const std::vector<std::uint8_t>& near_boundary,
                                const std::vector<std::uint8_t>* base) {
    std::vector<std::uint8_t> near(near_boundary.size()), inside(near_boundary.size());
    for (std::size_t f = 0; f < near.size(); ++f) {
        const bool in_base = base == nullptr || (*base)[f] != 0;
        near[f] = in_base && near_boundary[f] != 0;
        inside[f] = in_base && near_boundary[f] == 0;
    }
    return {vdbmap::scoreSemantics(transfer, labels, &near),
            vdbmap::scoreSemantics(transfer, labels, &inside)};
}

nlohmann::json boundaryJson(const BoundarySplit& b, double band_m) {
    const double total = b.near.matched_area_m2 + b.inside.matched_area_m2;
    const double n_wrong = (1.0 - b.near.overall_accuracy) * b.near.matched_area_m2;
    const double i_wrong = (1.0 - b.inside.overall_accuracy) * b.inside.matched_area_m2;
    nlohmann::json j;
    j["band_m"] = band_m;
    j["near_area_fraction"] = total > 0 ? b.near.matched_area_m2 / total : 0.0;
    j["near_accuracy"] = b.near.overall_accuracy;
    j["inside_accuracy"] = b.inside.overall_accuracy;
    j["wrong_area_near_m2"] = n_wrong;
    j["wrong_area_inside_m2"] = i_wrong;
    j["wrong_near_fraction"] = n_wrong + i_wrong > 0 ? n_wrong / (n_wrong + i_wrong) : 0.0;
    return j;
}

void boundaryTable(const BoundarySplit& b, double band_m, std::ostringstream& table) {
    const nlohmann::json j = boundaryJson(b, band_m);
    table << "  within " << band_m
          << " m of a class boundary: " << 100.0 * j["near_area_fraction"].get<double>()
          << " % of the area, accuracy " << b.near.overall_accuracy << "; elsewhere accuracy "
          << b.inside.overall_accuracy << "; " << 100.0 * j["wrong_near_fraction"].get<double>()
          << " % of the wrong area is near a boundary\n";
}

struct SemanticResult {
    fs::path mesh_path;
    vdbmap::SemanticMetrics all;
    std::size_t stacked_resolved = 0;
    std::size_t unknown_next_to_known = 0;
    std::optional<BoundarySplit> boundary;
    fs::path seq;
    std::string dataset_source;  ///< empty: no camera-seen scores
    std::vector<std::string> cameras;
    std::size_t frames = 0;
    vdbmap::SemanticMetrics seen;
    std::optional<BoundarySplit> seen_boundary;
};

SemanticResult computeSemantics(const EvalArgs& args, const fs::path& gt_dir, const GroundTruth& gt,
                                const fs::path& sem_path) {
    SemanticResult r;
    r.mesh_path = sem_path;
    std::vector<std::uint8_t> labels;
    const vdbmap::TriMesh sem_mesh = vdbmap::readMeshPly(sem_path, &labels);
    std::vector<vdbmap::Vec3f> sv;
    std::vector<std::array<std::uint32_t, 3>> st;
    std::vector<std::uint32_t> sf;
    vdbmap::triMeshArrays(sem_mesh, sv, st, &sf);
    if (labels.size() != sem_mesh.n_faces()) {
        throw vdbmap::IoError(sem_path.string() + ": has " + std::to_string(labels.size()) +
                              " face labels for " + std::to_string(sem_mesh.n_faces()) + " faces");
    }
    std::vector<std::uint8_t> tri_labels;
    for (std::uint32_t f : sf) tri_labels.push_back(labels[f]);
    const std::vector<std::uint8_t> gt_tri_labels = gt.triangleLabels();
    const vdbmap::GtLabelTransfer transfer = vdbmap::transferGtLabels(
        sv, st, *gt.raycaster, gt_tri_labels, args.cutoff_m, args.stack_tolerance_m);
    r.all = vdbmap::scoreSemantics(transfer, tri_labels);
    r.stacked_resolved = transfer.stacked_resolved;
    // Issue #6: no unlabelled face may have a labelled neighbour.
    r.unknown_next_to_known = vdbmap::unlabelledNextToLabelled(labels, vdbmap::faceAdjacency(sem_mesh));
    std::vector<std::uint8_t> near_boundary;
    if (args.boundary_band_m > 0) {
        near_boundary = vdbmap::nearGtClassBoundary(sv, st, transfer, *gt.raycaster, gt_tri_labels,
                                                    args.boundary_band_m, args.cutoff_m,
                                                    args.stack_tolerance_m);
        r.boundary = splitAtBoundaries(transfer, tri_labels, near_boundary, nullptr);
    }
    r.seq = args.seq_dir.empty() ? gt_dir.parent_path() : fs::path(args.seq_dir);
    const auto camera_dataset = cameraDataset(args, r.seq, r.dataset_source);
    if (camera_dataset) {
        const std::vector<std::uint8_t> seen =
            cameraSeenFaces(*camera_dataset, transfer, gt.vertices, gt.triangles, *gt.raycaster);
        r.seen = vdbmap::scoreSemantics(transfer, tri_labels, &seen);
        for (const auto& camera : camera_dataset->cameras()) r.cameras.push_back(camera.name);
        r.frames = camera_dataset->numFrames();
        if (!near_boundary.empty())
            r.seen_boundary = splitAtBoundaries(transfer, tri_labels, near_boundary, &seen);
    }
    return r;
}

double seenFraction(const SemanticResult& r) {
    return r.all.matched_area_m2 > 0 ? r.seen.matched_area_m2 / r.all.matched_area_m2 : 0.0;
}

nlohmann::json semanticsJson(const SemanticResult& r, const EvalArgs& args) {
    nlohmann::json j = semanticJson(r.all);
    j["mesh"] = r.mesh_path.string();
    j["stack_tolerance_m"] = args.stack_tolerance_m;
    j["faces_labelled_by_outer_stacked_surface"] = r.stacked_resolved;
    j["unlabelled_faces_next_to_labelled"] = r.unknown_next_to_known;
    if (r.boundary) j["boundary"] = boundaryJson(*r.boundary, args.boundary_band_m);
    if (r.dataset_source.empty()) {
        j["camera_seen"] = nullptr;
        return j;
    }
    nlohmann::json jo = semanticJson(r.seen);
    jo["sequence"] = r.seq.string();
    jo["dataset"] = r.dataset_source;
    jo["cameras"] = r.cameras;
    jo["frames"] = r.frames;
    jo["seen_fraction"] = seenFraction(r);
    if (r.seen_boundary) jo["boundary"] = boundaryJson(*r.seen_boundary, args.boundary_band_m);
    j["camera_seen"] = jo;
    return j;
}

void semanticsTable(const SemanticResult& r, const EvalArgs& args, std::ostringstream& table) {
    table << std::setprecision(4) << "semantics (all area)\n";
    printScores(table, r.all);
    table << " (unlabelled faces next to a labelled one: " << r.unknown_next_to_known << ")\n";
    if (r.boundary) boundaryTable(*r.boundary, args.boundary_band_m, table);
    if (r.dataset_source.empty()) {
        table << "semantics (camera-seen area): skipped (no --dataset, and neither "
                 "dataset.yaml nor calib.txt + poses.txt in "
              << r.seq.string() << ")\n";
        return;
    }
    table << "semantics (camera-seen area, " << 100.0 * seenFraction(r) << " % of the matched area; "
          << r.cameras.size() << " camera(s) of " << r.dataset_source << ")\n";
    printScores(table, r.seen);
    table << "\n";
    if (r.seen_boundary) boundaryTable(*r.seen_boundary, args.boundary_band_m, table);
}

// ---- Texture: compute, JSON, table.

struct TextureResult {
    fs::path mesh_path;
    vdbmap::TextureMetrics metrics;
};

/// Writes each held-out view's render, its ground truth and their absolute difference (times 4)
/// side by side into render_dir/view_NNNNNN.png (top to bottom), to look at.
void writeTextureRenders(const fs::path& render_dir, const std::vector<vdbmap::GtView>& views,
                         const std::vector<cv::Mat>& images, const std::vector<cv::Mat>& renders) {
    fs::create_directories(render_dir);
    for (std::size_t i = 0; i < renders.size(); ++i) {
        cv::Mat diff;
        cv::absdiff(renders[i], images[i], diff);
        diff.convertTo(diff, CV_8UC3, 4.0);
        cv::Mat stacked;
        cv::vconcat(std::vector<cv::Mat>{renders[i], images[i], diff}, stacked);
        vdbmap::writePng(render_dir / views[i].image, stacked);
    }
}

TextureResult computeTexture(const fs::path& obj_path, const fs::path& views_dir, const GroundTruth& gt,
                             const std::string& render_dir) {
    TextureResult r;
    r.mesh_path = obj_path;
    vdbmap::ObjMesh obj;
    std::vector<cv::Mat> textures;
    vdbmap::loadTexturedObj(obj_path, obj, textures);
    const auto views = vdbmap::readGtViews(views_dir);
    std::vector<cv::Mat> images;
    for (const auto& v : views) images.push_back(vdbmap::readColorImage(views_dir / v.image));
    std::vector<cv::Mat> renders;
    r.metrics = vdbmap::evaluateTexture(obj, textures, views, images, gt.raycaster.get(),
                                        render_dir.empty() ? nullptr : &renders);
    if (!render_dir.empty()) writeTextureRenders(render_dir, views, images, renders);
    return r;
}

nlohmann::json textureJson(const TextureResult& r) {
    const vdbmap::TextureMetrics& t = r.metrics;
    return {{"mesh", r.mesh_path.string()}, {"views", t.views},  {"pixels_compared", t.pixels_compared},
            {"coverage", t.coverage},       {"mae", t.mae},      {"psnr_db", t.psnr_db},
            {"view_psnr_db", t.view_psnr_db}};
}

void textureTable(const TextureResult& r, std::ostringstream& table) {
    const vdbmap::TextureMetrics& t = r.metrics;
    table << std::setprecision(3) << "texture (" << t.views << " held-out views)\n"
          << "  PSNR " << t.psnr_db << " dB  MAE " << t.mae << " (0-255)  coverage " << t.coverage << "\n";
}

void writeReport(const std::string& json_path, const nlohmann::json& report) {
    vdbmap::writeFileAtomically(json_path, report.dump(2) + "\n");  // checked to the last byte
}

void runEval(const EvalArgs& args, int& exit_code) {
    const fs::path gt_dir(args.gt_dir);
    const fs::path run(args.run_dir);
    if (!fs::is_directory(gt_dir)) {
        throw vdbmap::IoError("vdbmap eval: --gt " + gt_dir.string() + ": not a folder");
    }
    if (!fs::is_directory(run)) {
        throw vdbmap::IoError("vdbmap eval: --run " + run.string() + ": not a folder");
    }
    const std::vector<double> tau = parseTau(args.tau);
    nlohmann::json report;
    report["gt"] = gt_dir.string();
    report["run"] = run.string();
    std::ostringstream table;
    table << std::fixed;
    const GroundTruth gt = loadGroundTruth(gt_dir);

    const fs::path pred_mesh_path = run / "mesh.ply";
    if (fs::exists(pred_mesh_path)) {
        const GeometryResult g = computeGeometry(args, gt_dir, gt, tau);
        report["geometry"] = geometryJson(g, args);
        geometryTable(g, args, tau, table);
    } else {
        table << "geometry: skipped (" << pred_mesh_path.string() << " missing)\n";
        report["geometry"] = nullptr;
    }

    const fs::path sem_path = run / "semantic" / "mesh.ply";
    if (fs::exists(sem_path) && !gt.labels.empty()) {
        const SemanticResult s = computeSemantics(args, gt_dir, gt, sem_path);
        report["semantics"] = semanticsJson(s, args);
        semanticsTable(s, args, table);
    } else {
        table << "semantics: skipped ("
              << (gt.labels.empty() ? gt.mesh_path.string() + " has no face labels"
                                    : sem_path.string() + " missing")
              << ")\n";
        report["semantics"] = nullptr;
    }

    const fs::path obj_path = run / "textured" / "mesh.obj";
    const fs::path views_dir = gt_dir / "views";
    if (fs::exists(obj_path) && fs::exists(views_dir / "views.json")) {
        const TextureResult t = computeTexture(obj_path, views_dir, gt, args.render_dir);
        report["texture"] = textureJson(t);
        textureTable(t, table);
    } else {
        table << "texture: skipped ("
              << (fs::exists(obj_path) ? (views_dir / "views.json").string() : obj_path.string())
              << " missing)\n";
        report["texture"] = nullptr;
    }

    // Issue 33: with gt/movers.json (vdbmap-sim --traffic), the ghosts of the movers and the
    // scores of dynamic_points.ply.
    TrafficEvalOptions traffic_options;
    traffic_options.sample_spacing_m = args.sample_spacing_m;
    traffic_options.ghost_ply = args.ghost_ply;
    nlohmann::json traffic = evalTraffic(gt_dir, run, *gt.raycaster, traffic_options, table);
    if (!traffic.is_null()) report["traffic"] = std::move(traffic);

    if (!args.json_path.empty()) writeReport(args.json_path, report);
    if (!args.quiet) std::cout << table.str();
    exit_code = 0;
}

}  // namespace

void addEvalCommand(CLI::App& app, int& exit_code) {
    auto args = std::make_shared<EvalArgs>();
    CLI::App* cmd = app.add_subcommand(
        "eval", "Score a run against simulator ground truth (geometry, semantics, texture)");
    cmd->add_option("--gt", args->gt_dir, "Ground-truth folder (SEQ/gt from vdbmap-sim)")
        ->required();
    cmd->add_option("--run", args->run_dir, "Output folder of `vdbmap run`")->required();
    cmd->add_option("--json", args->json_path, "Write the metrics as JSON to this file");
    cmd->add_option("--error-ply", args->error_ply,
                    "Write the run's mesh with per-vertex error colours (blue 0 -> red max tau)");
    cmd->add_option("--ghost-ply", args->ghost_ply,
                    "With traffic (gt/movers.json): write the faces of the run's mesh that count "
                    "as ghost area to this PLY");
    cmd->add_option("--render-dir", args->render_dir,
                    "Write each held-out view's render, ground truth and difference (x4), top to "
                    "bottom, as DIR/view_NNNNNN.png");
    cmd->add_option("--tau", args->tau, "F-score thresholds in metres, comma-separated")
        ->capture_default_str();
    cmd->add_option("--cutoff", args->cutoff_m,
                    "Prediction farther than this (m) from observed ground truth is not scored")
        ->capture_default_str();
    cmd->add_option("--sample-spacing", args->sample_spacing_m,
                    "Sample spacing (m) on the run's mesh for accuracy")
        ->capture_default_str();
    cmd->add_option("--seq", args->seq_dir,
                    "Sequence folder whose cameras define the camera-seen area of the semantic "
                    "scores: its dataset.yaml, else its KITTI layout (default: the parent of "
                    "--gt)");
    cmd->add_option("--dataset", args->dataset_yaml,
                    "YAML file (the run's pipeline, or a file with a `dataset:` section) whose "
                    "dataset defines the camera-seen area, read as `vdbmap run` reads it");
    cmd->add_option("--set", args->dataset_sets,
                    "Override of the dataset YAML: dataset.<key>=value (as `vdbmap run --set`)");
    cmd->add_option("--stack-tolerance", args->stack_tolerance_m,
                    "Ground-truth surfaces stacked closer than this (m, e.g. a lane marking on "
                    "the asphalt): the outer one along the face normal labels the face")
        ->capture_default_str();
    cmd->add_option("--boundary-band", args->boundary_band_m,
                    "Also score the semantics split into faces within this distance (m) of a "
                    "ground-truth class boundary and the rest; 0 = off")
        ->capture_default_str();
    cmd->add_option("--classes", args->classes,
                    "Score geometry only where the nearest ground-truth face has one of these "
                    "class ids (e.g. 13 = the SUV without its ground)")
        ->delimiter(',');
    cmd->add_flag("-q,--quiet", args->quiet, "Print nothing (use --json)");
    cmd->callback([args, &exit_code] { runEval(*args, exit_code); });
}
