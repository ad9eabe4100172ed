// SPDX-License-Identifier: Apache-2.0
#include <algorithm>
#include <cstring>

#include "io/FileUtil.h"
#include "vdbmap/Error.h"
#include "vdbmap/io/AtomicFile.h"
#include "vdbmap/io/PointCloudIO.h"

namespace vdbmap {

PointCloud readBin(const std::filesystem::path& path) {
    const std::string bytes = detail::readWholeFile(path);
    constexpr std::size_t kPointBytes = 4 * sizeof(float);
    if (bytes.size() % kPointBytes != 0) {
        throw IoError("truncated KITTI scan " + path.string() + ": size " +
                      std::to_string(bytes.size()) + " bytes is not a multiple of 16 " +
                      "(float32 x y z reflectance per point)");
    }
    const std::size_t n = bytes.size() / kPointBytes;
    PointCloud cloud;
    cloud.points.resize(n);
    cloud.intensity.resize(n);
    // The format is little-endian float32, which is the host layout on every platform we build.
    for (std::size_t i = 0; i < n; ++i) {
        float v[4];
        std::memcpy(v, bytes.data() + i * kPointBytes, kPointBytes);
        cloud.points[i] = Vec3f(v[0], v[1], v[2]);
        cloud.intensity[i] = v[3];
    }
    return cloud;
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
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext == ".bin") return readBin(path);
    if (ext == ".pcd") return readPcd(path);
    if (ext == ".ply") return readPlyPoints(path);
    throw IoError("unknown point cloud format '" + ext + "' of " + path.string() +
                  " (expected .bin, .pcd or .ply)");
}

}  // namespace vdbmap
