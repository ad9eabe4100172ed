// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/map/BlockStats.h"

#include <openvdb/tools/Prune.h>

#include <Eigen/Eigenvalues>

#include <algorithm>

namespace vdbmap {

BlockStats batchStats(const std::vector<Vec3d>& points) {
    BlockStats s;
    if (points.empty()) return s;
    s.n = static_cast<double>(points.size());
    for (const Vec3d& p : points) s.mean += p;
    s.mean /= s.n;
    if (points.size() < 2) return s;
    for (const Vec3d& p : points) {
        const Vec3d d = p - s.mean;
        s.cov.noalias() += d * d.transpose();
    }
    s.cov /= (s.n - 1.0);
    return s;
}

BlockStats batchStatsIndexed(const Vec3f* points, const std::uint32_t* index, std::size_t count) {
    BlockStats batch;
    if (count == 0) return batch;
    batch.n = static_cast<double>(count);
    const Vec3d shift = points[index[0]].cast<double>();
    Vec3d sum = Vec3d::Zero();
    double sxx = 0, sxy = 0, sxz = 0, syy = 0, syz = 0, szz = 0;
    for (std::size_t k = 0; k < count; ++k) {
        const Vec3d d = points[index[k]].cast<double>() - shift;
        sum += d;
        sxx += d.x() * d.x(); sxy += d.x() * d.y(); sxz += d.x() * d.z();
        syy += d.y() * d.y(); syz += d.y() * d.z(); szz += d.z() * d.z();
    }
    const Vec3d mean_shifted = sum / batch.n;
    batch.mean = shift + mean_shifted;
    if (count > 1) {
        Mat3d scatter;
        scatter << sxx, sxy, sxz, sxy, syy, syz, sxz, syz, szz;
        batch.cov = (scatter - batch.n * mean_shifted * mean_shifted.transpose()) / (batch.n - 1.0);
    }
    return batch;
}

BlockStats mergeStats(const BlockStats& a, const BlockStats& b) {
    if (a.n <= 0.0) return b;
    if (b.n <= 0.0) return a;
    BlockStats m;
    m.n = a.n + b.n;
    // Paper Eq. (1): E' = (n1 E1 + n2 E2) / (n1 + n2)
    m.mean = (a.n * a.mean + b.n * b.mean) / m.n;
    // Paper Eq. (1): C' = [(n1-1) C1 + (n2-1) C2 + n1 d1 d1^T + n2 d2 d2^T] / (n1 + n2 - 1)
    const Vec3d d1 = m.mean - a.mean;
    const Vec3d d2 = m.mean - b.mean;
    m.cov = ((a.n - 1.0) * a.cov + (b.n - 1.0) * b.cov + a.n * d1 * d1.transpose() +
             b.n * d2 * d2.transpose()) /
            (m.n - 1.0);
    return m;
}

PlaneEstimate estimatePlane(const BlockStats& stats, const Vec3d& sensor_W, int min_points,
                            double min_spread_m, double collinear_ratio) {
    PlaneEstimate plane;
    if (stats.n < static_cast<double>(min_points) || stats.n < 3.0) return plane;
    // Closed-form 3x3 solver: eigenvalues in increasing order.
    Eigen::SelfAdjointEigenSolver<Mat3d> solver;
    solver.computeDirect(stats.cov);
    const Vec3d ev = solver.eigenvalues();
    const double l1 = ev(2), l2 = ev(1), l3 = std::max(ev(0), 0.0);
    plane.eigenvalues = Vec3d(l1, l2, l3);
    if (!(l2 > collinear_ratio * l1) || !(l2 > 0.0)) return plane;  // collinear or one point
    if (l2 < min_spread_m * min_spread_m) return plane;              // too small a patch
    Vec3d v3 = solver.eigenvectors().col(0);
    const double norm = v3.norm();
    if (!(norm > 0.0)) return plane;
    v3 /= norm;
    // Paper Eq. (2): orient the normal towards the sensor.
    plane.normal = v3.dot(sensor_W - stats.mean) > 0.0 ? v3 : Vec3d(-v3);
    // Paper Eq. (3): P_flat = 1 - lambda3 / lambda2.
    plane.flatness = std::clamp(1.0 - l3 / l2, 0.0, 1.0);
    plane.valid = true;
    return plane;
}

BlockStatsGrid::BlockStatsGrid() : index_tree_(-1) {}

std::int32_t BlockStatsGrid::find(const openvdb::Coord& block) const {
    return index_tree_.getValue(block);
}

std::int32_t BlockStatsGrid::findOrCreate(const openvdb::Coord& block) {
    std::int32_t index = index_tree_.getValue(block);
    if (index >= 0) return index;
    index = static_cast<std::int32_t>(entries_.size());
    entries_.emplace_back();
    coords_.push_back(block);
    index_tree_.setValueOn(block, index);
    return index;
}

std::size_t BlockStatsGrid::eraseIf(const std::function<bool(const openvdb::Coord& block)>& erase) {
    if (std::none_of(coords_.begin(), coords_.end(), erase)) return 0;
    std::vector<BlockEntry> entries;
    std::vector<openvdb::Coord> coords;
    for (std::size_t i = 0; i < entries_.size(); ++i) {
        if (erase(coords_[i])) {
            index_tree_.setValueOff(coords_[i], -1);
            continue;
        }
        index_tree_.setValueOn(coords_[i], static_cast<std::int32_t>(entries.size()));
        entries.push_back(entries_[i]);
        coords.push_back(coords_[i]);
    }
    const std::size_t erased = entries_.size() - entries.size();
    entries_.swap(entries);
    coords_.swap(coords);
    openvdb::tools::pruneInactive(index_tree_);
    return erased;
}

std::size_t BlockStatsGrid::memoryBytes() const {
    return entries_.capacity() * sizeof(BlockEntry) + coords_.capacity() * sizeof(openvdb::Coord) +
           static_cast<std::size_t>(index_tree_.memUsage());
}

double BlockStatsGrid::bytesPerBlock() const {
    if (entries_.empty()) return 0.0;
    return static_cast<double>(memoryBytes()) / static_cast<double>(entries_.size());
}

}  // namespace vdbmap
