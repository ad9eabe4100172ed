// SPDX-License-Identifier: Apache-2.0
// `vdbmap eval`, traffic section (issue 33): ghosts of moving objects and removed points.
#include "EvalTraffic.h"

#include <iomanip>

#include "vdbmap/Error.h"
#include "vdbmap/eval/GeometryMetrics.h"
#include "vdbmap/eval/TrafficMetrics.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/render/Raycaster.h"

namespace fs = std::filesystem;

namespace {

/// The faces of (vertices, triangles) whose ghost area is positive, as a PLY at `path`.
void writeGhostFaces(const fs::path& path, const std::vector<vdbmap::Vec3f>& vertices,
                     const std::vector<std::array<std::uint32_t, 3>>& triangles,
                     const std::vector<double>& ghost_area_m2) {
    vdbmap::TriMesh ghosts;
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        if (ghost_area_m2[t] <= 0.0) continue;
        std::array<vdbmap::TriMesh::VertexHandle, 3> vh;
        for (int k = 0; k < 3; ++k) {
            const vdbmap::Vec3f& p = vertices[triangles[t][k]];
            vh[k] = ghosts.add_vertex(vdbmap::TriMesh::Point(p.x(), p.y(), p.z()));
        }
        ghosts.add_face(vh[0], vh[1], vh[2]);
    }
    vdbmap::PlyWriteOptions options;
    options.vertex_normals = false;
    vdbmap::writeMeshPly(path, ghosts, options);
}

nlohmann::json movingPointsJson(const vdbmap::MovingPointScores& s, const fs::path& ply,
                                const fs::path& labels) {
    nlohmann::json j;
    j["file"] = ply.string();
    j["labels"] = labels.string();
    j["moving_points"] = s.moving_points;
    j["static_points"] = s.static_points;
    j["removed"] = s.removed;
    j["removed_moving"] = s.removed_moving;
    j["removed_static"] = s.removed_static;
    j["removed_unmatched"] = s.removed_unmatched;
    j["removed_duplicates"] = s.removed_duplicates;
    j["recall"] = s.moving_points > 0 ? nlohmann::json(s.recall) : nlohmann::json(nullptr);
    j["precision"] = s.removed > 0 ? nlohmann::json(s.precision) : nlohmann::json(nullptr);
    j["static_retention"] = s.static_retention;
    return j;
}

}  // namespace

nlohmann::json evalTraffic(const fs::path& gt_dir, const fs::path& run_dir,
                           const vdbmap::Raycaster& static_gt, const TrafficEvalOptions& options,
                           std::ostringstream& table) {
    const fs::path movers_path = gt_dir / "movers.json";
    if (!fs::exists(movers_path)) return nullptr;
    const vdbmap::MoversFile movers = vdbmap::readMoversJson(movers_path);
    const vdbmap::SweptVolume swept(movers, options.swept_inflate_m);
    nlohmann::json j;
    j["movers_file"] = movers_path.string();
    j["movers"] = movers.movers.size();
    j["frames"] = movers.times_s.size();
    j["ghost_distance_m"] = options.ghost_distance_m;
    j["swept_inflate_m"] = options.swept_inflate_m;
    j["footprint_cell_m"] = options.footprint_cell_m;
    const double swept_ground = swept.groundArea(options.footprint_cell_m);
    j["swept_ground_area_m2"] = swept_ground;
    table << std::setprecision(4) << "traffic (" << movers.movers.size() << " movers, "
          << movers.times_s.size() << " frames)\n"
          << "  swept ground area " << swept_ground << " m^2 (boxes + " << options.swept_inflate_m
          << " m, " << options.footprint_cell_m << " m raster)\n";

    const fs::path mesh_path = run_dir / "mesh.ply";
    if (fs::exists(mesh_path)) {
        std::vector<vdbmap::Vec3f> vertices;
        std::vector<std::array<std::uint32_t, 3>> triangles;
        vdbmap::triMeshArrays(vdbmap::readMeshPly(mesh_path), vertices, triangles);
        const std::vector<double> per_face =
            vdbmap::ghostAreaPerFace(vertices, triangles, static_gt, swept,
                                     options.ghost_distance_m, options.sample_spacing_m);
        double ghost = 0.0;
        for (double a : per_face) ghost += a;
        if (!options.ghost_ply.empty()) writeGhostFaces(options.ghost_ply, vertices, triangles, per_face);
        j["ghost_area_m2"] = ghost;
        j["ghost_fraction"] =
            swept_ground > 0 ? nlohmann::json(ghost / swept_ground) : nlohmann::json(nullptr);
        table << "  ghost area " << ghost << " m^2 (mesh farther than " << options.ghost_distance_m
              << " m from the static truth, inside the swept "
              << "volume) = " << (swept_ground > 0 ? 100.0 * ghost / swept_ground : 0.0)
              << " % of the swept ground area\n";
    } else {
        j["ghost_area_m2"] = nullptr;
        j["ghost_fraction"] = nullptr;
        table << "  ghost area: skipped (" << mesh_path.string() << " missing)\n";
    }

    const fs::path dyn_path = run_dir / "dynamic_points.ply";
    if (!fs::exists(dyn_path)) {
        j["moving_points"] = nullptr;
        table << "  moving points: skipped (" << dyn_path.string() << " missing)\n";
        return j;
    }
    const fs::path labels_dir = vdbmap::findSimLabelsDir(gt_dir);
    if (labels_dir.empty()) {
        throw vdbmap::IoError("vdbmap eval: " + dyn_path.string() +
                              " needs the sequence's per-point labels, found none beside " +
                              gt_dir.string() +
                              " (labels/, gt/labels/, dataset/sequences/*/labels)");
    }
    const vdbmap::MovingTruth truth = vdbmap::readMovingTruth(labels_dir, movers.times_s.size());
    const vdbmap::MovingPointScores s =
        vdbmap::scoreRemovedPoints(truth, vdbmap::readRemovedPointsPly(dyn_path));
    j["moving_points"] = movingPointsJson(s, dyn_path, labels_dir);
    table << "  moving points: " << s.moving_points << " moving, " << s.static_points
          << " static; removed " << s.removed << ": recall " << s.recall << "  precision "
          << s.precision << "  static retention " << s.static_retention << "\n";
    if (s.removed_unmatched > 0) {
        table << "  note: " << s.removed_unmatched
              << " removed points name a frame or index the labels do not have\n";
    }
    return j;
}
