// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <string>
#include <opencv2/core.hpp>

namespace vdbmap {

/// Reads a colour image as 8-bit BGR (OpenCV order). Throws IoError if unreadable.
cv::Mat readColorImage(const std::filesystem::path& path);
/// Reads an 8-bit single-channel id image (semantic_2/...). Throws IoError if unreadable or
/// not 8-bit single channel.
cv::Mat readLabelImage(const std::filesystem::path& path);
/// Writes a PNG atomically (8/16-bit, 1/3/4 channels, OpenCV channel order). Throws
/// IoError; InvalidInput for an empty image.
void writePng(const std::filesystem::path& path, const cv::Mat& image);
/// Throws IoError naming `path`, the size found and `expected` unless `image` is
/// expected.width x expected.height. `expected_from` says where the expected size comes from
/// (e.g. "camera 'image_2' (its first image)"). Readers of dataset views call it so that a
/// wrongly sized image is an error, not a view that silently projects nothing.
void requireImageSize(const cv::Mat& image, const std::filesystem::path& path,
                      const cv::Size& expected, const std::string& expected_from);
/// Width and height of an image file. Throws IoError if unreadable.
cv::Size readImageSize(const std::filesystem::path& path);

}  // namespace vdbmap
