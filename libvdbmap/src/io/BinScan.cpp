// SPDX-License-Identifier: Apache-2.0
#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "io/FileUtil.h"
#include "vdbmap/Error.h"
#include "vdbmap/io/AtomicFile.h"
#include "vdbmap/io/PointCloudIO.h"

namespace vdbmap {

namespace {

constexpr std::size_t kPointBytes = 4 * sizeof(float);

IoError truncatedScan(const std::filesystem::path& path, std::uintmax_t size_bytes) {
    return IoError("truncated KITTI scan " + path.string() + ": size " + std::to_string(size_bytes) +
                   " bytes is not a multiple of 16 (float32 x y z reflectance per point)");
}

/// Points [first, first + count) of `cloud` from their bytes. The format is little-endian
/// float32, which is the host layout on every platform we build.
void convertPoints(const char* bytes, std::size_t first, std::size_t count, PointCloud& cloud) {
    for (std::size_t k = 0; k < count; ++k) {
        float v[4];
        std::memcpy(v, bytes + k * kPointBytes, kPointBytes);
        cloud.points[first + k] = Vec3f(v[0], v[1], v[2]);
        cloud.intensity[first + k] = v[3];
    }
}

void readBinInto(const std::filesystem::path& path, PointCloud& cloud) {
    detail::OpenFile file = detail::openForReading(path);
    if (file.size_bytes == 0) {  // no size known (a pipe), or empty
        const std::string bytes = detail::readAll(file, path);
        if (bytes.size() % kPointBytes != 0) throw truncatedScan(path, bytes.size());
        const std::size_t n = bytes.size() / kPointBytes;
        cloud.points.resize(n);
        cloud.intensity.resize(n);
        convertPoints(bytes.data(), 0, n, cloud);
        return;
    }
    if (file.size_bytes % kPointBytes != 0) throw truncatedScan(path, file.size_bytes);
    // Read in pieces that stay in the cache, straight into the cloud's (reused) storage.
    const std::size_t n = static_cast<std::size_t>(file.size_bytes / kPointBytes);
    cloud.points.resize(n);
    cloud.intensity.resize(n);
    constexpr std::size_t kChunkPoints = 4096;
    std::vector<char> chunk(kChunkPoints * kPointBytes);
    for (std::size_t first = 0; first < n; first += kChunkPoints) {
        const std::size_t count = std::min(kChunkPoints, n - first);
        const std::streamsize want = static_cast<std::streamsize>(count * kPointBytes);
        file.in.read(chunk.data(), want);
        if (file.in.bad()) throw IoError("read error in " + path.string());
        if (file.in.gcount() != want) {  // the file shrank while it was read
            throw IoError("truncated KITTI scan " + path.string() + ": ended after " +
                          std::to_string(first * kPointBytes + static_cast<std::size_t>(file.in.gcount())) +
                          " of " + std::to_string(file.size_bytes) + " bytes");
        }
        convertPoints(chunk.data(), first, count, cloud);
    }
}

}  // namespace

PointCloud readBin(const std::filesystem::path& path) {
    PointCloud cloud;
    readBin(path, cloud);
    return cloud;
}

void readBin(const std::filesystem::path& path, PointCloud& cloud) {
    try {
        readBinInto(path, cloud);
    } catch (...) {
        cloud.points.clear();
        cloud.intensity.clear();
        throw;
    }
}

void writeBin(const std::filesystem::path& path, const PointCloud& cloud) {
    const bool has_intensity = cloud.intensity.size() == cloud.points.size();
    std::string bytes(cloud.size() * 4 * sizeof(float), '\0');
    for (std::size_t i = 0; i < cloud.size(); ++i) {
        const float v[4] = {cloud.points[i].x(), cloud.points[i].y(), cloud.points[i].z(),
                            has_intensity ? cloud.intensity[i] : 0.0f};
        std::memcpy(bytes.data() + i * sizeof(v), v, sizeof(v));
    }
    writeFileAtomically(path, bytes);
}

bool isPointCloudFile(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext == ".bin" || ext == ".pcd" || ext == ".ply";
}

PointCloud readPointCloud(const std::filesystem::path& path) {
    PointCloud cloud;
    readPointCloud(path, cloud);
    return cloud;
}

void readPointCloud(const std::filesystem::path& path, PointCloud& cloud) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext == ".bin") {
        readBin(path, cloud);
    } else if (ext == ".pcd") {
        cloud = readPcd(path);
    } else if (ext == ".ply") {
        cloud = readPlyPoints(path);
    } else {
        throw IoError("unknown point cloud format '" + ext + "' of " + path.string() +
                      " (expected .bin, .pcd or .ply)");
    }
}

}  // namespace vdbmap
