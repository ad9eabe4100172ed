// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "vdbmap/sim/SimSequence.h"

namespace vdbmap::test {

/// Writes a small surround-rig street (4 frames, 20 m, 320 x 180 images, no held-out views)
/// into `root / "seq"` unless it is there, and returns the dataset section the simulator wrote
/// for it (`seq/dataset.yaml`) with its `path` pointed at `seq`, relative to `root`: a pipeline
/// YAML run with base folder `root` then reads the rig. Append `plugins:` and `stages:`.
inline std::string rigDatasetYaml(const std::filesystem::path& root) {
    namespace fs = std::filesystem;
    if (!fs::exists(root / "seq" / "dataset.yaml")) {
        SimOptions sim;
        sim.frames = 4;
        sim.size_m = 20.0;
        sim.gt_views = 0;
        sim.quiet = true;
        sim.rig = "surround";
        sim.rig_options.width_px = 320;
        sim.rig_options.height_px = 180;
        writeSimSequence(sim, root / "seq");
    }
    std::ifstream in(root / "seq" / "dataset.yaml");
    std::string yaml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    yaml.replace(yaml.find("path: ."), 7, "path: seq");
    return yaml;
}

}  // namespace vdbmap::test
