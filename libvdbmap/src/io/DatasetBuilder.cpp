// SPDX-License-Identifier: Apache-2.0
#include "io/DatasetBuilder.h"

#include <algorithm>
#include <cctype>

#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/io/Image.h"
#include "vdbmap/io/PointCloudIO.h"

namespace vdbmap {
namespace {

/// The image of frame `id` in `folder`: id.png, id.jpg or id.jpeg; empty if none exists.
std::filesystem::path findView(const std::filesystem::path& folder, const std::string& id) {
    if (folder.empty()) return {};
    for (const char* ext : {".png", ".jpg", ".jpeg", ".PNG", ".JPG"}) {
        std::filesystem::path p = folder / (id + ext);
        std::error_code ec;
        if (std::filesystem::is_regular_file(p, ec)) return p;
    }
    return {};
}

}  // namespace

long long DatasetBuilder::frameNumber(const std::string& stem) {
    if (stem.empty() || stem.size() > 12) return -1;
    for (const char c : stem) {
        if (!std::isdigit(static_cast<unsigned char>(c))) return -1;
    }
    return std::stoll(stem);
}

std::filesystem::path DatasetBuilder::resolve(const std::filesystem::path& base,
                                              const std::string& relative) {
    const std::filesystem::path p(relative);
    if (p.is_absolute() || base.empty()) return p;
    return base / p;
}

void DatasetBuilder::requireFolder(const std::filesystem::path& folder, const std::string& what) {
    std::error_code ec;
    if (!std::filesystem::is_directory(folder, ec)) {
        throw IoError(what + " folder not found: " + folder.string());
    }
}

std::vector<std::filesystem::path> DatasetBuilder::listScans(const std::filesystem::path& folder,
                                                             const std::string& what) {
    requireFolder(folder, what);
    std::vector<std::filesystem::path> scans;
    std::vector<std::string> hidden;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
        if (!isPointCloudFile(entry.path())) continue;
        // Hidden files are never frames: another writer's temporary file (".000003.bin.tmp
        // <pid>-<n>.bin", see AtomicFile) or macOS's "._000003.bin". Counting one would add a
        // frame, so they are skipped, and said so.
        const std::string name = entry.path().filename().string();
        if (name.front() == '.') {
            hidden.push_back(name);
            continue;
        }
        // A folder (or socket, fifo...) named like a scan is not skipped in silence: the
        // frame count would quietly change.
        std::error_code type_ec;
        if (!entry.is_regular_file(type_ec)) {
            throw IoError(what + " folder " + folder.string() + " holds '" +
                          entry.path().filename().string() +
                          "', which has a scan extension but is not a regular file (a folder?); "
                          "move it away or rename it");
        }
        scans.push_back(entry.path());
    }
    if (ec) throw IoError("cannot list " + folder.string() + ": " + ec.message());
    if (!hidden.empty()) {
        std::sort(hidden.begin(), hidden.end());
        logWarn(what + " folder " + folder.string() + ": skipped " +
                std::to_string(hidden.size()) + " hidden file(s) named like scans, e.g. '" +
                hidden.front() + "'");
    }
    if (scans.empty()) {
        throw IoError(what + " folder " + folder.string() + " holds no scans (.bin, .pcd, .ply)");
    }
    std::sort(scans.begin(), scans.end());
    return scans;
}

void DatasetBuilder::selectFrames(Dataset& dataset, std::vector<FrameInfo> all) {
    const DatasetConfig& config = dataset.config_;
    if (config.first_frame < 0 || static_cast<std::size_t>(config.first_frame) >= all.size()) {
        throw ConfigError("dataset: option 'first_frame' is " + std::to_string(config.first_frame) +
                          " but the sequence has " + std::to_string(all.size()) +
                          " frames (valid: 0.." + std::to_string(all.size() - 1) + ")");
    }
    if (config.stride < 1) {
        throw ConfigError("dataset: option 'stride' must be >= 1, got " +
                          std::to_string(config.stride));
    }
    if (config.num_frames < -1 || config.num_frames == 0) {
        throw ConfigError("dataset: option 'num_frames' must be -1 (all) or >= 1, got " +
                          std::to_string(config.num_frames));
    }
    dataset.frames_.clear();
    for (std::size_t i = static_cast<std::size_t>(config.first_frame); i < all.size();
         i += static_cast<std::size_t>(config.stride)) {
        if (config.num_frames > 0 &&
            dataset.frames_.size() >= static_cast<std::size_t>(config.num_frames)) {
            break;
        }
        FrameInfo frame = all[i];
        frame.index = dataset.frames_.size();
        dataset.frames_.push_back(std::move(frame));
    }
}

void DatasetBuilder::findImages(Dataset& dataset) {
    std::vector<Camera> cameras;
    std::vector<std::filesystem::path> image_dirs, semantic_dirs;
    std::vector<std::vector<std::filesystem::path>> image_paths(dataset.frames_.size());
    std::vector<std::vector<std::filesystem::path>> semantic_paths(dataset.frames_.size());
    for (std::size_t c = 0; c < dataset.cameras_.size(); ++c) {
        std::vector<std::filesystem::path> images(dataset.frames_.size());
        std::vector<std::filesystem::path> semantics(dataset.frames_.size());
        std::size_t found = 0;
        for (std::size_t i = 0; i < dataset.frames_.size(); ++i) {
            images[i] = findView(dataset.image_dirs_[c], dataset.frames_[i].id);
            semantics[i] = findView(dataset.semantic_dirs_[c], dataset.frames_[i].id);
            found += images[i].empty() ? 0 : 1;
        }
        Camera camera = dataset.cameras_[c];
        if (found == 0) {
            logWarn("dataset: camera '" + camera.name + "' has no images for the selected " +
                    "frames in " + dataset.image_dirs_[c].string() + "; it is not used");
            continue;
        }
        // The first image gives the size; an unreadable one is an error naming the file.
        const auto first =
            std::find_if(images.begin(), images.end(), [](const auto& p) { return !p.empty(); });
        const cv::Size size = readImageSize(*first);
        camera.intrinsics.width = size.width;
        camera.intrinsics.height = size.height;
        if (found < images.size()) {
            logInfo("dataset: camera '" + camera.name + "' lacks images for " +
                    std::to_string(images.size() - found) + " of " + std::to_string(images.size()) +
                    " frames");
        }
        for (std::size_t i = 0; i < dataset.frames_.size(); ++i) {
            image_paths[i].push_back(images[i]);
            semantic_paths[i].push_back(semantics[i]);
        }
        cameras.push_back(camera);
        image_dirs.push_back(dataset.image_dirs_[c]);
        semantic_dirs.push_back(dataset.semantic_dirs_[c]);
    }
    dataset.cameras_ = std::move(cameras);
    dataset.image_dirs_ = std::move(image_dirs);
    dataset.semantic_dirs_ = std::move(semantic_dirs);
    dataset.image_paths_ = std::move(image_paths);
    dataset.semantic_paths_ = std::move(semantic_paths);
}

}  // namespace vdbmap
