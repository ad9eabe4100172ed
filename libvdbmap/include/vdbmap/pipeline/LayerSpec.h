// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

namespace vdbmap {

/// What a stage reads and writes (names from map/Layers.h, or a plugin's own). Before any
/// stage runs, the pipeline checks that every layer read has an earlier writer (or is
/// provided by the dataset: scans, images, semantic_images).
class LayerSpec {
public:
    void reads(const std::string& layer) { reads_.push_back(layer); }
    void writes(const std::string& layer) { writes_.push_back(layer); }
    const std::vector<std::string>& readLayers() const { return reads_; }
    const std::vector<std::string>& writtenLayers() const { return writes_; }

private:
    std::vector<std::string> reads_;
    std::vector<std::string> writes_;
};

}  // namespace vdbmap
