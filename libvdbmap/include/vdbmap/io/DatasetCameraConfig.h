// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

namespace vdbmap {

class OptionSpec;

/// One camera of the generic layout (docs/DATA.md): an entry of the `dataset: cameras:` list, e.g.
///
///     cameras:
///       - name: front                # optional; default: the image folder's name
///         image_dir: image_front     # relative to the dataset `path`
///         semantic_dir: semantic_front
///         intrinsics: [640, 640, 639.5, 359.5]   # fx fy cx cy, px
///         distortion: [0, 0, 0, 0]               # optional OpenCV k1 k2 p1 p2 [k3]
///         T_C_L: [12 or 16 row-major numbers]    # LiDAR -> this camera
///       - image_dir: image_rear
///         calib_file: calib_rear.txt  # K:, D:, T: lines instead of intrinsics / T_C_L
///
/// Declared through an OptionSpec, so that a camera map gets the same checks as every other
/// section (unknown key with file:line:col and the valid keys, wrong types) and
/// `vdbmap describe dataset` lists the keys.
struct DatasetCameraConfig {
    std::string name;                ///< "" = the last folder name of image_dir
    std::string image_dir;           ///< colour images (required)
    std::string semantic_dir;        ///< semantic id images ("" = none)
    std::vector<double> intrinsics;  ///< fx fy cx cy, px
    std::vector<double> distortion;  ///< k1 k2 p1 p2 [k3] ("" = none)
    std::vector<double> T_C_L;       ///< LiDAR -> camera, 12 (3x4) or 16 (4x4) row-major, m
    std::string calib_file;          ///< K/D/T file; replaces intrinsics, distortion, T_C_L

    /// Declares every field (key = field name) with its doc, default and unit; image_dir is
    /// required.
    void declareOptions(OptionSpec& spec);
};

}  // namespace vdbmap
