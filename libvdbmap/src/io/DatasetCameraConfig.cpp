// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/io/DatasetCameraConfig.h"

#include "vdbmap/core/OptionSpec.h"

namespace vdbmap {

void DatasetCameraConfig::declareOptions(OptionSpec& spec) {
    spec.add<std::string>("name", "Camera name in logs and reports; empty = image folder name",
                          name, "");
    spec.addRequired<std::string>("image_dir", "Colour image folder (relative to `path`)",
                                  image_dir);
    spec.add<std::string>("semantic_dir", "Semantic id image folder; empty = none", semantic_dir,
                          "");
    spec.add<std::vector<double>>("intrinsics", "fx fy cx cy", intrinsics, {}, "px");
    spec.add<std::vector<double>>("distortion", "OpenCV k1 k2 p1 p2 [k3]; empty = none", distortion,
                                  {});
    spec.add<std::vector<double>>(
        "T_C_L", "LiDAR -> camera transform, 12 (3x4) or 16 row-major numbers", T_C_L, {}, "m");
    spec.add<std::string>("calib_file",
                          "File with K:, D:, T: lines (replaces intrinsics, distortion, T_C_L)",
                          calib_file, "");
}

}  // namespace vdbmap
