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
        const int bits = image.depth() == CV_8U || image.depth() == CV_8S     ? 8
                         : image.depth() == CV_16U || image.depth() == CV_16S ? 16
                                                                              : 32;
        throw IoError(path.string() + ": a class-id (semantic) image must have one channel of "
                      "8-bit ids, but read as stored (unchanged) it has " +
                      std::to_string(image.channels()) +
                      (image.channels() == 1 ? " channel" : " channels") + " of " +
                      std::to_string(bits) + " bits; write it as an 8-bit grey PNG");
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

void requireImageSize(const cv::Mat& image, const std::filesystem::path& path,
                      const cv::Size& expected, const std::string& expected_from) {
    if (image.cols == expected.width && image.rows == expected.height) return;
    throw IoError(path.string() + ": image is " + std::to_string(image.cols) + " x " +
                  std::to_string(image.rows) + " pixels but " + expected_from + " is " +
                  std::to_string(expected.width) + " x " + std::to_string(expected.height));
}

/// Image size from the file header only where possible (cv::imread decodes; acceptable here:
/// it is called once per camera).
cv::Size readImageSize(const std::filesystem::path& path) { return readColorImage(path).size(); }

}  // namespace vdbmap
