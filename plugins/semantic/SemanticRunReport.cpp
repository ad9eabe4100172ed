// SPDX-License-Identifier: Apache-2.0
#include "SemanticRunReport.h"

#include <array>
#include <sstream>

#include "SemanticExport.h"
#include "VoteCombination.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/map/Layers.h"
#include "vdbmap/pipeline/Report.h"

namespace vdbmap::semantic {
namespace {

double perSecond(std::size_t n, double seconds) {
    return seconds > 0.0 ? static_cast<double>(n) / seconds : 0.0;
}

enum SourceKind { kImagesOnly, kLidarOnly, kBoth, kFillOnly, kUnlabelled, kSourceKinds };

// Faces and area by the sources that labelled them.
struct SourceShares {
    std::array<std::size_t, kSourceKinds> faces{};
    std::array<double, kSourceKinds> area_m2{};
    double total_area_m2 = 0, confidence_area = 0;
};

SourceShares sourceShares(const SemanticRunFigures& f) {
    SourceShares s;
    const FusionResult& result = *f.result;
    for (std::size_t i = 0; i < result.face_labels.size(); ++i) {
        const std::uint8_t src = (*f.sources)[i];
        const int k = result.face_labels[i] == kUnknownLabel        ? kUnlabelled
                      : src == (kSourceImages | kSourceLidar) ? kBoth
                      : src == kSourceImages                  ? kImagesOnly
                      : src == kSourceLidar                   ? kLidarOnly
                                                              : kFillOnly;
        const double area = f.faces->area_m2[i];
        ++s.faces[k];
        s.area_m2[k] += area;
        s.total_area_m2 += area;
        s.confidence_area += result.confidence[i] * area;
    }
    return s;
}

void reportCounts(Report& report, const std::string& stage, const SemanticRunFigures& f) {
    const FusionResult& r = *f.result;
    report.stage(stage, "faces", r.face_labels.size());
    report.stage(stage, "views", f.images->views);
    report.stage(stage, "observations", f.images->observations);
    report.stage(stage, "scan_hidden_observations", f.images->scan_hidden);
    report.stage(stage, "visibility_reused", f.images->visibility_reused);
    report.stage(stage, "masked_observations", f.images->masked);
    report.stage(stage, "votes", f.votes->votes);
    report.stage(stage, "void_votes", f.votes->void_votes);
    report.stage(stage, "unknown_id_votes", f.votes->unknown_id_votes);
    if (f.lidar) {
        const LidarVoteResult& l = *f.lidar;
        report.stage(stage, "lidar_scans", l.scans);
        report.stage(stage, "lidar_scans_without_labels", l.scans_without_labels);
        report.stage(stage, "lidar_scans_out_of_reach", l.scans_out_of_reach);
        report.stage(stage, "lidar_points", l.points);
        report.stage(stage, "lidar_points_dropped", l.points_dropped);
        report.stage(stage, "lidar_points_void", l.points_void);
        report.stage(stage, "lidar_points_unknown_id", l.points_unknown_id);
        report.stage(stage, "lidar_points_without_face", l.points_without_face);
        report.stage(stage, "label_map", f.label_map.empty() ? std::string("identity") : f.label_map);
    }
    report.stage(stage, "observed_faces", r.observed_faces);
    report.stage(stage, "filled_faces", r.filled_faces);
    report.stage(stage, "unlabelled_faces", r.unlabelled_faces);
    report.stage(stage, "unlabelled_components", r.unlabelled_components);
    report.stage(stage, "fill", f.fill);
    report.stage(stage, "energy_initial", r.initial_energy);
    report.stage(stage, "energy_final", r.final_energy);
    report.stage(stage, "mrf_sweeps", r.sweeps);
}

void reportTimings(Report& report, const std::string& stage, const SemanticRunFigures& f) {
    const std::size_t n = f.result->face_labels.size();
    report.stage(stage, "time_visibility_s", f.images->visibility_s);
    report.stage(stage, "time_votes_s", f.images->votes_s);
    report.stage(stage, "time_lidar_votes_s", f.lidar ? f.lidar->seconds : 0.0);
    report.stage(stage, "time_mrf_s", f.mrf_s);
    report.stage(stage, "time_export_s", f.export_s);
    report.stage(stage, "faces_per_s_visibility", perSecond(n, f.images->visibility_s));
    report.stage(stage, "faces_per_s_votes", perSecond(n, f.images->votes_s));
    report.stage(stage, "faces_per_s_mrf", perSecond(n, f.mrf_s));
    report.stage(stage, "faces_per_s_total", perSecond(n, f.total_s));
}

void reportSources(Report& report, const std::string& stage, const SourceShares& s,
                   std::size_t num_faces) {
    const char* keys[kSourceKinds] = {"images", "lidar", "both", "fill_only", "unlabelled"};
    for (int k = 0; k < kSourceKinds; ++k) {
        auto key = [&](const char* leaf) {
            return std::vector<std::string>{"stages", stage, "sources", keys[k], leaf};
        };
        report.set(key("faces"), s.faces[k]);
        report.set(key("face_share"), num_faces ? double(s.faces[k]) / double(num_faces) : 0.0);
        report.set(key("area_m2"), s.area_m2[k]);
        report.set(key("area_share"), s.total_area_m2 > 0 ? s.area_m2[k] / s.total_area_m2 : 0.0);
    }
    report.stage(stage, "mean_confidence_area_weighted",
                 s.total_area_m2 > 0 ? s.confidence_area / s.total_area_m2 : 0.0);
}

void reportClasses(Report& report, const std::string& stage, const TriMesh& mesh,
                   const SemanticRunFigures& f) {
    for (const auto& [id, c] : classStatistics(mesh, f.result->face_labels)) {
        const std::string cls = std::to_string(static_cast<int>(id));
        report.set({"stages", stage, "classes", cls, "name"},
                   id == kUnknownLabel ? std::string("unknown") : f.labels->name(id));
        report.set({"stages", stage, "classes", cls, "faces"}, c.faces);
        report.set({"stages", stage, "classes", cls, "area_m2"}, c.area_m2);
    }
}

void logSummary(const std::string& stage, const SemanticRunFigures& f, const SourceShares& s) {
    std::ostringstream msg;
    msg << stage << ": " << f.result->face_labels.size() << " faces, " << f.images->views
        << " views, " << (f.lidar ? f.lidar->scans : 0) << " labelled scans; faces by images "
        << s.faces[kImagesOnly] << ", LiDAR " << s.faces[kLidarOnly] << ", both " << s.faces[kBoth]
        << ", fill " << s.faces[kFillOnly] << ", unlabelled " << s.faces[kUnlabelled]
        << "; energy " << f.result->initial_energy << " -> " << f.result->final_energy << "; "
        << f.total_s << " s";
    logInfo(msg.str());
}

}  // namespace

void reportSemanticRun(Report& report, const std::string& stage, const TriMesh& mesh,
                       const SemanticRunFigures& figures) {
    reportCounts(report, stage, figures);
    reportTimings(report, stage, figures);
    const SourceShares shares = sourceShares(figures);
    reportSources(report, stage, shares, figures.result->face_labels.size());
    reportClasses(report, stage, mesh, figures);
    logSummary(stage, figures, shares);
}

}  // namespace vdbmap::semantic
