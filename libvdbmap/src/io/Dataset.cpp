// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/io/Dataset.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "io/DatasetBuilder.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/io/Image.h"
#include "vdbmap/io/LabelSet.h"
#include "vdbmap/io/PointCloudIO.h"

namespace vdbmap {

void filterScan(PointCloud& cloud, double min_range_m, double max_range_m, ScanReadStats* stats) {
    filterScan(cloud, min_range_m, max_range_m, stats, nullptr);
}

void filterScan(PointCloud& cloud, double min_range_m, double max_range_m, ScanReadStats* stats,
                std::vector<std::uint32_t>* kept_index) {
    if (kept_index) kept_index->clear();
    const bool has_intensity = cloud.intensity.size() == cloud.points.size();
    const double min2 = min_range_m * min_range_m;
    const double max2 = max_range_m * max_range_m;
    // The squared range in float is within 1e-6 of the double one (three products and two sums,
    // each rounded to 2^-24; above 1e-30 m^2, far from float's underflow): a point further than
    // 1e-5 inside the bounds is kept without the double check, which decides only the points
    // near a bound.
    const float keep_min2 = std::max(static_cast<float>(min2 * (1.0 + 1e-5)), 1e-30f);
    const float keep_max2 = static_cast<float>(std::min(max2 * (1.0 - 1e-5), 1e30));
    std::size_t kept = 0, non_finite = 0, out_of_range = 0;
    for (std::size_t i = 0; i < cloud.points.size(); ++i) {
        const Vec3f& p = cloud.points[i];
        const float r2f = p.squaredNorm();
        if (!(r2f > keep_min2 && r2f < keep_max2)) {  // near a bound, outside, or not finite
            if (!p.allFinite()) {
                ++non_finite;
                continue;
            }
            const double r2 = p.cast<double>().squaredNorm();
            if (r2 < min2 || r2 > max2) {
                ++out_of_range;
                continue;
            }
        }
        if (kept != i) {
            cloud.points[kept] = p;
            if (has_intensity) cloud.intensity[kept] = cloud.intensity[i];
        }
        if (kept_index) kept_index->push_back(static_cast<std::uint32_t>(i));
        ++kept;
    }
    if (stats != nullptr) {
        stats->points_read += cloud.points.size();
        stats->dropped_non_finite += non_finite;
        stats->dropped_range += out_of_range;
    }
    cloud.points.resize(kept);
    if (has_intensity) {
        cloud.intensity.resize(kept);
    } else {
        cloud.intensity.clear();
    }
}

std::shared_ptr<Dataset> Dataset::open(const DatasetConfig& config,
                                       const std::filesystem::path& base_dir) {
    std::shared_ptr<Dataset> dataset(new Dataset());
    dataset->config_ = config;
    dataset->base_dir_ = base_dir;
    if (config.path.empty()) {
        throw ConfigError("dataset: option 'path' is empty (the sequence folder)");
    }
    if (!(config.min_range_m >= 0.0) || !(config.max_range_m > config.min_range_m)) {
        throw ConfigError("dataset: need 0 <= min_range_m < max_range_m, got min_range_m " +
                          std::to_string(config.min_range_m) + ", max_range_m " +
                          std::to_string(config.max_range_m));
    }
    if (!config.drive.empty() && config.format != "kitti360") {
        throw ConfigError("dataset: option 'drive' is for format 'kitti360', not '" +
                          config.format + "'");
    }
    dataset->root_ = DatasetBuilder::resolve(base_dir, config.path);
    DatasetBuilder::requireFolder(dataset->root_, "dataset");
    if (config.format == "kitti") {
        DatasetBuilder::openKitti(*dataset);
    } else if (config.format == "kitti360") {
        DatasetBuilder::openKitti360(*dataset);
    } else if (config.format == "generic") {
        DatasetBuilder::openGeneric(*dataset);
    } else {
        throw ConfigError(
            "dataset: option 'format' must be 'kitti', 'kitti360' or 'generic', got '" +
            config.format + "'");
    }
    DatasetBuilder::findImages(*dataset);
    DatasetBuilder::findLidarLabels(*dataset);
    logInfo("dataset: poses from " + dataset->poses_path_.string());
    return dataset;
}

PointCloud Dataset::loadScan(std::size_t i, ScanReadStats* stats) const {
    PointCloud cloud;
    loadScan(i, cloud, stats);
    return cloud;
}

void Dataset::loadScan(std::size_t i, PointCloud& cloud, ScanReadStats* stats) const {
    loadScan(i, cloud, stats, nullptr);
}

void Dataset::loadScan(std::size_t i, PointCloud& cloud, ScanReadStats* stats,
                       std::vector<std::uint32_t>* kept_index) const {
    readPointCloud(frame(i).scan_path, cloud);
    filterScan(cloud, config_.min_range_m, config_.max_range_m, stats, kept_index);
}

Isometry3d Dataset::T_W_C(std::size_t i, std::size_t cam) const {
    return frame(i).T_W_L * cameras_.at(cam).T_C_L.inverse();
}

std::optional<std::filesystem::path> Dataset::imagePath(std::size_t i, std::size_t cam) const {
    const std::filesystem::path& p = image_paths_.at(i).at(cam);
    if (p.empty()) return std::nullopt;
    return p;
}

std::optional<std::filesystem::path> Dataset::semanticPath(std::size_t i, std::size_t cam) const {
    const std::filesystem::path& p = semantic_paths_.at(i).at(cam);
    if (p.empty()) return std::nullopt;
    return p;
}

std::size_t Dataset::missingImages() const {
    std::size_t missing = 0;
    for (const auto& per_camera : image_paths_) {
        for (const auto& p : per_camera) missing += p.empty() ? 1 : 0;
    }
    return missing;
}

std::size_t Dataset::missingImages(std::size_t cam) const {
    if (cam >= cameras_.size()) {
        throw std::out_of_range("Dataset::missingImages: camera " + std::to_string(cam) + " of " +
                                std::to_string(cameras_.size()));
    }
    std::size_t missing = 0;
    for (const auto& per_camera : image_paths_) missing += per_camera[cam].empty() ? 1 : 0;
    return missing;
}

std::size_t Dataset::missingSemantics() const {
    std::size_t missing = 0;
    for (const auto& per_camera : semantic_paths_) {
        for (std::size_t c = 0; c < per_camera.size(); ++c) {
            if (!semantic_dirs_[c].empty() && per_camera[c].empty()) ++missing;
        }
    }
    return missing;
}

LabelSet Dataset::labels() const {
    if (config_.labels_file.empty()) return LabelSet::defaults();
    return LabelSet::fromFile(DatasetBuilder::resolve(base_dir_, config_.labels_file));
}

}  // namespace vdbmap
