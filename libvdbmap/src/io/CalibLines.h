// SPDX-License-Identifier: Apache-2.0
// The "KEY: numbers" lines shared by the calibration files we read: KITTI calib.txt, the K/D/T
// files of the generic layout, KITTI-360's calib_cam_to_pose.txt and perspective.txt.
#pragma once

#include <cstddef>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <vector>

#include "vdbmap/io/CalibIO.h"

namespace vdbmap::detail {

/// One "key: numbers" line of a calibration file.
struct CalibLine {
    std::string key;
    std::vector<double> values;
    std::size_t line_number = 0;
    std::string text;     ///< the line, at most 160 characters, for messages
    bool numeric = true;  ///< false: a value is not a number (allowed only when lenient)
};

/// How readCalibLines treats a line whose values are not all numbers.
enum class CalibText {
    Strict,  ///< IoError naming file:line (KITTI calib.txt, K/D/T files)
    Lenient  ///< kept with numeric = false (perspective.txt's "calib_time: 09-Jan-2012 ...")
};

/// Reads every non-empty, non-'#' line as "KEY: values". Throws IoError naming file:line for a
/// line without a key, a non-finite value, and (Strict) a value that is not a number.
std::vector<CalibLine> readCalibLines(const std::filesystem::path& path,
                                      CalibText mode = CalibText::Strict);

/// The line with `key`, or null.
const CalibLine* findCalibLine(const std::vector<CalibLine>& lines, const std::string& key);

/// Throws IoError naming file:line and the key unless the line holds numbers, as many as one
/// of `counts`.
void requireCount(const std::filesystem::path& path, const CalibLine& line,
                  std::initializer_list<std::size_t> counts);

/// Row-major 3x4 matrix of 12 values.
Mat34d toMat34(const std::vector<double>& values);

}  // namespace vdbmap::detail
