// SPDX-License-Identifier: Apache-2.0
// Issue 16 on real data: one real KITTI scan (tests/data/kitti_scans_real/000000.bin, HDL-64E,
// no pose needed: the scan is integrated in its own frame). Its ground patch (the road around
// the car, 4 to 20 m, seen at grazing incidence by rings that get sparse with range) is where
// a small truncation leaves holes. The adaptive mode must leave fewer holes there than fixed
// eps_min and be no less accurate there than fixed eps_max.
#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <filesystem>
#include <map>
#include <utility>

#include "vdbmap/io/PointCloudIO.h"
#include "vdbmap/map/AtsdfIntegrator.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/mesh/MarchingCubes.h"

using namespace vdbmap;

namespace {

constexpr double kVoxel = 0.1;
constexpr double kCell = 0.5;  // ground cells (m)

using CellKey = std::pair<int, int>;
CellKey cellOf(double x, double y) {
    return {static_cast<int>(std::floor(x / kCell)), static_cast<int>(std::floor(y / kCell))};
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
std::map<CellKey, GroundCell> groundPatch(const std::vector<Vec3f>& scan) {
    std::map<CellKey, GroundCell> cells;
    for (const Vec3f& pf : scan) {
        const Vec3d p = pf.cast<double>();
        const double r = std::hypot(p.x(), p.y());
        if (r < 4.0 || r > 20.0 || std::abs(p.z() + 1.73) > 0.4) continue;
        cells[cellOf(p.x(), p.y())].points.push_back(p);
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
    std::map<CellKey, std::pair<double, int>> cell_error;
};

/// Mean vertex distance to the cell planes over the cells that both `a` and `b` cover (the
/// accuracy of two meshes compared on the same surface: a mesh that covers more of the sparse
/// far road is not charged for the cells the other one leaves open).
std::pair<double, double> commonError(const PatchScore& a, const PatchScore& b) {
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

PatchScore score(TruncationMode mode, double eps_min, double eps_max, const std::vector<Vec3f>& scan,
                 const std::map<CellKey, GroundCell>& patch, int merge_divisions = 0) {
    VoxelMap map(kVoxel, static_cast<float>(eps_max), 1000.0f);
    AtsdfConfig c;
    c.max_weight = 1000.0;
    c.truncation.mode = mode;
    c.truncation.min_m = eps_min;
    c.truncation.max_m = eps_max;
    c.truncation.grazing_band_m = 2.0 * kVoxel;
    c.merge_divisions = merge_divisions;
    AtsdfIntegrator integrator(map, c);
    integrator.integrateScan(scan, Isometry3d::Identity());
    integrator.finalize();
    const auto mesh = extractMesh(map, MarchingCubesConfig{});
    std::map<CellKey, std::pair<double, int>> err;  // per cell: sum of distances, vertices
    for (auto v : mesh->vertices()) {
        const auto q = mesh->point(v);
        const Vec3d x(q[0], q[1], q[2]);
        const auto it = patch.find(cellOf(x.x(), x.y()));
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

}  // namespace

TEST_CASE("Real KITTI scan: adaptive (every point, and the stage's default merged rays) has "
          "fewer ground holes than fixed eps_min and is no less accurate there than fixed eps_max",
          "[tsdf][adaptive][real]") {
    const auto path = std::filesystem::path(VDBMAP_TEST_DATA_DIR) / "kitti_scans_real" / "000000.bin";
    const std::vector<Vec3f> scan = readBin(path).points;
    REQUIRE(scan.size() == 124668);
    const auto patch = groundPatch(scan);
    REQUIRE(patch.size() > 300);  // the road and sidewalk around the car
    for (const auto& [lo, hi] : {std::pair<double, double>{0.1, 0.3}, {0.4, 0.8}}) {
        const PatchScore small = score(TruncationMode::Fixed, lo, lo, scan, patch);
        const PatchScore large = score(TruncationMode::Fixed, hi, hi, scan, patch);
        const PatchScore adaptive = score(TruncationMode::Adaptive, lo, hi, scan, patch);
        const auto [adaptive_err, large_err] = commonError(adaptive, large);
        const auto [adaptive_err_s, small_err] = commonError(adaptive, small);
        INFO("range [" << lo << ", " << hi << "]: " << patch.size() << " ground cells; holes fixed "
                       << lo << " " << small.holes << ", fixed " << hi << " " << large.holes
                       << ", adaptive " << adaptive.holes << "; mean error (m) on the cells both "
                       << "cover: adaptive " << adaptive_err << " vs fixed " << hi << " " << large_err
                       << "; adaptive " << adaptive_err_s << " vs fixed " << lo << " " << small_err);
        CHECK(adaptive.holes < small.holes);
        CHECK(adaptive.holes <= large.holes);
        // No less accurate than fixed eps_max on the road both meshes cover (measured 7.4 vs
        // 7.6 mm at [0.1, 0.3], 10.0 vs 10.5 mm at [0.4, 0.8]; a reach of 1.5 eps_max along
        // grazing rays closes more cells but gives 11.2 mm at [0.4, 0.8]).
        CHECK(adaptive_err <= large_err);

        // merge_points: auto is one ray per voxel in the adaptive mode, its band started half a
        // voxel diagonal further in front (mergedRayFrontExtension). Measured: holes 6.3 %
        // against 52 % (fixed 0.1), error 7.43 against 7.45 mm (fixed 0.3); holes 1.3 % against
        // 4.0 % (fixed 0.4), 10.10 against 10.33 mm (fixed 0.8). Without the longer front,
        // merged rays lost the real ground at [0.1, 0.3] (docs/results/geometry.md, "On the real
        // scan").
        const PatchScore merged = score(TruncationMode::Adaptive, lo, hi, scan, patch, 1);
        const auto [merged_err, large_err_m] = commonError(merged, large);
        INFO("merged rays: holes " << merged.holes << ", error " << merged_err << " vs fixed " << hi
                                   << " " << large_err_m);
        CHECK(merged.holes < small.holes);
        CHECK(merged_err <= large_err_m);
    }
}
