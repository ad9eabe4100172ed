// SPDX-License-Identifier: Apache-2.0
// KITTI velodyne .bin scans (readBin, and readPointCloud's dispatch by extension).
#include "FuzzSupport.h"
#include "vdbmap/io/PointCloudIO.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace vdbmap;
    const auto path = fuzz::writeInput("scan.bin", fuzz::asText(data, size));
    fuzz::refusesOnlyWithTypedErrors([&] {
        const PointCloud cloud = readPointCloud(path);
        if (cloud.points.size() * 16 != size) std::abort();  // every point, no more
    });
    return 0;
}
