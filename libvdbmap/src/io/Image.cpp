// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/io/Image.h"

#include <opencv2/imgcodecs.hpp>

#include "vdbmap/Error.h"
#include "vdbmap/io/AtomicFile.h"

namespace vdbmap {
namespace {

void requireFile(const std::filesystem::path& path, const char* what) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        throw IoError(std::string(what) + " not found: " + path.string());
    }
}

}  // namespace

cv::Mat readColorImage(const std::filesystem::path& path) {
    requireFile(path, "image");
    cv::Mat image = cv::imread(path.string(), cv::IMREAD_COLOR);
    if (image.empty()) {
        throw IoError("unreadable image (not a PNG/JPEG or corrupt): " + path.string());
    }
    return image;
}

cv::Mat readLabelImage(const std::filesystem::path& path) {
    requireFile(path, "semantic image");
    cv::Mat image = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
    if (image.empty()) {
        throw IoError("unreadable semantic image (not a PNG or corrupt): " + path.string());
    }
    if (image.type() != CV_8UC1) {
        throw IoError("semantic image must be 8-bit single channel (class ids), got " +
                      std::to_string(image.channels()) + " channel(s) of depth " +
                      std::to_string(image.depth()) + ": " + path.string());
    }
    return image;
}

void writePng(const std::filesystem::path& path, const cv::Mat& image) {
    if (image.empty()) {
        throw InvalidInput("writePng: empty image for " + path.string());
    }
    std::vector<unsigned char> bytes;
    bool ok = false;
    try {
        ok = cv::imencode(".png", image, bytes);
    } catch (const cv::Exception& e) {
        throw IoError("cannot encode PNG " + path.string() + ": " + e.what());
    }
    if (!ok) throw IoError("cannot encode PNG " + path.string());
    writeFileAtomically(
        path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

/// Image size from the file header only where possible (cv::imread decodes; acceptable here:
/// it is called once per camera).
cv::Size readImageSize(const std::filesystem::path& path) { return readColorImage(path).size(); }

}  // namespace vdbmap
