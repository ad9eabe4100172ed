// SPDX-License-Identifier: Apache-2.0
// The per-point LiDAR labels of a dataset (docs/DATA.md: SEQ/labels/NNNNNN.label, or `labels_dir`).
#include <system_error>

#include "io/DatasetBuilder.h"
#include "vdbmap/io/Dataset.h"

namespace vdbmap {

void DatasetBuilder::findLidarLabels(Dataset& dataset) {
    const DatasetConfig& config = dataset.config_;
    if (!config.labels_dir.empty()) {
        dataset.lidar_labels_dir_ = resolve(dataset.root_, config.labels_dir);
        requireFolder(dataset.lidar_labels_dir_, "dataset: labels_dir");
        return;
    }
    std::error_code ec;
    if (config.format == "kitti" && std::filesystem::is_directory(dataset.root_ / "labels", ec)) {
        dataset.lidar_labels_dir_ = dataset.root_ / "labels";
    }
}

std::optional<std::filesystem::path> Dataset::lidarLabelPath(std::size_t i) const {
    if (lidar_labels_dir_.empty()) return std::nullopt;
    std::filesystem::path path = lidar_labels_dir_ / (frame(i).id + ".label");
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
    return path;
}

}  // namespace vdbmap
