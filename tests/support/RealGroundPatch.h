// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <Eigen/Eigenvalues>

#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "support/PlainAtsdfConfig.h"
#include "vdbmap/map/AtsdfIntegrator.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/mesh/MarchingCubes.h"

/// The ground patch of one real KITTI scan (HDL-64E, no pose needed: the scan is integrated in
/// its own frame) and how a mesh covers it: the road around the car, 4 to 20 m, seen at grazing
/// incidence by rings that get sparse with range, where a small truncation leaves holes.
/// Shared by RealGroundPatchTest (one frame, asserted) and bench_real_ground (every frame).
namespace vdbmap::test {

/// Side of a ground cell (m).
constexpr double kGroundCell_m = 0.5;

using GroundCellKey = std::pair<int, int>;
inline GroundCellKey groundCellOf(double x, double y) {
    return {static_cast<int>(std::floor(x / kGroundCell_m)), static_cast<int>(std::floor(y / kGroundCell_m))};
}

/// A ground cell: its scan points' plane (least squares, PCA), fitted when flat and level.
struct GroundCell {
    std::vector<Vec3d> points;
    Vec3d mean = Vec3d::Zero(), normal = Vec3d::UnitZ();
    bool plane = false;
};

/// The ground patch: scan points 4-20 m away horizontally, within 0.4 m of the sensor's height
/// minus 1.73 m (KITTI's Velodyne is 1.73 m above the road), in cells whose points are flat
/// and level (the road and the sidewalk, not cars or kerbs).
inline std::map<GroundCellKey, GroundCell> groundPatch(const std::vector<Vec3f>& scan_L) {
    std::map<GroundCellKey, GroundCell> cells;
    for (const Vec3f& pf : scan_L) {
        const Vec3d p = pf.cast<double>();
        const double r = std::hypot(p.x(), p.y());
        if (r < 4.0 || r > 20.0 || std::abs(p.z() + 1.73) > 0.4) continue;
        cells[groundCellOf(p.x(), p.y())].points.push_back(p);
    }
    for (auto it = cells.begin(); it != cells.end();) {
        GroundCell& c = it->second;
        if (c.points.size() >= 6) {
            for (const Vec3d& p : c.points) c.mean += p;
            c.mean /= static_cast<double>(c.points.size());
            Mat3d cov = Mat3d::Zero();
            for (const Vec3d& p : c.points) cov += (p - c.mean) * (p - c.mean).transpose();
            Eigen::SelfAdjointEigenSolver<Mat3d> es(cov / static_cast<double>(c.points.size()));
            c.normal = es.eigenvectors().col(0);
            // Flat (points within ~2 cm of their plane) and level (normal within 15 deg of up).
            c.plane = es.eigenvalues()(0) < 4e-4 && std::abs(c.normal.z()) > std::cos(0.26) &&
                      es.eigenvalues()(1) > 1e-3;
        }
        if (!c.plane) {
            it = cells.erase(it);
        } else {
            ++it;
        }
    }
    return cells;
}

struct PatchScore {
    double holes = 0.0;  ///< share of ground cells without a mesh vertex on their plane
    /// Per covered cell: the sum of its mesh vertices' distances to the cell's plane, and their
    /// number.
    std::map<GroundCellKey, std::pair<double, int>> cell_error;
};

/// Mean vertex distance to the cell planes over the cells that both `a` and `b` cover (the
/// accuracy of two meshes compared on the same surface: a mesh that covers more of the sparse
/// far road is not charged for the cells the other one leaves open).
inline std::pair<double, double> commonError(const PatchScore& a, const PatchScore& b) {
    double sa = 0.0, sb = 0.0;
    int na = 0, nb = 0;
    for (const auto& [key, e] : a.cell_error) {
        const auto it = b.cell_error.find(key);
        if (it == b.cell_error.end()) continue;
        sa += e.first;
        na += e.second;
        sb += it->second.first;
        nb += it->second.second;
    }
    return {na ? sa / na : 1e9, nb ? sb / nb : 1e9};
}

/// Integrates `scan_L` alone at `voxel_m` (grazing band 2 voxels, as the stage's default) and
/// scores its mesh on `patch`.
inline PatchScore scoreGroundPatch(TruncationMode mode, double eps_min_m, double eps_max_m,
                                   const std::vector<Vec3f>& scan_L,
                                   const std::map<GroundCellKey, GroundCell>& patch,
                                   int merge_divisions = 0, double voxel_m = 0.1) {
    VoxelMap map(voxel_m, static_cast<float>(eps_max_m), 1000.0f);
    AtsdfConfig c = plainAtsdfConfig();
    c.max_weight = 1000.0;
    c.truncation.mode = mode;
    c.truncation.min_m = eps_min_m;
    c.truncation.max_m = eps_max_m;
    c.truncation.grazing_band_m = 2.0 * voxel_m;
    c.merge_divisions = merge_divisions;
    AtsdfIntegrator integrator(map, c);
    integrator.integrateScan(scan_L, Isometry3d::Identity());
    integrator.finalize();
    const auto mesh = extractMesh(map, MarchingCubesConfig{});
    std::map<GroundCellKey, std::pair<double, int>> err;  // per cell: sum of distances, vertices
    for (auto v : mesh->vertices()) {
        const auto q = mesh->point(v);
        const Vec3d x(q[0], q[1], q[2]);
        const auto it = patch.find(groundCellOf(x.x(), x.y()));
        if (it == patch.end()) continue;
        const double d = std::abs(it->second.normal.dot(x - it->second.mean));
        if (d > 0.3) continue;  // another surface above the cell (a car's side)
        err[it->first].first += d;
        err[it->first].second += 1;
    }
    PatchScore s;
    for (const auto& [key, cell] : patch)
        if (err.find(key) == err.end()) s.holes += 1.0;
    s.holes /= static_cast<double>(patch.size());
    s.cell_error = std::move(err);
    return s;
}

}  // namespace vdbmap::test
